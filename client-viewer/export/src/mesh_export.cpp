#include "hapsim/viewer/mesh_export.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>

#include <tiny_gltf.h>

namespace hapsim::viewer {

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Triangle indices name existing vertices and parts existing names: a file
// that would not load again is refused before anything is written.
bool Check(const CompactMesh& mesh, std::string* error) {
  const auto n = static_cast<std::uint32_t>(mesh.vertices_m.cols());
  if (mesh.triangles.size() % 3 != 0) {
    *error = "triangle list is not a multiple of 3";
    return false;
  }
  for (const std::uint32_t v : mesh.triangles) {
    if (v >= n) {
      *error = "a triangle names vertex " + std::to_string(v) + " of " + std::to_string(n);
      return false;
    }
  }
  if (!mesh.part_names.empty()) {
    if (mesh.triangle_parts.size() * 3 != mesh.triangles.size()) {
      *error = "one part per triangle is needed";
      return false;
    }
    for (const auto p : mesh.triangle_parts) {
      if (p >= mesh.part_names.size()) {
        *error = "a triangle names part " + std::to_string(p) + " of " + std::to_string(mesh.part_names.size());
        return false;
      }
    }
  }
  return true;
}

std::size_t PartCount(const CompactMesh& mesh) { return std::max<std::size_t>(mesh.part_names.size(), 1); }
std::uint16_t PartOf(const CompactMesh& mesh, std::size_t t) {
  return mesh.part_names.empty() ? std::uint16_t{0} : mesh.triangle_parts[t];
}
std::string PartName(const CompactMesh& mesh, std::size_t p) {
  return mesh.part_names.empty() ? std::string("mesh") : mesh.part_names[p];
}

template <class T>
void Append(std::vector<unsigned char>* bytes, const T& value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  bytes->insert(bytes->end(), p, p + sizeof(T));
}

}  // namespace

bool IsToolPart(const std::string& part_name) {
  return part_name == "needle" || part_name == "blade" || part_name == "probe";
}

std::array<float, 3> PartColour(const std::string& name) {
  static const std::map<std::string, std::array<float, 3>> kColours = {
      {"skin", {0.91f, 0.72f, 0.62f}},   {"fat", {0.98f, 0.88f, 0.52f}},    {"muscle", {0.72f, 0.22f, 0.22f}},
      {"needle", {0.78f, 0.78f, 0.82f}}, {"blade", {0.78f, 0.78f, 0.82f}},  {"probe", {0.78f, 0.78f, 0.82f}},
      {"wound", {0.55f, 0.08f, 0.08f}},  {"vessel", {0.45f, 0.20f, 0.45f}}, {"wall", {0.45f, 0.20f, 0.45f}},
      {"bed", {0.85f, 0.65f, 0.55f}},    {"tissue", {0.91f, 0.66f, 0.60f}}, {"vessel_wall", {0.55f, 0.30f, 0.55f}},
      {"lumen", {0.60f, 0.10f, 0.12f}}};
  const auto found = kColours.find(name);
  return found == kColours.end() ? std::array<float, 3>{0.7f, 0.7f, 0.7f} : found->second;
}

namespace {

// Float32 positions appended to `bytes`; their box into lo/hi (glTF wants it).
void AppendGltfPositions(const CompactMesh& mesh, std::vector<unsigned char>* bytes, std::vector<double>* lo,
                         std::vector<double>* hi) {
  lo->assign(3, std::numeric_limits<double>::infinity());
  hi->assign(3, -std::numeric_limits<double>::infinity());
  for (Eigen::Index i = 0; i < mesh.vertices_m.cols(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const float x = static_cast<float>(mesh.vertices_m(static_cast<Eigen::Index>(k), i));
      Append(bytes, x);
      (*lo)[k] = std::min((*lo)[k], static_cast<double>(x));
      (*hi)[k] = std::max((*hi)[k], static_cast<double>(x));
    }
  }
}

std::vector<std::vector<std::uint32_t>> TrianglesByPart(const CompactMesh& mesh) {
  std::vector<std::vector<std::uint32_t>> by_part(PartCount(mesh));
  for (std::size_t t = 0; t < mesh.triangles.size() / 3; ++t) {
    auto& out = by_part[PartOf(mesh, t)];
    out.insert(out.end(), mesh.triangles.begin() + static_cast<std::ptrdiff_t>(3 * t),
               mesh.triangles.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
  }
  return by_part;
}

// Views 0 (positions) and 1 (every part's indices) of the one buffer, and accessor 0 (POSITION).
void AddGltfViews(std::size_t positions_bytes, std::size_t vertices, const std::vector<double>& lo,
                  const std::vector<double>& hi, tinygltf::Model* model) {
  tinygltf::BufferView positions_view;
  positions_view.buffer = 0;
  positions_view.byteOffset = 0;
  positions_view.byteLength = positions_bytes;
  positions_view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  model->bufferViews.push_back(positions_view);
  tinygltf::BufferView indices_view;
  indices_view.buffer = 0;
  indices_view.byteOffset = positions_bytes;
  indices_view.byteLength = model->buffers[0].data.size() - positions_bytes;
  indices_view.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  model->bufferViews.push_back(indices_view);
  tinygltf::Accessor positions;
  positions.bufferView = 0;
  positions.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  positions.type = TINYGLTF_TYPE_VEC3;
  positions.count = vertices;
  if (vertices > 0) {  // min/max are required for POSITION
    positions.minValues = lo;
    positions.maxValues = hi;
  }
  model->accessors.push_back(positions);
}

// The material named after part p, in the viewer's colour for it.
tinygltf::Material PartMaterial(const CompactMesh& mesh, std::size_t p) {
  tinygltf::Material material;
  material.name = PartName(mesh, p);
  const auto rgb = PartColour(material.name);
  material.pbrMetallicRoughness.baseColorFactor = {static_cast<double>(rgb[0]), static_cast<double>(rgb[1]),
                                                   static_cast<double>(rgb[2]), 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.8;
  material.doubleSided = true;  // cut surfaces are seen from both sides
  return material;
}

// One material per part; one primitive per part with triangles, its indices
// an accessor into view 1.
tinygltf::Mesh AddGltfParts(const CompactMesh& mesh, const std::vector<std::vector<std::uint32_t>>& by_part,
                            tinygltf::Model* model) {
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = "hapsim";
  std::size_t offset = 0;
  for (std::size_t p = 0; p < by_part.size(); ++p) {
    model->materials.push_back(PartMaterial(mesh, p));
    if (by_part[p].empty()) continue;  // a part without triangles now (e.g. a tool out of view)
    tinygltf::Accessor indices;
    indices.bufferView = 1;
    indices.byteOffset = offset;
    indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    indices.type = TINYGLTF_TYPE_SCALAR;
    indices.count = by_part[p].size();
    offset += by_part[p].size() * sizeof(std::uint32_t);
    model->accessors.push_back(indices);
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = 0;
    primitive.indices = static_cast<int>(model->accessors.size() - 1);
    primitive.material = static_cast<int>(p);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    gltf_mesh.primitives.push_back(primitive);
  }
  return gltf_mesh;
}

}  // namespace

bool WriteGltf(const std::string& path, const CompactMesh& mesh, bool binary, std::string* error) {
  if (!Check(mesh, error)) return false;
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "hapsim";
  // One buffer: float32 positions, then each part's uint32 indices.
  tinygltf::Buffer buffer;
  std::vector<double> lo, hi;
  AppendGltfPositions(mesh, &buffer.data, &lo, &hi);
  const std::size_t positions_bytes = buffer.data.size();
  const auto by_part = TrianglesByPart(mesh);
  for (const auto& indices : by_part) {
    for (const std::uint32_t v : indices) Append(&buffer.data, v);
  }
  model.buffers.push_back(std::move(buffer));
  AddGltfViews(positions_bytes, static_cast<std::size_t>(mesh.vertices_m.cols()), lo, hi, &model);
  model.meshes.push_back(AddGltfParts(mesh, by_part, &model));
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "hapsim";
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, path, /*embedImages=*/true, /*embedBuffers=*/true,
                                   /*prettyPrint=*/!binary, binary)) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

bool WriteVtk(const std::string& path, const CompactMesh& mesh, const std::string& comment, std::string* error) {
  if (!Check(mesh, error)) return false;
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    *error = "cannot write " + path;
    return false;
  }
  std::string title = comment.substr(0, 250);
  std::replace(title.begin(), title.end(), '\n', ' ');
  const auto n = static_cast<long>(mesh.vertices_m.cols());
  const std::size_t m = mesh.triangles.size() / 3;
  std::fprintf(f, "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET POLYDATA\n", title.c_str());
  // Dataset field data: the part names (spaces written as %20, as VTK reads them).
  std::fprintf(f, "FIELD FieldData 1\npart_names 1 %zu string\n", PartCount(mesh));
  for (std::size_t p = 0; p < PartCount(mesh); ++p) {
    std::string name = PartName(mesh, p);
    std::string escaped;
    for (const char c : name) escaped += c == ' ' ? std::string("%20") : std::string(1, c);
    std::fprintf(f, "%s\n", escaped.c_str());
  }
  std::fprintf(f, "POINTS %ld double\n", n);
  for (Eigen::Index i = 0; i < n; ++i) {
    std::fprintf(f, "%.17g %.17g %.17g\n", mesh.vertices_m(0, i), mesh.vertices_m(1, i), mesh.vertices_m(2, i));
  }
  std::fprintf(f, "POLYGONS %zu %zu\n", m, 4 * m);
  for (std::size_t t = 0; t < m; ++t) {
    std::fprintf(f, "3 %u %u %u\n", mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]);
  }
  std::fprintf(f, "CELL_DATA %zu\nSCALARS part int 1\nLOOKUP_TABLE default\n", m);
  for (std::size_t t = 0; t < m; ++t) std::fprintf(f, "%u\n", static_cast<unsigned>(PartOf(mesh, t)));
  if (std::fclose(f) != 0) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

bool WriteMeshFile(const std::string& path, const CompactMesh& mesh, const std::string& comment, std::string* error) {
  if (EndsWith(path, ".obj")) {
    if (!Check(mesh, error)) return false;
    if (!WriteObj(path, mesh, comment)) {
      *error = "cannot write " + path;
      return false;
    }
    return true;
  }
  if (EndsWith(path, ".gltf")) return WriteGltf(path, mesh, false, error);
  if (EndsWith(path, ".glb")) return WriteGltf(path, mesh, true, error);
  if (EndsWith(path, ".vtk")) return WriteVtk(path, mesh, comment, error);
  *error = "unknown mesh format of '" + path + "' (use .obj, .gltf, .glb or .vtk)";
  return false;
}

}  // namespace hapsim::viewer
