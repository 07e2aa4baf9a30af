// The web app's files as the console endpoint serves them: a request target
// mapped to a file under the root, never outside it.
#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace hapsim::web {

struct StaticFile {
  std::string path;          // the file on disk
  std::string content_type;  // from its extension
};

// "/" and "/index.html" -> ROOT/index.html; "/assets/app.js?v=3" ->
// ROOT/assets/app.js. nullopt for anything that could leave the root or is
// not a plain path: "..", backslashes, NUL, "//", a target longer than 512
// characters, or a path that does not name a regular file.
std::optional<StaticFile> ResolveStaticFile(const std::string& root, std::string_view target);

// The MIME type for a file name's extension ("application/octet-stream" if unknown).
std::string ContentTypeFor(std::string_view path);

}  // namespace hapsim::web
