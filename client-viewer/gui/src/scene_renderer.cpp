#include "hapsim/gui/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "hapsim/gui/display_simplifier.h"
#include "hapsim/gui/gl.h"
#include "hapsim/gui/vertex_normals.h"
#include "hapsim/viewer/mesh_export.h"

namespace hapsim::gui {

namespace {

// Lit per vertex (Gouraud) from the eye and from above, both sides of a
// face alike (cut surfaces are seen from inside); the fragment shader only
// passes the colour on. Software rendering (llvmpipe) shades whole 4x4
// pixel blocks for every tiny triangle of a fine mesh, so per-pixel lighting
// cost twice the frame time at 50k vertices (docs/viewer.md, frame rates).
constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_m;
layout(location = 1) in vec3 normal;
uniform mat4 view_projection;
uniform mat4 model;
uniform mat3 normal_matrix;
uniform vec3 colour;
uniform float alpha;
uniform vec3 eye_m;
out vec4 lit_colour;
void main() {
  vec4 w = model * vec4(position_m, 1.0);
  gl_Position = view_projection * w;
  vec3 to_eye = normalize(eye_m - w.xyz);
  vec3 n = normal_matrix * normal;
  float length_n = length(n);
  n = length_n > 1e-6 ? n / length_n : to_eye;
  if (dot(n, to_eye) < 0.0) n = -n;
  vec3 key = normalize(vec3(0.3, -0.4, 1.0));
  float diffuse = 0.55 * max(dot(n, to_eye), 0.0) + 0.35 * max(dot(n, key), 0.0);
  float specular = 0.25 * pow(max(dot(reflect(-key, n), to_eye), 0.0), 24.0);
  lit_colour = vec4(colour * (0.22 + diffuse) + vec3(specular), alpha);
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec4 lit_colour;
out vec4 out_colour;
void main() { out_colour = lit_colour; }
)";

unsigned Compile(unsigned kind, const char* source) {
  const unsigned shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("viewer shader does not compile: ") + log);
  }
  return shader;
}

bool IsTranslucentLayer(const std::string& part) { return part == "skin" || part == "fat"; }
float LayerAlpha(const std::string& part) { return part == "skin" ? 0.35f : 0.5f; }

}  // namespace

struct SceneRenderer::Solid {
  unsigned vao = 0, positions = 0, normals = 0, indices = 0;
  int count = 0;
  Solid(const std::vector<float>& p, const std::vector<std::uint32_t>& tri) {
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &positions);
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(p.size() * sizeof(float)), p.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    std::vector<float> n;
    ComputeVertexNormals(p, tri, &n);
    glGenBuffers(1, &normals);
    glBindBuffer(GL_ARRAY_BUFFER, normals);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(n.size() * sizeof(float)), n.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(1);
    glGenBuffers(1, &indices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(tri.size() * sizeof(std::uint32_t)), tri.data(),
                 GL_STATIC_DRAW);
    count = static_cast<int>(tri.size());
    glBindVertexArray(0);
  }
  ~Solid() {
    glDeleteBuffers(1, &positions);
    glDeleteBuffers(1, &normals);
    glDeleteBuffers(1, &indices);
    glDeleteVertexArrays(1, &vao);
  }
};

namespace {

// Unit solids along +z: a cylinder r = 1 from z = 0 to 1, a cone of base
// r = 1 at z = 0 and apex at z = 1, an octahedron of radius 1.
constexpr int kSides = 12;
void Ring(std::vector<float>* p, float z, float r) {
  for (int k = 0; k < kSides; ++k) {
    const double a = 2.0 * 3.14159265358979323846 * k / kSides;
    p->insert(p->end(), {r * static_cast<float>(std::cos(a)), r * static_cast<float>(std::sin(a)), z});
  }
}
void Cylinder(std::vector<float>* p, std::vector<std::uint32_t>* t) {
  Ring(p, 0.0f, 1.0f);
  Ring(p, 1.0f, 1.0f);
  p->insert(p->end(), {0, 0, 0, 0, 0, 1});
  const std::uint32_t c0 = 2 * kSides, c1 = c0 + 1;
  for (std::uint32_t k = 0; k < kSides; ++k) {
    const std::uint32_t a = k, b = (k + 1) % kSides;
    t->insert(t->end(), {a, b, b + kSides, a, b + kSides, a + kSides, c0, b, a, c1, a + kSides, b + kSides});
  }
}
void Cone(std::vector<float>* p, std::vector<std::uint32_t>* t) {
  Ring(p, 0.0f, 1.0f);
  p->insert(p->end(), {0, 0, 1, 0, 0, 0});
  const std::uint32_t apex = kSides, base = kSides + 1;
  for (std::uint32_t k = 0; k < kSides; ++k) {
    const std::uint32_t a = k, b = (k + 1) % kSides;
    t->insert(t->end(), {a, b, apex, base, b, a});
  }
}
void Octahedron(std::vector<float>* p, std::vector<std::uint32_t>* t) {
  *p = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  *t = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
}

// Model matrix putting a unit +z solid from `from` along `direction` (unit),
// `length` long and `radius` wide.
Eigen::Matrix4f Along(const Eigen::Vector3d& from, const Eigen::Vector3d& direction, double length, double radius) {
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), direction);
  Eigen::Affine3d m = Eigen::Translation3d(from) * q * Eigen::Scaling(radius, radius, length);
  return m.matrix().cast<float>();
}

// Normals go through the inverse transpose of the model's linear part (the
// solids are scaled unevenly: thin and long).
Eigen::Matrix3f NormalMatrix(const Eigen::Matrix4f& model) {
  return model.topLeftCorner<3, 3>().inverse().transpose();
}

}  // namespace

SceneRenderer::SceneRenderer() {
  LinkProgram();
  CreateMeshBuffers();
  std::vector<float> p;
  std::vector<std::uint32_t> t;
  Cylinder(&p, &t);
  cylinder_ = std::make_unique<Solid>(p, t);
  p.clear();
  t.clear();
  Cone(&p, &t);
  cone_ = std::make_unique<Solid>(p, t);
  Octahedron(&p, &t);
  octahedron_ = std::make_unique<Solid>(p, t);
}

void SceneRenderer::LinkProgram() {
  const unsigned vs = Compile(GL_VERTEX_SHADER, kVertexShader), fs = Compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("viewer shaders do not link");
  u_view_projection_ = glGetUniformLocation(program_, "view_projection");
  u_model_ = glGetUniformLocation(program_, "model");
  u_colour_ = glGetUniformLocation(program_, "colour");
  u_alpha_ = glGetUniformLocation(program_, "alpha");
  u_eye_ = glGetUniformLocation(program_, "eye_m");
  u_normal_matrix_ = glGetUniformLocation(program_, "normal_matrix");
}

void SceneRenderer::CreateMeshBuffers() {
  glGenVertexArrays(1, &mesh_vao_);
  glBindVertexArray(mesh_vao_);
  glGenBuffers(1, &mesh_positions_);
  glBindBuffer(GL_ARRAY_BUFFER, mesh_positions_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &mesh_normals_);
  glBindBuffer(GL_ARRAY_BUFFER, mesh_normals_);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glGenBuffers(1, &mesh_indices_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_indices_);
  glBindVertexArray(0);
}

SceneRenderer::~SceneRenderer() {
  cylinder_.reset();
  cone_.reset();
  octahedron_.reset();
  glDeleteBuffers(1, &mesh_positions_);
  glDeleteBuffers(1, &mesh_normals_);
  glDeleteBuffers(1, &mesh_indices_);
  glDeleteVertexArrays(1, &mesh_vao_);
  glDeleteProgram(program_);
}

// Replaces a buffer's contents: in place when the size is unchanged (a new
// store every frame costs llvmpipe fresh pages, i.e. page faults, for the
// whole array).
void SceneRenderer::Overwrite(unsigned target, unsigned buffer, const void* data, std::size_t bytes,
                              std::size_t* stored_bytes) {
  glBindBuffer(target, buffer);
  if (bytes == *stored_bytes) {
    glBufferSubData(target, 0, static_cast<GLsizeiptr>(bytes), data);
  } else {
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
    *stored_bytes = bytes;
  }
}

void SceneRenderer::Upload(const SceneView& scene) {
  glBindVertexArray(mesh_vao_);
  const bool moved = scene.version != uploaded_version_, cut = scene.topology_stamp != uploaded_topology_;
  if (moved) {
    // Straight from the buffer the stream's thread wrote (no copy on the way).
    Overwrite(GL_ARRAY_BUFFER, mesh_positions_, scene.positions_m.data(), scene.positions_m.size() * sizeof(float),
              &positions_bytes_);
    uploaded_version_ = scene.version;
  }
  if (moved || cut) {
    static const std::vector<std::uint32_t> kNone;
    ComputeVertexNormals(scene.positions_m.values(), scene.triangles ? scene.triangles->vertices : kNone, &normals_);
    Overwrite(GL_ARRAY_BUFFER, mesh_normals_, normals_.data(), normals_.size() * sizeof(float), &normals_bytes_);
  }
  if (cut) {
    UploadTriangles(scene);
    uploaded_topology_ = scene.topology_stamp;
  }
  glBindVertexArray(0);
}

// Above the budget, a coarser list over the same vertices (see
// display_simplifier.h); then sorted by part so each part is one draw call.
void SceneRenderer::UploadTriangles(const SceneView& scene) {
  ranges_.clear();
  std::vector<std::uint32_t> sorted;
  mesh_triangles_ = drawn_triangles_ = 0;
  if (scene.triangles) {
    const TriangleList& list = *scene.triangles;
    const CoarseTriangles drawn =
        SimplifyToBudget(scene.positions_m.values(), list.vertices, list.parts, triangle_budget_);
    mesh_triangles_ = list.parts.size();
    drawn_triangles_ = drawn.parts.size();
    SortByPart(drawn, list.part_names.size(), &sorted);
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_indices_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(sorted.size() * sizeof(std::uint32_t)), sorted.data(),
               GL_STATIC_DRAW);
}

// A counting sort of the triangles by part (parts past `parts` last), and
// each part's range of indices.
void SceneRenderer::SortByPart(const CoarseTriangles& drawn, std::size_t parts, std::vector<std::uint32_t>* sorted) {
  std::vector<std::size_t> count(parts + 1, 0);
  for (const auto p : drawn.parts) ++count[std::min<std::size_t>(p, parts)];
  std::vector<std::size_t> start(parts + 2, 0);
  for (std::size_t p = 0; p <= parts; ++p) start[p + 1] = start[p] + count[p];
  sorted->resize(3 * start[parts + 1]);
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < drawn.parts.size(); ++t) {
    const std::size_t at = next[std::min<std::size_t>(drawn.parts[t], parts)]++;
    for (std::size_t k = 0; k < 3; ++k) (*sorted)[3 * at + k] = drawn.vertices[3 * t + k];
  }
  for (std::size_t p = 0; p < parts; ++p)
    if (count[p] > 0) ranges_.push_back({static_cast<std::uint16_t>(p), 3 * start[p], 3 * count[p]});
}

void SceneRenderer::SetTriangleBudget(std::size_t max_triangles) {
  if (max_triangles == triangle_budget_) return;
  triangle_budget_ = max_triangles;
  uploaded_topology_ = ~0ull;  // rebuild the drawn list at the next Upload
}

double SceneRenderer::ToolLength_m(const SceneView& scene) {
  return std::clamp(0.6 * (scene.hi_m - scene.lo_m).norm(), 0.02, 0.08);
}

void SceneRenderer::DrawSolid(const Solid& solid, const Eigen::Matrix4f& model, const float rgb[3], float alpha) {
  glUniformMatrix4fv(u_model_, 1, GL_FALSE, model.data());
  const Eigen::Matrix3f normal_matrix = NormalMatrix(model);
  glUniformMatrix3fv(u_normal_matrix_, 1, GL_FALSE, normal_matrix.data());
  glUniform3f(u_colour_, rgb[0], rgb[1], rgb[2]);
  glUniform1f(u_alpha_, alpha);
  glBindVertexArray(solid.vao);
  glDrawElements(GL_TRIANGLES, solid.count, GL_UNSIGNED_INT, nullptr);
}

void SceneRenderer::Draw(const SceneView& scene, const OrbitCamera& camera, int x_px, int y_px, int width_px,
                         int height_px, const RenderOptions& options) {
  ClearViewport(x_px, y_px, width_px, height_px, options);
  glUseProgram(program_);
  const Eigen::Matrix4f view_projection =
      camera.Projection(static_cast<double>(width_px) / std::max(height_px, 1)) * camera.View();
  glUniformMatrix4fv(u_view_projection_, 1, GL_FALSE, view_projection.data());
  const Eigen::Vector3f eye = camera.Eye_m().cast<float>();
  glUniform3f(u_eye_, eye.x(), eye.y(), eye.z());
  DrawParts(scene, options, false);
  if (options.show_tool && scene.tool.valid) DrawTool(scene);
  if (options.show_force && scene.tool.valid) DrawForceArrow(scene, options);
  if (options.show_events) DrawEventMarkers(scene);
  // Translucent layers last, without writing depth, so what is inside shows.
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  DrawParts(scene, options, true);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glUseProgram(0);
}

void SceneRenderer::ClearViewport(int x_px, int y_px, int width_px, int height_px, const RenderOptions& options) {
  glViewport(x_px, y_px, width_px, height_px);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x_px, y_px, width_px, height_px);
  glClearColor(options.background[0], options.background[1], options.background[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
}

// The mesh's parts of one pass: opaque, or the see-through layers.
void SceneRenderer::DrawParts(const SceneView& scene, const RenderOptions& options, bool translucent_pass) {
  static const Eigen::Matrix4f kIdentity4 = Eigen::Matrix4f::Identity();
  static const Eigen::Matrix3f kIdentity3 = Eigen::Matrix3f::Identity();
  static const std::vector<std::string> kNoNames;
  const auto& names = scene.triangles ? scene.triangles->part_names : kNoNames;
  const bool layered = scene.layer_names.size() > 1;
  glUniformMatrix4fv(u_model_, 1, GL_FALSE, kIdentity4.data());
  glUniformMatrix3fv(u_normal_matrix_, 1, GL_FALSE, kIdentity3.data());
  glBindVertexArray(mesh_vao_);
  for (const auto& range : ranges_) {
    const std::string& name = range.part < names.size() ? names[range.part] : "";
    if (!scene.tool.valid && viewer::IsToolPart(name)) continue;  // parked: no device streams
    // Only over other layers (acupuncture's skin over fat over muscle): a
    // single skin (the cutting patch) stays opaque.
    const bool translucent = options.see_through_layers && layered && IsTranslucentLayer(name);
    if (translucent != translucent_pass) continue;
    const auto rgb = viewer::PartColour(name);
    glUniform3f(u_colour_, rgb[0], rgb[1], rgb[2]);
    glUniform1f(u_alpha_, translucent ? LayerAlpha(name) : 1.0f);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(range.first * sizeof(std::uint32_t)));
  }
}

// The tool's +z runs from the tip to the handle (the scenes' convention).
void SceneRenderer::DrawTool(const SceneView& scene) {
  const Eigen::Vector3d up = scene.tool.orientation * Eigen::Vector3d::UnitZ();
  const double len = ToolLength_m(scene);
  const float steel[3] = {0.80f, 0.82f, 0.88f};
  DrawSolid(*cylinder_, Along(scene.tool.tip_m, up, len, kToolRadius_m), steel, 1.0f);
  const float grip[3] = {0.20f, 0.45f, 0.85f};
  DrawSolid(*cylinder_, Along(scene.tool.tip_m + 0.6 * len * up, up, 0.4 * len, 4 * kToolRadius_m), grip, 1.0f);
}

void SceneRenderer::DrawForceArrow(const SceneView& scene, const RenderOptions& options) {
  const double f = scene.tool.force_N.norm();
  if (f <= 1e-3) return;
  const double scale_m = std::max((scene.hi_m - scene.lo_m).norm(), 0.01);
  const Eigen::Vector3d dir = scene.tool.force_N / f;
  const double length = std::min(f * options.force_arrow_m_per_N, kMaxArrow_m);
  const double head = std::min(0.3 * length, 0.004), radius = 0.012 * scale_m;
  const float yellow[3] = {1.0f, 0.85f, 0.10f};
  DrawSolid(*cylinder_, Along(scene.tool.tip_m, dir, length - head, 0.4 * radius), yellow, 1.0f);
  DrawSolid(*cone_, Along(scene.tool.tip_m + (length - head) * dir, dir, head, radius), yellow, 1.0f);
}

// The newest punctures (red) and cut ends (orange) where they happened;
// contact begin/end would clutter the tip.
void SceneRenderer::DrawEventMarkers(const SceneView& scene) {
  const double scale_m = std::max((scene.hi_m - scene.lo_m).norm(), 0.01);
  const float red[3] = {0.95f, 0.15f, 0.15f}, orange[3] = {1.0f, 0.55f, 0.1f};
  int shown = 0;
  for (auto e = scene.events.rbegin(); e != scene.events.rend() && shown < 24; ++e) {
    if (!e->has_where || !viewer::MarksTissue(e->kind)) continue;
    const Eigen::Affine3d m = Eigen::Translation3d(e->where_m) * Eigen::Scaling(0.012 * scale_m);
    DrawSolid(*octahedron_, m.matrix().cast<float>(), e->kind == viewer::EventKind::kPuncture ? red : orange, 1.0f);
    ++shown;
  }
}

}  // namespace hapsim::gui
