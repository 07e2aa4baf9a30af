// Any bytes as an OBJ file: io::ParseObj returns a mesh whose every triangle
// names existing vertices and whose positions are finite, or throws
// io::MeshError — nothing else (no other exception, no crash, no UB).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "hapsim/io/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hapsim::core::TriangleMesh mesh = hapsim::io::ParseObj(text);
    if (!mesh.vertices_m.allFinite()) std::abort();
    for (const auto& t : mesh.triangles)
      for (const std::int32_t v : t)
        if (v < 0 || v >= mesh.vertices_m.cols()) std::abort();
  } catch (const hapsim::io::MeshError&) {
    // refused with a message: fine
  }
  return 0;
}
