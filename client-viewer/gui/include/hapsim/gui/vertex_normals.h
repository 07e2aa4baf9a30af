// Per-vertex normals of a triangle mesh, for lighting in the vertex shader
// (software rendering shades every pixel of a tiny triangle's 4x4 block, so
// the fragment shader must stay trivial; see docs/viewer.md, frame rates).
#pragma once
#include <cstdint>
#include <vector>

namespace hapsim::gui {

// Writes into *normals (3 floats per vertex, resized to match positions_m)
// the unit normal of each vertex: the sum of its triangles' normals weighted
// by area (the cross product of two edges, counter-clockwise = +side).
// Vertices no triangle names get (0, 0, 0); so do vertices whose faces cancel.
// Indices out of range are skipped (the caller's triangles come from a cache
// that has checked them; this keeps a bad list from reading past the end).
void ComputeVertexNormals(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                          std::vector<float>* normals);

}  // namespace hapsim::gui
