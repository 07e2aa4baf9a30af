#include "hapsim/web/static_files.h"

#include <sys/stat.h>

#include <array>
#include <utility>

namespace hapsim::web {

std::string ContentTypeFor(std::string_view path) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 10> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".ico", "image/x-icon"},
      {".wasm", "application/wasm"},
      {".map", "application/json"},
  }};
  const auto dot = path.rfind('.');
  if (dot != std::string_view::npos && path.find('/', dot) == std::string_view::npos) {
    const auto ext = path.substr(dot);
    for (const auto& [e, type] : kTypes) {
      if (e == ext) return std::string(type);
    }
  }
  return "application/octet-stream";
}

std::optional<StaticFile> ResolveStaticFile(const std::string& root, std::string_view target) {
  if (root.empty() || target.empty() || target.size() > 512 || target.front() != '/') return std::nullopt;
  if (const auto query = target.find_first_of("?#"); query != std::string_view::npos) {
    target = target.substr(0, query);
  }
  if (target == "/") target = "/index.html";
  for (const char c : target) {
    // Plain file names only: no escapes, backslashes or control characters.
    if (c == '\\' || c == '%' || static_cast<unsigned char>(c) < 0x20) return std::nullopt;
  }
  if (target.find("//") != std::string_view::npos || target.find("/.") != std::string_view::npos) {
    return std::nullopt;  // "..", hidden files, empty segments
  }
  std::string path = root;
  if (path.back() == '/') path.pop_back();
  path.append(target);
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return std::nullopt;
  return StaticFile{path, ContentTypeFor(target)};
}

}  // namespace hapsim::web
