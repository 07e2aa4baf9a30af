// Export round trips: a mesh written as OBJ, glTF (text and binary) and
// legacy VTK, read back — glTF with tinygltf, OBJ and VTK with the small
// parsers below — equals the mesh: the same triangles with the same parts,
// positions exact (VTK: 17 digits), to float32 rounding (glTF), or to half a
// unit of the 9th significant digit (OBJ).
#include "hapsim/viewer/mesh_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <unistd.h>

namespace hapsim::viewer {
namespace {

using Triangle = std::tuple<std::string, std::uint32_t, std::uint32_t, std::uint32_t>;  // part, a, b, c

// Two parts with triangles and one ("needle") without; coordinates with
// many significant digits.
CompactMesh SampleMesh() {
  CompactMesh m;
  m.vertices_m.resize(3, 5);
  m.vertices_m << 0.0123456789012345, -0.02, 0.031415926535897, 0.0, 1e-7,  //
      -0.0049999999, 0.011, 0.0, 0.027182818284590, -0.013,                //
      0.0, -0.003, 0.0071, -1.5e-3, 0.0;
  m.triangles = {0, 1, 2, 0, 2, 3, 1, 3, 4};
  m.triangle_parts = {0, 2, 0};
  m.part_names = {"skin", "needle", "muscle layer"};
  return m;
}

std::vector<Triangle> TrianglesOf(const CompactMesh& m) {
  std::vector<Triangle> out;
  for (std::size_t t = 0; t < m.triangles.size() / 3; ++t) {
    out.emplace_back(m.part_names[m.triangle_parts[t]], m.triangles[3 * t], m.triangles[3 * t + 1],
                     m.triangles[3 * t + 2]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("hapsim-export-" + std::to_string(::getpid()) + "-" + name))
      .string();
}

TEST(MeshExport, ObjRoundTripKeepsTrianglesPartsAndNineDigits) {
  const CompactMesh mesh = SampleMesh();
  const std::string path = TempPath("m.obj");
  std::string error;
  ASSERT_TRUE(WriteMeshFile(path, mesh, "test", &error)) << error;
  std::ifstream in(path);
  std::string line, part;
  std::vector<Eigen::Vector3d> v;
  std::vector<Triangle> tris;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind;
    s >> kind;
    if (kind == "v") {
      Eigen::Vector3d p;
      s >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (kind == "o") {
      std::getline(s >> std::ws, part);
    } else if (kind == "f") {
      std::uint32_t a, b, c;
      s >> a >> b >> c;
      tris.emplace_back(part, a - 1, b - 1, c - 1);
    }
  }
  std::sort(tris.begin(), tris.end());
  EXPECT_EQ(tris, TrianglesOf(mesh));
  ASSERT_EQ(v.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    // %.9g rounds to 9 significant digits: |error| <= half a unit of the
    // 9th digit, 0.5 * 10^(floor(log10 |x|) - 8) (plus the double's own ulp).
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.vertices_m(k, i);
      const double bound = x == 0.0 ? 0.0 : 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(x))) - 8) * (1 + 1e-6);
      EXPECT_NEAR(v[static_cast<std::size_t>(i)][k], x, bound);
    }
  }
  std::filesystem::remove(path);
}

void CheckGltf(const std::string& path, bool binary) {
  const CompactMesh mesh = SampleMesh();
  std::string error, warning;
  ASSERT_TRUE(WriteMeshFile(path, mesh, "test", &error)) << error;
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                         : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  ASSERT_TRUE(ok) << error;
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.materials.size(), 3u);  // one per part, the empty one too
  const auto& pos = model.accessors[static_cast<std::size_t>(model.meshes[0].primitives[0].attributes.at("POSITION"))];
  ASSERT_EQ(pos.count, 5u);
  ASSERT_EQ(pos.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const auto& view = model.bufferViews[static_cast<std::size_t>(pos.bufferView)];
  const auto* xyz = reinterpret_cast<const float*>(model.buffers[0].data.data() + view.byteOffset + pos.byteOffset);
  for (int i = 0; i < 5; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(xyz[3 * i + k], static_cast<float>(mesh.vertices_m(k, i)));  // float32 rounding only
  }
  std::vector<Triangle> tris;
  for (const auto& primitive : model.meshes[0].primitives) {
    EXPECT_EQ(primitive.mode, TINYGLTF_MODE_TRIANGLES);
    const auto& acc = model.accessors[static_cast<std::size_t>(primitive.indices)];
    ASSERT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    const auto& iv = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    const auto* idx =
        reinterpret_cast<const std::uint32_t*>(model.buffers[0].data.data() + iv.byteOffset + acc.byteOffset);
    const std::string part = model.materials[static_cast<std::size_t>(primitive.material)].name;
    for (std::size_t t = 0; t < acc.count / 3; ++t) tris.emplace_back(part, idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]);
  }
  std::sort(tris.begin(), tris.end());
  EXPECT_EQ(tris, TrianglesOf(mesh));
  // The part colour travels as the material's base colour.
  const auto skin = PartColour("skin");
  EXPECT_FLOAT_EQ(static_cast<float>(model.materials[0].pbrMetallicRoughness.baseColorFactor[0]), skin[0]);
  std::filesystem::remove(path);
}

TEST(MeshExport, GltfRoundTripThroughTinygltf) { CheckGltf(TempPath("m.gltf"), false); }
TEST(MeshExport, GlbRoundTripThroughTinygltf) { CheckGltf(TempPath("m.glb"), true); }

TEST(MeshExport, VtkRoundTripIsExact) {
  const CompactMesh mesh = SampleMesh();
  const std::string path = TempPath("m.vtk");
  std::string error;
  ASSERT_TRUE(WriteMeshFile(path, mesh, "hapsim test\nsecond line", &error)) << error;
  // A legacy-VTK polydata reader for what the writer may emit.
  std::ifstream in(path);
  std::string header, title, format, token;
  std::getline(in, header);
  std::getline(in, title);
  std::getline(in, format);
  EXPECT_EQ(header, "# vtk DataFile Version 3.0");
  EXPECT_EQ(title, "hapsim test second line");  // one line, as the format wants
  EXPECT_EQ(format, "ASCII");
  std::vector<std::string> names;
  Eigen::Matrix3Xd points;
  std::vector<std::uint32_t> triangles;
  std::vector<int> parts;
  while (in >> token) {
    if (token == "FIELD") {
      std::string field_name, array_name, type;
      int arrays = 0, components = 0;
      std::size_t tuples = 0;
      in >> field_name >> arrays >> array_name >> components >> tuples >> type;
      ASSERT_EQ(array_name, "part_names");
      ASSERT_EQ(type, "string");
      names.resize(tuples);
      for (auto& n : names) {
        std::string word;
        in >> word;
        for (std::size_t i = 0; i < word.size(); ++i) {  // "%20" -> ' '
          const bool space = word.compare(i, 3, "%20") == 0;
          n += space ? ' ' : word[i];
          if (space) i += 2;
        }
      }
    } else if (token == "POINTS") {
      long n = 0;
      std::string type;
      in >> n >> type;
      EXPECT_EQ(type, "double");
      points.resize(3, n);
      for (long i = 0; i < n; ++i) in >> points(0, i) >> points(1, i) >> points(2, i);
    } else if (token == "POLYGONS") {
      std::size_t m = 0, size = 0;
      in >> m >> size;
      EXPECT_EQ(size, 4 * m);
      for (std::size_t t = 0; t < m; ++t) {
        int corners = 0;
        std::uint32_t a, b, c;
        in >> corners >> a >> b >> c;
        EXPECT_EQ(corners, 3);
        triangles.insert(triangles.end(), {a, b, c});
      }
    } else if (token == "LOOKUP_TABLE") {
      in >> token;  // "default"
      parts.resize(triangles.size() / 3);
      for (auto& p : parts) in >> p;
    }
  }
  EXPECT_EQ(names, mesh.part_names);
  EXPECT_TRUE(points == mesh.vertices_m) << "17 digits give every double back exactly";
  EXPECT_EQ(triangles, mesh.triangles);
  ASSERT_EQ(parts.size(), mesh.triangle_parts.size());
  for (std::size_t t = 0; t < parts.size(); ++t) EXPECT_EQ(parts[t], mesh.triangle_parts[t]);
  std::filesystem::remove(path);
}

TEST(MeshExport, BadMeshesAndUnknownFormatsAreRefusedWithoutAFile) {
  std::string error;
  const std::string path = TempPath("bad.vtk");
  CompactMesh bad = SampleMesh();
  bad.triangles[4] = 99;
  EXPECT_FALSE(WriteMeshFile(path, bad, "", &error));
  EXPECT_NE(error.find("vertex 99"), std::string::npos) << error;
  EXPECT_FALSE(std::filesystem::exists(path));
  bad = SampleMesh();
  bad.triangle_parts[1] = 7;
  EXPECT_FALSE(WriteMeshFile(TempPath("bad.gltf"), bad, "", &error));
  EXPECT_NE(error.find("part 7"), std::string::npos) << error;
  EXPECT_FALSE(WriteMeshFile(TempPath("m.stl"), SampleMesh(), "", &error));
  EXPECT_NE(error.find("unknown mesh format"), std::string::npos) << error;
  EXPECT_FALSE(WriteMeshFile("/nonexistent/dir/m.vtk", SampleMesh(), "", &error));
  EXPECT_NE(error.find("cannot write"), std::string::npos) << error;
}

}  // namespace
}  // namespace hapsim::viewer
