// Built against the installed hapsim::core: every scene of the catalog is
// there, and a needle lowered from 2 mm above the default tissue block to
// 3 mm below its top is pushed back up, by less than 3 N (1000 N/m, the
// stiffest contact the scenes render, at 3 mm).
#include <cmath>
#include <cstdio>

#include "hapsim/core/scenes/scene.h"

int main() {
  const auto catalog = hapsim::core::SceneCatalog();
  std::printf("scenes: %zu\n", catalog.size());
  auto scene = hapsim::core::MakeScene({"tissue_block", {}});
  hapsim::core::ToolInput tool;
  tool.valid = true;
  for (int tick = 0; tick <= 600; ++tick) {  // 2 mm above to 3 mm deep at 5 mm/s, then held 0.2 s
    tool.tip_W_m.z() = std::max(0.002 - 5e-3 * 1e-3 * tick, -0.003);
    scene->Step(tool, 1e-3);
  }
  const double up_N = scene->ToolForce_W_N().z();
  std::printf("tip 3 mm below the top: force up %.4f N, tip depth %.4f mm, state hash %llu\n", up_N,
              1e3 * scene->Status().tip_depth_m, static_cast<unsigned long long>(scene->StateHash()));
  const bool ok = catalog.size() == 4 && up_N > 0.0 && up_N < 3.0 && std::isfinite(up_N);
  std::printf("%s\n", ok ? "ok" : "FAIL");
  return ok ? 0 : 1;
}
