// The viewer's frame cost on software rendering (target: "smooth at 60 fps
// on a 50k-vertex mesh with Mesa llvmpipe"), off screen at 1280x720: every
// iteration re-uploads every vertex (as if a delta moved them all), draws
// the lit mesh, tool and force arrow, and the ImGui panels with a full
// force history, then waits for the GL to finish. Baseline, same run: the
// same frame with no mesh (panels and clear only). Frames per second =
// 1 / (time per iteration). See docs/viewer.md for the figures.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include <benchmark/benchmark.h>
#include <imgui.h>
#include <backends/imgui_impl_opengl3.h>

#include "hapsim/gui/gl.h"
#include "hapsim/gui/gl_context.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/orbit_camera.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/gui/vertex_normals.h"
#include "hapsim/gui/viewer_panels.h"
#include "hapsim/viewer/frame_log.h"

namespace {

using namespace hapsim;
constexpr int kW = 1280, kH = 720;

// A wavy n x n sheet of "skin" 60 mm wide, with the tool pressing in.
hapsim::v1::Frame Sheet(int n) {
  hapsim::v1::Frame frame;
  auto* key = frame.mutable_keyframe();
  key->set_quantum_m(1e-5);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const double x = 0.06 * (ix / (n - 1.0) - 0.5), y = 0.06 * (iy / (n - 1.0) - 0.5);
      const double z = -0.003 * std::exp(-(x * x + y * y) / 1e-4);
      for (const double v : {x, y, z}) key->add_positions_q(static_cast<std::int32_t>(std::lround(v / 1e-5)));
    }
  for (int iy = 0; iy + 1 < n; ++iy)
    for (int ix = 0; ix + 1 < n; ++ix) {
      const auto v = static_cast<std::uint32_t>(ix + n * iy), nu = static_cast<std::uint32_t>(n);
      for (const std::uint32_t t : {v, v + 1, v + nu + 1, v, v + nu + 1, v + nu}) key->add_triangles(t);
      key->add_triangle_parts(0);
      key->add_triangle_parts(0);
    }
  key->add_part_names("skin");
  key->set_vertex_capacity(static_cast<std::uint32_t>(n * n));
  key->set_triangle_capacity(static_cast<std::uint32_t>(2 * (n - 1) * (n - 1)));
  auto* tool = frame.mutable_tool();
  for (const double v : {0.0, 0.0, -0.003}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  for (const double v : {0.0, 0.1, 0.9}) tool->add_force_n(v);
  tool->set_contact_state("contact");
  return frame;
}

void BM_ViewerFrame(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));  // grid side; 0: no mesh (baseline)
  const bool panels = state.range(1) != 0;
  const auto budget = static_cast<std::size_t>(state.range(2));  // triangles drawn at most (0: all)
  std::string error;
  auto gl = gui::HeadlessGl::Open(kW, kH, &error);
  if (!gl) {
    state.SkipWithError(error.c_str());
    return;
  }
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplOpenGL3_Init("#version 330 core");
  gui::LiveScene live;
  viewer::MeshCache cache;
  if (n > 0) {
    const auto frame = Sheet(n);
    cache.Apply(frame);
    live.OnFrame(frame, cache);
  }
  gui::SceneView scene;
  live.CopyIfNewer(&scene);
  for (int i = 0; i < 30000; ++i)  // a full force history to plot (five minutes at 100 Hz)
    scene.history.push_back({0.01 * i, 1.0 + std::sin(0.01 * i), 0.003 * (1.0 + std::sin(0.003 * i))});
  gui::OrbitCamera camera;
  camera.Fit(Eigen::Vector3d(-0.03, -0.03, -0.003), Eigen::Vector3d(0.03, 0.03, 0.0));
  gui::SceneRenderer renderer;
  renderer.SetTriangleBudget(budget);
  gui::ViewState view;
  gui::StreamRate rate;
  for (auto _ : state) {
    ++scene.version;  // re-upload every vertex
    ImGui::GetIO().DisplaySize = ImVec2(kW, kH);
    ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    if (panels) {
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(380, kH));
      ImGui::Begin("hapsim");
      gui::DrawSessionPanel(scene, "bench", "127.0.0.1", rate, &view, nullptr);
      gui::DrawForcePlots(scene, 0.0f, 150.0f);
      gui::DrawEventList(scene);
      ImGui::End();
    }
    ImGui::Render();
    glBindFramebuffer(GL_FRAMEBUFFER, gl->framebuffer());
    renderer.Upload(scene);
    renderer.Draw(scene, camera, 380, 0, kW - 380, kH, view.render);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glFinish();
  }
  state.counters["vertices"] = static_cast<double>(n) * n;
  state.counters["drawn_triangles"] = static_cast<double>(renderer.drawn_triangles());
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui::DestroyContext();
  state.SetLabel(gl->Renderer());
}
// Grid side 0: baseline (no mesh); 71^2 = 5041 and 224^2 = 50176 vertices;
// second argument: with the panels (1) or the 3D view alone (0); third: the
// triangle budget (0: every triangle drawn; the viewer's default simplifies
// the 50k sheet's 99 458 triangles).
BENCHMARK(BM_ViewerFrame)
    ->ArgsProduct({{0, 71, 224}, {1, 0}, {0}})
    ->Args({224, 1, static_cast<long>(gui::RenderOptions{}.max_triangles)})
    ->Args({224, 0, static_cast<long>(gui::RenderOptions{}.max_triangles)})
    ->ArgNames({"grid", "panels", "budget"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

}  // namespace

// The CPU side of lighting per vertex: normals of every vertex from the
// triangles, done each time a frame moves the mesh.
void BM_VertexNormals(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  viewer::MeshCache cache;
  cache.Apply(Sheet(n));
  const viewer::CompactMesh mesh = cache.Compact();
  std::vector<float> positions(mesh.vertices_m.data(), mesh.vertices_m.data() + mesh.vertices_m.size());
  std::vector<float> normals;
  for (auto _ : state) {
    gui::ComputeVertexNormals(positions, mesh.triangles, &normals);
    benchmark::DoNotOptimize(normals.data());
  }
  state.counters["vertices"] = static_cast<double>(n) * n;
}
BENCHMARK(BM_VertexNormals)->Arg(71)->Arg(224)->ArgName("grid")->Unit(benchmark::kMillisecond);

// HAPSIM_BENCH_RECORDINGS=DIR also writes the sheets as recordings
// (DIR/sheet_71.frames, DIR/sheet_224.frames) so the whole viewer can be
// timed on them: hapsim-viewer --replay FILE --benchmark-seconds S.
int main(int argc, char** argv) {
  if (const char* dir = std::getenv("HAPSIM_BENCH_RECORDINGS")) {
    for (const int n : {71, 224}) {
      hapsim::viewer::FrameLogWriter writer;
      std::string error;
      const std::string path = std::string(dir) + "/sheet_" + std::to_string(n) + ".frames";
      if (!writer.Open(path, &error) || !writer.Write(Sheet(n))) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
      }
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
