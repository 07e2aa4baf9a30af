#include "hapsim/dds/partition.h"

#include "hapsim/common/session_id.h"

namespace hapsim::dds {

std::string SessionPartition(std::string_view session_id) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "hapsim_s_";
  for (const char ch : session_id) {
    const auto c = static_cast<unsigned char>(ch);
    if (common::IsAlnumOrDash(c)) {
      out += static_cast<char>(c);
    } else {
      out += '_';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

}  // namespace hapsim::dds
