// ListScenes gives clients what they need to build a form for every scene:
// each parameter of each scene's table, with its default, range, unit and
// description, exactly as the core declares them.
#include <gtest/gtest.h>

#include "hapsim/api/session_service.h"

namespace hapsim::service {
namespace {

TEST(ListScenes, ReturnsEveryParameterOfEverySceneWithDefaultRangeAndUnit) {
  SessionServiceImpl service(nullptr, nullptr, nullptr);  // ListScenes needs no session state
  hapsim::v1::ListScenesRequest request;
  hapsim::v1::ListScenesResponse response;
  ASSERT_TRUE(service.ListScenes(nullptr, &request, &response).ok());
  const auto catalog = core::SceneCatalog();
  ASSERT_EQ(response.scenes_size(), static_cast<int>(catalog.size()));
  for (std::size_t i = 0; i < catalog.size(); ++i) {
    const auto& wire = response.scenes(static_cast<int>(i));
    const auto& scene = catalog[i];
    SCOPED_TRACE(scene.name);
    EXPECT_EQ(wire.name(), scene.name);
    EXPECT_EQ(wire.description(), scene.description);
    ASSERT_EQ(wire.parameters_size(), static_cast<int>(scene.params.size()));
    for (std::size_t k = 0; k < scene.params.size(); ++k) {
      const auto& w = wire.parameters(static_cast<int>(k));
      const auto& p = scene.params[k];
      SCOPED_TRACE(p.spec.name);
      EXPECT_EQ(w.name(), p.spec.name);
      EXPECT_EQ(w.unit(), p.spec.unit);
      EXPECT_EQ(w.default_value(), p.default_value);
      EXPECT_EQ(w.min(), p.spec.min);
      EXPECT_EQ(w.max(), p.spec.max);
      EXPECT_EQ(w.min_exclusive(), p.spec.min_open);
      EXPECT_EQ(w.max_exclusive(), p.spec.max_open);
      EXPECT_EQ(w.integer(), p.spec.integer);
      EXPECT_EQ(w.description(), p.spec.description);
      EXPECT_EQ(w.range(), core::DescribeRange(p.spec));
      EXPECT_EQ(w.choices_size(), static_cast<int>(p.spec.choices.size()));
    }
  }
}

}  // namespace
}  // namespace hapsim::service
