// Wavefront OBJ meshes in: vertices ("v x y z") and faces ("f a b c ...",
// fan-triangulated; "a/b/c" and negative indices accepted); every other
// record (vn, vt, o, g, s, usemtl, #...) is skipped. The result is plain
// arrays for the core (core::TriangleMesh).
//
// Strict on purpose: a vertex without three finite numbers or a face index
// out of range is an error naming the line. Debian's tinyobjloader 2.0rc10
// was considered and not used for this: it reads "v 1 2" and "v 1 2 x" as
// vertices without complaint and reports out-of-range face indices only as a
// warning — a malformed mesh must be refused, not simulated.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>

#include "hapsim/core/mesh/triangle_mesh.h"

namespace hapsim::io {

// Bad mesh content or an unreadable file; the message names the line or path.
class MeshError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// OBJ text -> mesh. Throws MeshError ("OBJ line N: ...").
core::TriangleMesh ParseObj(std::string_view text);

// Reads and parses an OBJ file. Throws MeshError naming the path when the
// file cannot be read, is larger than max_bytes, or is malformed.
core::TriangleMesh ReadObjFile(const std::string& path, std::size_t max_bytes = 256u << 20);

}  // namespace hapsim::io
