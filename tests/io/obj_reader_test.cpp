// hapsim::io's OBJ reader: what it reads equals the mesh written, fan
// triangulation and index forms as the format defines them, and every
// malformed input refused with the line (or file) named.
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "hapsim/io/obj_reader.h"

namespace hapsim::io {
namespace {

std::string ErrorOf(std::string_view text) {
  try {
    ParseObj(text);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

TEST(ObjReader, ReadsVerticesAndFanTriangulatesPolygons) {
  // A unit square as one quad, a pentagon with every index form: v, v/vt,
  // v//vn, v/vt/vn and negative (relative) indices.
  const std::string text =
      "# comment\no square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\ns off\nf 1 2 3 4\n"
      "v 2 0 0\nv 3 0 0\nv 3.5 1 0\nv 2.5 2 0\nv 1.5 1 0\n"
      "f -5 6/1 7//1 8/1/1 -1\n";
  const core::TriangleMesh mesh = ParseObj(text);
  ASSERT_EQ(mesh.vertices_m.cols(), 9);
  EXPECT_EQ(mesh.vertices_m.col(6), Eigen::Vector3d(3.5, 1, 0));
  const std::vector<std::array<std::int32_t, 3>> expected = {
      {0, 1, 2}, {0, 2, 3},                // quad: fan from its first vertex
      {4, 5, 6}, {4, 6, 7}, {4, 7, 8}};  // pentagon: -5 is vertex 5 (index 4), -1 is vertex 9
  EXPECT_EQ(mesh.triangles, expected);
}

TEST(ObjReader, WrittenMeshReadsBackWithinTheTextPrecision) {
  // The star of tests/core/sh_fit_test.cpp, written at 17 significant digits.
  const int nt = 6, np = 10;
  std::string text;
  Eigen::Matrix3Xd v(3, (nt + 1) * np);
  char line[128];
  for (int i = 0; i <= nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double th = std::numbers::pi * i / nt, ph = 2 * std::numbers::pi * j / np;
      v.col(i * np + j) = Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)) *
                          (0.05 + 0.01 * std::sin(th) * std::cos(ph));
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v(0, i * np + j), v(1, i * np + j), v(2, i * np + j));
      text += line;
    }
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const int a = i * np + j + 1, b = i * np + (j + 1) % np + 1;
      text += "f " + std::to_string(a) + " " + std::to_string(a + np) + " " + std::to_string(b + np) + " " +
              std::to_string(b) + "\n";
    }
  const core::TriangleMesh mesh = ParseObj(text);
  EXPECT_EQ(mesh.vertices_m, v);  // %.17g round-trips a double exactly
  EXPECT_EQ(mesh.triangles.size(), static_cast<std::size_t>(2 * nt * np));
}

TEST(ObjReader, MalformedInputIsRefusedNamingTheLine) {
  EXPECT_NE(ErrorOf("v 1 2\n").find("OBJ line 1: vertex needs 3 finite numbers"), std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 x\n").find("line 1"), std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 nan\n").find("line 1"), std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 3\nv 0 0 0\nv 1 1 1\nf 1 2 5\n").find("OBJ line 4: face index 5 out of range"),
            std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 3\nf 1 0 1\n").find("line 2: bad face index '0'"), std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 3\nv 0 0 0\nf 1 2\n").find("line 3: face needs at least 3 vertices"), std::string::npos);
  EXPECT_NE(ErrorOf("v 1 2 3\nf -2 1 1\n").find("line 2: face index -2 out of range"), std::string::npos);
  EXPECT_EQ(ParseObj("").vertices_m.cols(), 0);  // empty is a valid (empty) mesh; the caller decides
}

TEST(ObjReader, FileIsReadAndFileErrorsNameThePath) {
  const std::string path = ::testing::TempDir() + "/hapsim_obj_reader_test.obj";
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const core::TriangleMesh mesh = ReadObjFile(path);
  EXPECT_EQ(mesh.vertices_m.cols(), 3);
  EXPECT_EQ(mesh.triangles.size(), 1u);

  try {
    ReadObjFile(path, 10);
    ADD_FAILURE() << "a file over the size limit was read";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("limit"), std::string::npos);
  }
  std::ofstream(path) << "v 0 0 0\nf 1 2 3\n";
  try {
    ReadObjFile(path);
    ADD_FAILURE() << "a malformed file was read";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": OBJ line 2: face index 2 out of range");
  }
  std::remove(path.c_str());
  EXPECT_THROW(ReadObjFile(path), MeshError);  // gone
}

}  // namespace
}  // namespace hapsim::io
