#include "backends/replay_device.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hapsim::bridge {

std::vector<PoseLogRow> ParsePoseLog(const std::string& text) {
  std::vector<PoseLogRow> rows;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1 || line.empty()) continue;  // header
    double v[8];
    const char* p = line.c_str();
    for (int k = 0; k < 8; ++k) {
      char* end = nullptr;
      v[k] = std::strtod(p, &end);
      if (end == p || !std::isfinite(v[k]) || (*end != ',' && *end != '\0' && *end != '\r')) {
        throw std::invalid_argument("pose log line " + std::to_string(line_no) + ": field " + std::to_string(k + 1) +
                                    " is not a finite number (expected t_s,x_m,y_m,z_m,qw,qx,qy,qz)");
      }
      p = *end == ',' ? end + 1 : end;
      if (k < 7 && *end != ',') {
        throw std::invalid_argument("pose log line " + std::to_string(line_no) + ": expected 8 fields");
      }
    }
    PoseLogRow row;
    row.t_s = v[0];
    row.tip_W_m = {v[1], v[2], v[3]};
    Eigen::Quaterniond q(v[4], v[5], v[6], v[7]);
    if (std::abs(q.norm() - 1.0) > 0.05) {
      throw std::invalid_argument("pose log line " + std::to_string(line_no) + ": orientation is not a unit quaternion");
    }
    row.orientation_W = q.normalized();
    if (!rows.empty() && !(row.t_s > rows.back().t_s)) {
      throw std::invalid_argument("pose log line " + std::to_string(line_no) + ": t_s must increase");
    }
    rows.push_back(row);
  }
  if (rows.empty()) throw std::invalid_argument("pose log has no rows");
  return rows;
}

std::vector<PoseLogRow> LoadPoseLog(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::invalid_argument("cannot open pose log '" + path + "'");
  std::stringstream text;
  text << f.rdbuf();
  return ParsePoseLog(text.str());
}

ReplayDevice::ReplayDevice(std::vector<PoseLogRow> rows) : rows_(std::move(rows)) {
  if (rows_.empty()) throw std::invalid_argument("replay needs at least one pose");
}

DeviceReading ReplayDevice::Read(double t_s) {
  DeviceReading r;
  r.phase = "replay";
  const double t = rows_.front().t_s + t_s;  // the log's own time origin
  while (cursor_ + 1 < rows_.size() && rows_[cursor_ + 1].t_s <= t) ++cursor_;
  const PoseLogRow& a = rows_[cursor_];
  if (cursor_ + 1 >= rows_.size()) {  // past the end: hold the last pose
    r.tip_W_m = a.tip_W_m;
    r.orientation_W = a.orientation_W;
    r.finished = true;
    return r;
  }
  const PoseLogRow& b = rows_[cursor_ + 1];
  const double span = b.t_s - a.t_s;
  const double u = std::clamp((t - a.t_s) / span, 0.0, 1.0);
  r.tip_W_m = (1.0 - u) * a.tip_W_m + u * b.tip_W_m;
  r.velocity_W_m_per_s = (b.tip_W_m - a.tip_W_m) / span;
  Eigen::Vector4d qa = a.orientation_W.coeffs(), qb = b.orientation_W.coeffs();
  if (qa.dot(qb) < 0) qb = -qb;  // shortest arc
  const Eigen::Vector4d q = ((1.0 - u) * qa + u * qb).normalized();
  r.orientation_W = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
  return r;
}

}  // namespace hapsim::bridge
