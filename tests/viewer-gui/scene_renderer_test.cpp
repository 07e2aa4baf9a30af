// The renderer, off screen (EGL surfaceless, Mesa llvmpipe here), checked
// by pixels: where the camera model (tested against the pinhole model in
// orbit_camera_test) says a thing is, its colour must be.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "hapsim/gui/gl.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_export.h"
#include "render_test_util.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>

namespace hapsim::gui {
namespace {

using testing::GridKeyframe;
using testing::Pixel;

constexpr int kW = 320, kH = 240;

class SceneRendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    gl_ = HeadlessGl::Open(kW, kH, &error).release();
    if (!gl_) std::fprintf(stderr, "no off-screen GL: %s\n", error.c_str());
  }
  static void TearDownTestSuite() {
    delete gl_;
    gl_ = nullptr;
  }
  void SetUp() override {
    if (!gl_) GTEST_FAIL() << "EGL surfaceless + OpenGL 3.3 must be available (Mesa)";
  }
  Image Render(const hapsim::v1::Frame& frame, const OrbitCamera& camera, const RenderOptions& options = {},
               std::size_t* drawn_triangles = nullptr) {
    viewer::MeshCache cache;
    EXPECT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
    LiveScene live;
    live.OnFrame(frame, cache);
    SceneView view;
    live.CopyIfNewer(&view);
    SceneRenderer renderer;
    renderer.SetTriangleBudget(options.max_triangles);
    glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer());
    renderer.Upload(view);
    if (drawn_triangles) *drawn_triangles = renderer.drawn_triangles();
    renderer.Draw(view, camera, 0, 0, kW, kH, options);
    glFinish();
    return ReadFramebuffer(kW, kH);
  }
  static HeadlessGl* gl_;
};
HeadlessGl* SceneRendererTest::gl_ = nullptr;

OrbitCamera LookingDown() {
  OrbitCamera c;
  c.pose.target_m = Eigen::Vector3d::Zero();
  c.pose.distance_m = 0.06;
  c.pose.yaw_deg = 0.0;
  c.pose.pitch_deg = 89.0;
  return c;
}

TEST_F(SceneRendererTest, TheTissueHasItsPartColourAndTheRestIsBackground) {
  RenderOptions opaque;
  opaque.see_through_layers = false;
  const Image image = Render(GridKeyframe(5, 0.01, "muscle"), LookingDown(), opaque);
  const auto centre = Pixel(image, kW / 2.0, kH / 2.0);
  const auto muscle = viewer::PartColour("muscle");  // (0.72, 0.22, 0.22): red dominates
  EXPECT_GT(centre[0], 2 * centre[1]) << "muscle red";
  EXPECT_NEAR(static_cast<double>(centre[1]) / centre[0], muscle[1] / muscle[0], 0.05) << "hue kept by the lighting";
  const auto corner = Pixel(image, 2, 2);  // the 20 mm square covers the middle only
  EXPECT_EQ(corner[0], static_cast<int>(std::lround(0.13 * 255)));
  EXPECT_EQ(corner[1], static_cast<int>(std::lround(0.15 * 255)));
  EXPECT_EQ(corner[2], static_cast<int>(std::lround(0.18 * 255)));
  // The square's edge where the camera puts it: just inside is tissue, just outside background.
  const OrbitCamera c = LookingDown();
  Eigen::Vector2d inside, outside;
  ASSERT_TRUE(c.ToPixel(Eigen::Vector3d(0.0093, 0.0, 0.0), kW, kH, &inside));
  ASSERT_TRUE(c.ToPixel(Eigen::Vector3d(0.0107, 0.0, 0.0), kW, kH, &outside));
  EXPECT_GT(Pixel(image, inside.x(), inside.y())[0], 100);
  EXPECT_EQ(Pixel(image, outside.x(), outside.y())[0], corner[0]);
}

TEST_F(SceneRendererTest, SkinIsSeeThroughOverTheNeedle) {
  auto frame = GridKeyframe(5, 0.01, "skin");
  auto* tool = frame.mutable_tool();  // a needle 4 mm under the skin, pointing down
  for (const double v : {0.0, 0.0, -0.004}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  OrbitCamera side = LookingDown();
  side.pose.pitch_deg = 30.0;
  const Image see_through = Render(frame, side);
  RenderOptions opaque;
  opaque.see_through_layers = false;
  const Image hidden = Render(frame, side, opaque);
  Eigen::Vector2d under;  // a point of the shaft 2 mm below the skin
  ASSERT_TRUE(side.ToPixel(Eigen::Vector3d(0.0, 0.0, -0.002), kW, kH, &under));
  const auto a = Pixel(see_through, under.x(), under.y()), b = Pixel(hidden, under.x(), under.y());
  // Opaque skin hides the steel (skin: r > g > b); see-through lets its grey-blue through (b rises).
  EXPECT_GT(b[0], b[2] + 40) << "opaque skin colour";
  EXPECT_GT(a[2], b[2] + 20) << "the steel shows through the skin";
}

TEST_F(SceneRendererTest, ASingleSkinLayerStaysOpaque) {
  auto frame = GridKeyframe(5, 0.01, "skin");
  frame.mutable_keyframe()->mutable_layer_names()->RemoveLast();  // the cutting patch: skin only
  auto* tool = frame.mutable_tool();
  for (const double v : {0.0, 0.0, -0.004}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  OrbitCamera side = LookingDown();
  side.pose.pitch_deg = 30.0;
  const Image image = Render(frame, side);  // see-through on (the default)
  Eigen::Vector2d under;
  ASSERT_TRUE(side.ToPixel(Eigen::Vector3d(0.0, 0.0, -0.002), kW, kH, &under));
  const auto p = Pixel(image, under.x(), under.y());
  EXPECT_GT(p[0], p[2] + 40) << "skin colour, the needle under it hidden";
}

TEST_F(SceneRendererTest, TheToolIsDrawnAtItsPose) {
  auto frame = GridKeyframe(5, 0.01, "muscle");
  auto* tool = frame.mutable_tool();
  for (const double v : {0.004, -0.002, 0.0}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);  // handle straight up
  OrbitCamera side = LookingDown();
  side.pose.pitch_deg = 20.0;
  side.pose.distance_m = 0.12;
  const Image image = Render(frame, side);
  // Along the shaft (+z from the tip) the pixels are steel: bright, blue >= red.
  for (const double up_mm : {3.0, 8.0, 14.0}) {
    Eigen::Vector2d px;
    ASSERT_TRUE(side.ToPixel(Eigen::Vector3d(0.004, -0.002, up_mm * 1e-3), kW, kH, &px));
    const auto p = Pixel(image, px.x(), px.y());
    EXPECT_GE(p[2], p[0]) << "steel at " << up_mm << " mm";
    EXPECT_GT(p[2], 120) << "steel at " << up_mm << " mm";
  }
  // Beside the shaft, 3 mm off, background.
  Eigen::Vector2d off;
  ASSERT_TRUE(side.ToPixel(Eigen::Vector3d(0.007, -0.002, 0.008), kW, kH, &off));
  EXPECT_LT(Pixel(image, off.x(), off.y())[2], 60);
}

TEST_F(SceneRendererTest, TheForceArrowPointsAlongTheForce) {
  auto frame = GridKeyframe(5, 0.01, "muscle");
  auto* tool = frame.mutable_tool();
  for (const double v : {0.0, 0.0, 0.0}) tool->add_tip_m(v);
  for (const double v : {1.0, 0.0, 0.0, 0.0}) tool->add_orientation_wxyz(v);
  for (const double v : {1.5, 0.0, 0.0}) tool->add_force_n(v);  // 1.5 N along +x: a 15 mm arrow
  OrbitCamera above = LookingDown();
  const Image image = Render(frame, above);
  Eigen::Vector2d mid, beyond;
  ASSERT_TRUE(above.ToPixel(Eigen::Vector3d(0.008, 0.0, 0.0), kW, kH, &mid));
  ASSERT_TRUE(above.ToPixel(Eigen::Vector3d(-0.008, 0.0, 0.0), kW, kH, &beyond));
  const auto yellow = Pixel(image, mid.x(), mid.y()), other_side = Pixel(image, beyond.x(), beyond.y());
  EXPECT_GT(yellow[1], 150) << "arrow yellow (high green) at +8 mm";
  EXPECT_LT(yellow[2], yellow[1] / 2);
  EXPECT_LT(other_side[1], 120) << "no arrow at -8 mm";
}

// The same recorded frames must give the same picture on the same renderer.
TEST_F(SceneRendererTest, AFineMeshDrawnSimplifiedLooksLikeTheFullOne) {
  // 201 x 201 vertices (80 000 triangles, 0.3 mm apart) with a 3 mm deep
  // dimple, in 320 x 240 pixels: far more triangles than pixels. Drawn
  // within a 20 000-triangle budget, the picture must stay the same to the
  // eye: 99 % of pixels within 2 of 255 levels and the mean within 0.5.
  hapsim::v1::Frame frame = GridKeyframe(201, 0.03, "skin");
  auto* q = frame.mutable_keyframe()->mutable_positions_q();
  for (int v = 0; v < 201 * 201; ++v) {
    const double x = q->Get(3 * v) * 1e-5, y = q->Get(3 * v + 1) * 1e-5;
    q->Set(3 * v + 2, static_cast<std::int32_t>(std::lround(-0.003 * std::exp(-(x * x + y * y) / 1e-4) / 1e-5)));
  }
  OrbitCamera camera;
  camera.pose.distance_m = 0.12;
  camera.pose.pitch_deg = 35.0;
  RenderOptions full, simplified;
  full.max_triangles = 0;
  simplified.max_triangles = 20000;
  std::size_t drawn_full = 0, drawn_simplified = 0;
  const Image a = Render(frame, camera, full, &drawn_full), b = Render(frame, camera, simplified, &drawn_simplified);
  EXPECT_EQ(drawn_full, 80000u);
  EXPECT_LE(drawn_simplified, 20000u);
  std::vector<int> worst;
  double sum = 0.0;
  for (std::size_t i = 0; i + 3 < a.rgba.size(); i += 4) {
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a.rgba[i + k] - b.rgba[i + k]));
    worst.push_back(d);
    sum += d;
  }
  std::sort(worst.begin(), worst.end());
  EXPECT_LE(worst[worst.size() * 99 / 100], 2);
  EXPECT_LE(sum / static_cast<double>(worst.size()), 0.5);
  // And it is the sheet that was compared, not the background (33, 38, 46):
  // the centre (the dimple) is lit tissue.
  const auto centre = Pixel(b, kW / 2.0, kH / 2.0);
  EXPECT_GT(std::abs(centre[0] - 33) + std::abs(centre[1] - 38) + std::abs(centre[2] - 46), 100);
}

TEST_F(SceneRendererTest, ARecordedAcupunctureFrameMatchesItsGoldenPicture) {
  const std::string dir = std::string(HAPSIM_SOURCE_DIR) + "/tests/viewer-gui/data/";
  std::vector<hapsim::v1::Frame> frames;
  std::string error;
  ASSERT_TRUE(viewer::ReadFrameLog(dir + "acupuncture.frames", &frames, &error)) << error;
  viewer::MeshCache cache;
  LiveScene live;
  for (const auto& f : frames) {
    ASSERT_EQ(cache.Apply(f, &error), viewer::ApplyResult::kApplied) << error;
    live.OnFrame(f, cache);
  }
  SceneView view;
  live.CopyIfNewer(&view);
  OrbitCamera camera;
  camera.pose.target_m = Eigen::Vector3d(0.0, 0.0, -0.004);
  camera.pose.distance_m = 0.07;
  camera.pose.yaw_deg = -30.0;
  camera.pose.pitch_deg = 25.0;
  SceneRenderer renderer;
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer());
  renderer.Upload(view);
  renderer.Draw(view, camera, 0, 0, kW, kH, RenderOptions());
  glFinish();
  const Image image = ReadFramebuffer(kW, kH);
  const std::string golden = dir + "acupuncture_golden.png";
  if (std::getenv("HAPSIM_UPDATE_GOLDEN")) {
    ASSERT_TRUE(WritePng(golden, image, &error)) << error;
    std::ofstream(dir + "acupuncture_golden.renderer") << gl_->Renderer() << "\n";
  }
  std::string renderer_name;
  std::getline(std::ifstream(dir + "acupuncture_golden.renderer"), renderer_name);
  if (renderer_name != gl_->Renderer())
    GTEST_SKIP() << "golden made on '" << renderer_name << "', this is '" << gl_->Renderer() << "'";
  int w = 0, h = 0, channels = 0;
  unsigned char* expected = stbi_load(golden.c_str(), &w, &h, &channels, 4);
  ASSERT_NE(expected, nullptr) << golden;
  ASSERT_EQ(w, kW);
  ASSERT_EQ(h, kH);
  std::size_t differing = 0;
  double sum_abs = 0.0;
  for (std::size_t i = 0; i < image.rgba.size(); ++i) {
    const int d = std::abs(static_cast<int>(image.rgba[i]) - static_cast<int>(expected[i]));
    sum_abs += d;
    if (d > 24) ++differing;
  }
  stbi_image_free(expected);
  // Same renderer, same input: at most rounding noise (mean |d| < 0.5 of a
  // level, under 0.1 % of the samples off by more than 24 levels).
  EXPECT_LT(sum_abs / static_cast<double>(image.rgba.size()), 0.5);
  EXPECT_LT(differing, image.rgba.size() / 1000);
  // And the picture is not blank: the tissue covers a good part of it.
  std::size_t tissue = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    if (image.rgba[i] > image.rgba[i + 2] + 30) ++tissue;
  EXPECT_GT(tissue, image.rgba.size() / 4 / 5) << "at least a fifth of the picture is reddish tissue";
}

}  // namespace
}  // namespace hapsim::gui
