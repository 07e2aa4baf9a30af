// Draws a SceneView with OpenGL 3.3: the mesh lit per vertex, one
// colour per part (viewer::PartColour), tissue layers optionally
// see-through so the needle's path inside shows; the tool from the frame's
// pose; the force on the tool as an arrow; scene events as markers. Owns its
// GL objects: create and use it with a context current.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "hapsim/gui/display_simplifier.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/orbit_camera.h"

namespace hapsim::gui {

struct RenderOptions {
  bool see_through_layers = true;  // draw "skin" and "fat" translucent when the scene has several layers
  bool show_tool = true;
  bool show_force = true;
  bool show_events = true;
  // A mesh of more triangles is drawn simplified to at most this many
  // (display_simplifier.h: software rendering pays per triangle); 0: all.
  std::size_t max_triangles = 50000;
  double force_arrow_m_per_N = 0.01;  // arrow length per newton (10 mm/N), capped at kMaxArrow_m
  float background[3] = {0.13f, 0.15f, 0.18f};
};

class SceneRenderer {
 public:
  static constexpr double kMaxArrow_m = 0.05;
  static constexpr double kToolRadius_m = 0.35e-3;

  SceneRenderer();
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  // Uploads what changed since the last call (positions every new version,
  // triangles when the topology changed).
  void Upload(const SceneView& scene);
  // Draws into the viewport [x, y, width, height] (GL pixels, y up) of the
  // bound framebuffer, clearing it first.
  void Draw(const SceneView& scene, const OrbitCamera& camera, int x_px, int y_px, int width_px, int height_px,
            const RenderOptions& options);
  // Meshes of more triangles are drawn simplified to at most this many
  // (display_simplifier.h); 0 draws every triangle. Takes effect at the
  // next Upload.
  void SetTriangleBudget(std::size_t max_triangles);
  std::size_t mesh_triangles() const { return mesh_triangles_; }    // live triangles of the scene
  std::size_t drawn_triangles() const { return drawn_triangles_; }  // what is drawn of them
  // Tool length drawn for a scene of this size [m].
  static double ToolLength_m(const SceneView& scene);

 private:
  struct Solid;  // a small static mesh (cylinder, cone, octahedron)
  void LinkProgram();
  void CreateMeshBuffers();
  void UploadTriangles(const SceneView& scene);
  void SortByPart(const CoarseTriangles& drawn, std::size_t parts, std::vector<std::uint32_t>* sorted);
  void ClearViewport(int x_px, int y_px, int width_px, int height_px, const RenderOptions& options);
  void DrawParts(const SceneView& scene, const RenderOptions& options, bool translucent_pass);
  void DrawTool(const SceneView& scene);
  void DrawForceArrow(const SceneView& scene, const RenderOptions& options);
  void DrawEventMarkers(const SceneView& scene);
  void DrawSolid(const Solid& solid, const Eigen::Matrix4f& model, const float rgb[3], float alpha);
  static void Overwrite(unsigned target, unsigned buffer, const void* data, std::size_t bytes,
                        std::size_t* stored_bytes);

  unsigned program_ = 0;
  int u_view_projection_ = -1, u_model_ = -1, u_normal_matrix_ = -1, u_colour_ = -1, u_alpha_ = -1, u_eye_ = -1;
  unsigned mesh_vao_ = 0, mesh_positions_ = 0, mesh_normals_ = 0, mesh_indices_ = 0;
  std::uint64_t uploaded_version_ = ~0ull, uploaded_topology_ = ~0ull;
  std::size_t positions_bytes_ = 0, normals_bytes_ = 0;
  std::size_t triangle_budget_ = 0, mesh_triangles_ = 0, drawn_triangles_ = 0;
  std::vector<float> normals_;  // 3 per vertex slot, recomputed as the mesh moves
  struct PartRange {
    std::uint16_t part = 0;
    std::size_t first = 0, count = 0;  // in indices
  };
  std::vector<PartRange> ranges_;
  std::unique_ptr<Solid> cylinder_, cone_, octahedron_;
};

}  // namespace hapsim::gui
