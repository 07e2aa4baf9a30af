// The viewer's mesh out to files other tools open:
//   .obj   Wavefront OBJ, one object per part (Blender, MeshLab)
//   .gltf  glTF 2.0, JSON with the buffer embedded (base64); .glb binary.
//          One mesh, one primitive and one material (named after the part,
//          with the viewer's part colour) per part; float32 positions [m],
//          uint32 indices.
//   .vtk   legacy VTK polydata, ASCII (ParaView): double points [m],
//          triangles, the part index as cell scalars "part", the part names
//          as a dataset field array "part_names".
// Units are metres everywhere (glTF's own unit).
#pragma once
#include <array>
#include <string>

#include "hapsim/viewer/mesh_cache.h"

namespace hapsim::viewer {

// Writes by the path's extension (.obj, .gltf, .glb, .vtk). False with
// *error set (unknown extension, unwritable path, out-of-range indices).
bool WriteMeshFile(const std::string& path, const CompactMesh& mesh, const std::string& comment, std::string* error);

bool WriteGltf(const std::string& path, const CompactMesh& mesh, bool binary, std::string* error);
bool WriteVtk(const std::string& path, const CompactMesh& mesh, const std::string& comment, std::string* error);

// RGB in [0, 1] the viewer draws a part with (skin, fat, muscle, needle,
// wound, blade, vessel, ...; grey for an unknown name).
std::array<float, 3> PartColour(const std::string& part_name);
// A part that is the scene's own copy of the tool (needle, blade, probe):
// parked away from the tissue while no device streams, so a viewer hides it
// when the frame carries no tool.
bool IsToolPart(const std::string& part_name);

}  // namespace hapsim::viewer
