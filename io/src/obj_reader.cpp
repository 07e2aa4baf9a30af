#include "hapsim/io/obj_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

namespace hapsim::io {

namespace {

std::string_view NextToken(std::string_view& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) {
    s = {};
    return {};
  }
  s.remove_prefix(b);
  const auto e = s.find_first_of(" \t\r");
  const std::string_view tok = s.substr(0, e);
  s.remove_prefix(e == std::string_view::npos ? s.size() : e);
  return tok;
}

[[noreturn]] void Fail(std::size_t line, const std::string& what) {
  throw MeshError("OBJ line " + std::to_string(line) + ": " + what);
}

}  // namespace

core::TriangleMesh ParseObj(std::string_view text) {
  std::vector<double> xyz;
  core::TriangleMesh mesh;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    ++line_no;
    const std::string_view kind = NextToken(line);
    if (kind == "v") {
      for (int c = 0; c < 3; ++c) {
        const std::string_view tok = NextToken(line);
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size() || !std::isfinite(v))
          Fail(line_no, "vertex needs 3 finite numbers");
        xyz.push_back(v);
      }
    } else if (kind == "f") {
      std::vector<std::int32_t> idx;
      for (std::string_view tok = NextToken(line); !tok.empty(); tok = NextToken(line)) {
        const std::string_view first = tok.substr(0, tok.find('/'));
        long v = 0;
        const auto [ptr, ec] = std::from_chars(first.data(), first.data() + first.size(), v);
        if (first.empty() || ec != std::errc() || ptr != first.data() + first.size() || v == 0)
          Fail(line_no, "bad face index '" + std::string(tok) + "'");
        const long nv = static_cast<long>(xyz.size() / 3);
        const long i = v > 0 ? v - 1 : nv + v;
        if (i < 0 || i >= nv) Fail(line_no, "face index " + std::to_string(v) + " out of range");
        idx.push_back(static_cast<std::int32_t>(i));
      }
      if (idx.size() < 3) Fail(line_no, "face needs at least 3 vertices");
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) mesh.triangles.push_back({idx[0], idx[k], idx[k + 1]});
    }
    // other records (vn, vt, o, g, s, #, ...) carry nothing we need
  }
  mesh.vertices_m = Eigen::Map<const Eigen::Matrix3Xd>(xyz.data(), 3, static_cast<Eigen::Index>(xyz.size() / 3));
  return mesh;
}

core::TriangleMesh ReadObjFile(const std::string& path, std::size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot open mesh file '" + path + "'");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw MeshError("cannot read mesh file '" + path + "'");
  if (static_cast<std::size_t>(size) > max_bytes) {
    throw MeshError("mesh file '" + path + "' is " + std::to_string(size) + " bytes; the limit is " +
                    std::to_string(max_bytes));
  }
  in.seekg(0, std::ios::beg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    return ParseObj(text);
  } catch (const MeshError& e) {
    throw MeshError(path + ": " + e.what());
  }
}

}  // namespace hapsim::io
