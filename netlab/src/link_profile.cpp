#include "hapsim/netlab/link_profile.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace hapsim::netlab {
namespace {

bool ParseNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*value);
}

// One "key=value" into *p; "" on success, else what is wrong.
std::string ApplyKey(const std::string& key, const std::string& value_text, LinkProfile* p) {
  if (key == "outage") {
    const auto plus = value_text.find('+');
    Outage o;
    if (plus == std::string::npos || !ParseNumber(value_text.substr(0, plus), &o.start_s) ||
        !ParseNumber(value_text.substr(plus + 1), &o.duration_s) || o.start_s < 0.0 || o.duration_s <= 0.0) {
      return "outage must be START_S+DURATION_S with START_S >= 0 and DURATION_S > 0, got '" + value_text + "'";
    }
    p->outages.push_back(o);
    return "";
  }
  double v = 0.0;
  if (!ParseNumber(value_text, &v)) return key + " needs a number, got '" + value_text + "'";
  struct Field {
    const char* name;
    double* target;
    double lo, hi;
    const char* range;
  };
  double reorder = p->reorder ? 1.0 : 0.0;
  const Field fields[] = {
      {"delay_ms", &p->delay_ms, 0.0, 10000.0, "[0, 10000]"},
      {"jitter_ms", &p->jitter_ms, 0.0, 10000.0, "[0, 10000]"},
      {"loss", &p->loss, 0.0, 1.0, "[0, 1]"},
      {"burst_rate", &p->burst_rate, 0.0, 1.0, "[0, 1]"},
      {"burst_packets", &p->burst_packets, 0.0, 1e9, "0 or [1, 1e9]"},
      {"rate_mbit_s", &p->rate_mbit_s, 0.0, 1e5, "[0, 1e5]"},
      {"queue_ms", &p->queue_ms, 0.0, 10000.0, "[0, 10000]"},
      {"reorder", &reorder, 0.0, 1.0, "0 or 1"},
  };
  for (const Field& f : fields) {
    if (key != f.name) continue;
    if (v < f.lo || v > f.hi) return key + " must be within " + f.range + ", got " + value_text;
    *f.target = v;
    p->reorder = reorder != 0.0;
    return "";
  }
  return "unknown link key '" + key +
         "' (known: delay_ms, jitter_ms, reorder, loss, burst_rate, burst_packets, rate_mbit_s, queue_ms, outage)";
}

}  // namespace

bool ParseLinkProfile(const std::string& text, LinkProfile* profile, std::string* error) {
  LinkProfile p;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      *error = "link setting '" + item + "' is not KEY=VALUE";
      return false;
    }
    *error = ApplyKey(item.substr(0, eq), item.substr(eq + 1), &p);
    if (!error->empty()) return false;
  }
  if (p.burst_rate > 0.0 && p.burst_packets < 1.0) {
    *error = "burst_rate needs burst_packets >= 1 (the mean burst length)";
    return false;
  }
  *profile = p;
  return true;
}

std::string ToString(const LinkProfile& p) {
  std::ostringstream s;
  s << "delay_ms=" << p.delay_ms << ",jitter_ms=" << p.jitter_ms << ",reorder=" << (p.reorder ? 1 : 0)
    << ",loss=" << p.loss << ",burst_rate=" << p.burst_rate << ",burst_packets=" << p.burst_packets
    << ",rate_mbit_s=" << p.rate_mbit_s << ",queue_ms=" << p.queue_ms;
  for (const Outage& o : p.outages) s << ",outage=" << o.start_s << "+" << o.duration_s;
  return s.str();
}

}  // namespace hapsim::netlab
