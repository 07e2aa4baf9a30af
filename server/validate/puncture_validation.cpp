// hapsim-validate puncture: constant-speed needle insertion through skin,
// fat and muscle of the acupuncture scene and back out, checked against the
// paper's Table 1/2 model and the measured skin puncture range.
//
// Protocol: needle vertical (identity orientation), tip from 2 mm above the
// skin at the acupuncture site straight down at 5 mm/s to 30 mm depth (well
// into muscle), then back up at 5 mm/s to 2 mm above; 1 kHz ticks.
//
// Writes force_depth.csv (t_s,depth_mm,force_N,layer,state; force_N is the
// axial force on the needle, positive = pushing it out of the tissue),
// springback.csv (t_s,offset_mm: skin puncture point above the tip reference
// line at the puncture instant; t from the puncture), punctures.csv and
// summary.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hapsim/core/scenes/acupuncture/acupuncture_scene.h"
#include "hapsim/core/scenes/scene.h"
#include "validate_command.h"

namespace hapsim::validate {
namespace {

using core::AcupunctureScene;

constexpr double kSpeed_m_per_s = 5e-3;
constexpr double kDt_s = 1e-3;
constexpr double kStart_m = 2e-3;       // above the skin
constexpr double kMaxDepth_m = 30e-3;   // below the skin top
constexpr int kSpringbackSteps = 300;

struct Sample {
  double t_s, depth_m, force_N;
  int layer;
  std::string state;
  bool inserting;
};

struct Check {
  std::string claim;
  bool ok;
  std::string detail;
};

// The speed sweep: the default scene (what a trainee gets), tip
// straight down from 2 mm above the skin to 30 mm at each speed. Per layer:
// indentation at puncture (tip depth below where the layer's surface was
// when pressing began), peak force,
// and the contact phase (ticks pressing that layer's surface) — against the
// force net's design targets (skin indentation 2-6 mm, fat contact >= 20 ticks
// at 10 mm/s, every peak below the bridge's 2.5 N clamp).
struct SweepRow {
  double speed_mm_s;
  int layer;
  double indentation_mm, peak_N;
  int contact_ticks;
};

// Per layer at one speed: the peak force, the indentation at puncture and
// the ticks pressing its surface.
struct SweepLayers {
  std::array<double, 3> peak{}, indentation{};
  std::array<int, 3> ticks{};
  std::array<bool, 3> pierced{};
};

// One insertion of the default scene at speed_mm_s, its curve written to
// force_depth_<speed>mm_s.csv.
SweepLayers SweepOneSpeed(const std::filesystem::path& out, const core::AcupunctureParams& defaults,
                          double speed_mm_s) {
  AcupunctureScene scene(defaults);
  const double v = 1e-3 * speed_mm_s;
  std::ofstream curve(out / ("force_depth_" + std::to_string(static_cast<int>(speed_mm_s)) + "mm_s.csv"));
  curve << "depth_mm,force_N,pressing_layer\n";
  SweepLayers l;
  for (double z = kStart_m; z > -kMaxDepth_m; z -= v * kDt_s) {
    core::ToolInput tool;
    tool.valid = true;
    tool.tip_W_m = Eigen::Vector3d(0, 0, z);
    tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, -v);
    const int before = scene.PuncturedLayers();
    scene.Step(tool, kDt_s);
    const int layer = scene.Pressing() ? scene.PuncturedLayers() : -1;
    const double f = scene.ToolForce_W_N().norm();
    if (layer >= 0 && layer < 3) {
      ++l.ticks[static_cast<std::size_t>(layer)];
      l.peak[static_cast<std::size_t>(layer)] = std::max(l.peak[static_cast<std::size_t>(layer)], f);
    }
    for (int i = before; i < scene.PuncturedLayers() && i < 3; ++i) {
      // From where its surface was when pressing began (its top, or
      // deeper if the layer above carried it down).
      l.indentation[static_cast<std::size_t>(i)] = -z + scene.NetState(i).n1_rest_W_m.z();
      l.pierced[static_cast<std::size_t>(i)] = true;
    }
    char line[96];
    std::snprintf(line, sizeof line, "%.5f,%.6e,%d\n", -1e3 * z, f, layer);
    curve << line;
  }
  return l;
}

std::vector<SweepRow> SpeedSweep(const std::filesystem::path& out) {
  std::vector<SweepRow> rows;
  const core::AcupunctureParams defaults;
  for (const double speed_mm_s : {2.0, 5.0, 10.0, 20.0}) {
    const SweepLayers l = SweepOneSpeed(out, defaults, speed_mm_s);
    for (int i = 0; i < 3; ++i)
      rows.push_back({speed_mm_s, i,
                      l.pierced[static_cast<std::size_t>(i)] ? 1e3 * l.indentation[static_cast<std::size_t>(i)] : -1.0,
                      l.peak[static_cast<std::size_t>(i)], l.ticks[static_cast<std::size_t>(i)]});
  }
  std::ofstream csv(out / "speed_sweep.csv");
  csv << "speed_mm_s,layer,name,indentation_at_puncture_mm,peak_force_N,contact_ticks\n";
  for (const auto& r : rows) {
    char line[160];
    std::snprintf(line, sizeof line, "%.0f,%d,%s,%.4f,%.4f,%d\n", r.speed_mm_s, r.layer,
                  defaults.layers[static_cast<std::size_t>(r.layer)].name.c_str(), r.indentation_mm, r.peak_N,
                  r.contact_ticks);
    csv << line;
  }
  return rows;
}

// The scene's default shaft law (stick-slip Coulomb friction plus a tenth of
// Table 1's damping; docs/validation.md#shaft-friction): straight down from
// 2 mm above the skin to 30 mm at 10 mm/s, held 0.3 s, out to 20 mm, back in
// to 25 mm. One row per tick (check_puncture.py simulates the law on its
// own from these poses); returns the shaft force [N] as the tip reaches
// 30 mm.
// One tick of the shaft-law run: the needle at tip_z_m moving at v_z_m_per_s,
// one CSV row.
void ShaftLawTick(AcupunctureScene& scene, std::ofstream& csv, double& t, double tip_z_m, double v_z_m_per_s) {
  core::ToolInput tool;
  tool.valid = true;
  tool.tip_W_m = Eigen::Vector3d(0, 0, tip_z_m);
  tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, v_z_m_per_s);
  scene.Step(tool, kDt_s);
  t += kDt_s;
  const int punctured = scene.PuncturedLayers();
  const bool pressing = scene.Status().current_layer == punctured;
  char line[200];
  std::snprintf(line, sizeof line, "%.3f,%.17g,%.17g,%d,%d,%.17g\n", t, tip_z_m, v_z_m_per_s, punctured,
                pressing ? 1 : 0, scene.ToolForce_W_N().z());
  csv << line;
}

double DefaultShaftLaw(const std::filesystem::path& out) {
  AcupunctureScene scene{core::AcupunctureParams{}};
  std::ofstream csv(out / "shaft_friction_default.csv");
  csv << "t_s,tip_z_m,v_z_m_per_s,punctured,pressing,force_z_N\n";
  constexpr double kV_m_per_s = 10e-3;
  struct Leg {
    double to_z_m, v_m_per_s;
    int hold_ticks;
  };
  const Leg legs[] = {{-30e-3, kV_m_per_s, 0}, {-30e-3, 0.0, 300}, {-20e-3, kV_m_per_s, 0}, {-25e-3, kV_m_per_s, 0}};
  double z = kStart_m, t = 0.0, force_at_30_N = 0.0;
  for (const Leg& leg : legs) {
    if (leg.v_m_per_s == 0.0) {
      for (int k = 0; k < leg.hold_ticks; ++k) ShaftLawTick(scene, csv, t, z, 0.0);
      continue;
    }
    const double dir = leg.to_z_m > z ? 1.0 : -1.0;
    const int n = static_cast<int>(std::lround(std::abs(leg.to_z_m - z) / (leg.v_m_per_s * kDt_s)));
    const double from = z;
    for (int k = 1; k <= n; ++k) {
      z = from + (leg.to_z_m - from) * k / n;
      ShaftLawTick(scene, csv, t, z, dir * leg.v_m_per_s);
    }
    if (leg.to_z_m == -30e-3) force_at_30_N = std::abs(scene.ToolForce_W_N().z());
  }
  return force_at_30_N;
}

using PunctureLayers = decltype(core::AcupunctureParams::layers);

// The paper-model insertion and withdrawal, one sample per tick.
struct InsertionRun {
  std::vector<Sample> samples;
  std::vector<std::pair<double, double>> springback;  // (t since puncture, offset)
  std::vector<std::size_t> puncture_sample;           // index of the tick of each puncture
  std::vector<int> puncture_layer;
};

InsertionRun InsertAndWithdraw(AcupunctureScene& scene) {
  InsertionRun run;
  std::uint64_t events_seen = 0;
  double skin_puncture_t = -1.0;
  const int insert_steps = static_cast<int>(std::lround((kStart_m + kMaxDepth_m) / (kSpeed_m_per_s * kDt_s)));
  for (int k = 0; k <= 2 * insert_steps; ++k) {
    const bool inserting = k <= insert_steps;
    const double travelled_m = kSpeed_m_per_s * kDt_s * (inserting ? k : 2 * insert_steps - k);
    core::ToolInput tool;
    tool.valid = true;
    tool.tip_W_m = Eigen::Vector3d(0, 0, kStart_m - travelled_m);
    tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, inserting ? -kSpeed_m_per_s : kSpeed_m_per_s);
    scene.Step(tool, kDt_s);
    const auto events = scene.Events();
    for (std::uint64_t e = events_seen; e < scene.EventsTotal(); ++e) {
      const core::SceneEvent& ev = events[events.size() - (scene.EventsTotal() - e)];
      if (ev.kind != core::SceneEventKind::kPuncture) continue;
      run.puncture_sample.push_back(run.samples.size());
      run.puncture_layer.push_back(ev.layer);
      if (ev.layer == 0) skin_puncture_t = scene.SimTime_s();
    }
    events_seen = scene.EventsTotal();
    run.samples.push_back({scene.SimTime_s(), scene.Status().tip_depth_m, scene.ToolForce_W_N().z(),
                           scene.Status().current_layer, core::ToString(scene.ForceModel().state), inserting});
    if (skin_puncture_t >= 0.0 && static_cast<int>(run.springback.size()) <= kSpringbackSteps)
      run.springback.emplace_back(scene.SimTime_s() - skin_puncture_t, *scene.PuncturePointOffset_m(0));
  }
  return run;
}

// force_depth.csv and springback.csv.
void WriteInsertionCsvs(const std::filesystem::path& out, const InsertionRun& run) {
  {
    std::ofstream f(out / "force_depth.csv");
    f << "t_s,depth_mm,force_N,layer,state\n";
    for (const auto& s : run.samples) {
      char line[160];
      std::snprintf(line, sizeof line, "%.4f,%.6f,%.6e,%d,%s\n", s.t_s, 1e3 * s.depth_m, s.force_N, s.layer,
                    s.state.c_str());
      f << line;
    }
  }
  {
    std::ofstream f(out / "springback.csv");
    f << "t_s,offset_mm\n";
    for (const auto& [t, off] : run.springback) {
      char line[80];
      std::snprintf(line, sizeof line, "%.4f,%.6e\n", t, 1e3 * off);
      f << line;
    }
  }
}

// Walks back from the tick before the puncture while each earlier tick (of
// this layer, in contact) has no more force: *begin is where the rise
// starts; true if the force never fell from there to the puncture.
bool RisesMonotonicallyBeforePuncture(const std::vector<Sample>& samples, std::size_t puncture_tick, int layer,
                                      std::size_t* begin) {
  *begin = puncture_tick - 1;
  while (*begin > 0 && samples[*begin - 1].layer == layer && samples[*begin - 1].state != "free" &&
         samples[*begin - 1].force_N <= samples[*begin].force_N + 1e-15)
    --*begin;
  bool monotone = true;
  for (std::size_t k = *begin + 1; k < puncture_tick; ++k)
    monotone = monotone && samples[k].force_N >= samples[k - 1].force_N - 1e-15;
  return monotone;
}

// Monotone rise from first contact with layer i's surface to its puncture.
Check CheckRiseBeforePuncture(const InsertionRun& run, std::size_t i, const std::string& name) {
  const Sample& at = run.samples[run.puncture_sample[i] - 1];  // last tick before the puncture tick
  std::size_t begin = 0;
  const bool monotone =
      RisesMonotonicallyBeforePuncture(run.samples, run.puncture_sample[i], static_cast<int>(i), &begin);
  const bool rose_over_contact = run.samples[begin].force_N < at.force_N;
  return {name + " force rises monotonically before puncture", monotone && rose_over_contact,
          "over " + std::to_string(run.puncture_sample[i] - begin) + " ticks"};
}

// What the layers above layer i leave for it: the top of its undisturbed
// surface, their Table 1 shaft damping, and how deep the one above was pierced.
struct LayersAbove {
  double top_m = 0.0, shaft_b = 0.0, previous_m = 0.0;
};

// Layer i's row of punctures.csv and its checks.
void CheckLayerPuncture(const AcupunctureScene& scene, const InsertionRun& run, std::size_t i, const LayersAbove& above,
                        std::ofstream& pf, std::vector<Check>* checks) {
  const auto& layers = scene.Params().layers;
  const core::ForceNetModel& net = scene.Net(static_cast<int>(i));
  // The tip its net's puncture depth below N1 along the surface normal at
  // the site (the fitted surface tilts a few degrees there; the needle
  // moves along -z). N1 is the layer's top, or deeper if the layer above
  // carried it down.
  const core::ForceNetState& placed = scene.NetState(static_cast<int>(i));
  const double expected_depth_m =
      (net.puncture_depth_m - placed.n1_rest_W_m.dot(placed.normal_W)) / placed.normal_W.z();
  const bool n1_where_expected = std::abs(-placed.n1_rest_W_m.z() - std::max(above.top_m, above.previous_m)) <= 6e-6;
  const double expected_peak_N = net.def.puncture_force_N + above.shaft_b * kSpeed_m_per_s;
  const double slope_N_per_m = core::NetStiffnessAtDepth_N_per_m(net, net.puncture_depth_m);
  const Sample& at = run.samples[run.puncture_sample[i] - 1];  // last tick before the puncture tick
  const Sample& after = run.samples[run.puncture_sample[i]];
  const double step_m = kSpeed_m_per_s * kDt_s;
  char row[200];
  std::snprintf(row, sizeof row, "%zu,%s,%.6f,%.6f,%.6f,%.6f,%.6f\n", i, layers[i].name.c_str(), 1e3 * after.depth_m,
                1e3 * expected_depth_m, at.force_N, expected_peak_N, after.force_N);
  pf << row;
  const std::string name = layers[i].name;
  checks->push_back({name + " punctures where its pressing began + its net's puncture depth (within one 5 um tick)",
                     n1_where_expected && std::abs(after.depth_m - expected_depth_m) <= step_m + 1e-9,
                     "depth " + std::to_string(1e3 * after.depth_m) + " mm, expected " +
                         std::to_string(1e3 * expected_depth_m) + " mm"});
  checks->push_back({name + " peak force = its puncture force + shaft damping (within one tick of rise)",
                     std::abs(at.force_N - expected_peak_N) <= slope_N_per_m * step_m + 1e-9,
                     std::to_string(at.force_N) + " N vs " + std::to_string(expected_peak_N) + " N"});
  checks->push_back({name + " force drops at puncture", after.force_N < at.force_N,
                     std::to_string(at.force_N) + " -> " + std::to_string(after.force_N) + " N"});
  checks->push_back(CheckRiseBeforePuncture(run, i, name));
  if (i == 0)
    checks->push_back({"skin peak puncture force within 0.1-2 N (van Gerwen 2012)",
                       at.force_N > 0.1 && at.force_N < 2.0, std::to_string(at.force_N) + " N"});
}

// Expected puncture depth of layer i: where its pressing started (its top,
// or deeper if the layer above carried it down) plus its net's puncture
// depth; expected peak force: the layer's puncture force plus the Table 1
// damping of the layers above. Writes punctures.csv.
void CheckPunctures(const std::filesystem::path& out, const AcupunctureScene& scene, const InsertionRun& run,
                    std::vector<Check>* checks) {
  std::ofstream pf(out / "punctures.csv");
  pf << "layer,name,depth_mm,expected_depth_mm,peak_force_N,expected_peak_force_N,force_after_N\n";
  bool order_ok = run.puncture_layer.size() == 3;
  for (std::size_t i = 0; i < run.puncture_layer.size(); ++i)
    order_ok = order_ok && run.puncture_layer[i] == static_cast<int>(i);
  checks->push_back({"three punctures, skin then fat then muscle", order_ok,
                     std::to_string(run.puncture_layer.size()) + " puncture events"});
  LayersAbove above;
  const auto& layers = scene.Params().layers;
  for (std::size_t i = 0; i < run.puncture_layer.size() && i < 3; ++i) {
    CheckLayerPuncture(scene, run, i, above, pf, checks);
    above.previous_m = run.samples[run.puncture_sample[i]].depth_m;
    above.shaft_b += layers[i].damping_Ns_per_m2 * layers[i].thickness_m;
    above.top_m += layers[i].thickness_m;
  }
}

// Withdrawal: shaft friction only, F = -(sum d h) v, pulling the needle in.
void CheckWithdrawal(const PunctureLayers& layers, const std::vector<Sample>& samples, std::vector<Check>* checks) {
  double worst_withdraw_N = 0.0;
  bool withdraw_negative = true;
  for (const auto& s : samples) {
    if (s.inserting || s.depth_m <= 0.0) continue;
    double b = 0.0, top = 0.0;
    for (const auto& l : layers) {
      b += l.damping_Ns_per_m2 * std::clamp(s.depth_m - top, 0.0, l.thickness_m);
      top += l.thickness_m;
    }
    worst_withdraw_N = std::max(worst_withdraw_N, std::abs(s.force_N + b * kSpeed_m_per_s));
    withdraw_negative = withdraw_negative && s.force_N <= 0.0;
  }
  checks->push_back({"withdrawal gives shaft friction only: F = -(sum d_i h_i) v",
                     worst_withdraw_N < 1e-9 && withdraw_negative,
                     "max deviation " + std::to_string(worst_withdraw_N) + " N"});
}

// Every layer's surface springs back above its reference line (paper
// Fig. 6), and the needle ends free.
void CheckSpringback(const AcupunctureScene& scene, const InsertionRun& run, std::vector<Check>* checks) {
  const auto& layers = scene.Params().layers;
  const double final_offset = run.springback.empty() ? -1.0 : run.springback.back().second;
  checks->push_back({"skin springs back above the tip reference line", final_offset > 0.0,
                     "final offset " + std::to_string(1e3 * final_offset) + " mm"});
  for (int i = 1; i < 3; ++i) {
    const auto off = scene.PuncturePointOffset_m(i);
    checks->push_back({layers[static_cast<std::size_t>(i)].name + " springs back above the tip reference line",
                       off && *off > 0.0,
                       off ? "final offset " + std::to_string(1e3 * *off) + " mm" : "not punctured"});
  }
  checks->push_back(
      {"back to free once the tip leaves the skin", run.samples.back().state == "free", run.samples.back().state});
}

// Each layer's tabulated net (for check_puncture.py's independent solve):
// depth, tip force, mean inward deflection of every ring.
void WriteNetTables(const std::filesystem::path& out, const AcupunctureScene& scene) {
  std::ofstream t(out / "net_tables.csv");
  t << "layer,depth_mm,force_N,ring,Z_mm\n";
  for (int i = 0; i < 3; ++i) {
    const core::ForceNetModel& net = scene.Net(i);
    const auto& first = net.topology.ring_first_node;
    for (std::size_t k = 0; k < net.force_N.size(); ++k) {
      for (int j = 0; j < net.def.rings_w; ++j) {
        const auto b = first[static_cast<std::size_t>(j)], e = first[static_cast<std::size_t>(j + 1)];
        const double z = -net.displacement_T_m[k].row(2).segment(b, e - b).mean();
        char line[160];
        std::snprintf(line, sizeof line, "%d,%.6f,%.12e,%d,%.12e\n", i,
                      1e3 * static_cast<double>(k) * net.def.table_step_m, net.force_N[k], j + 1, 1e3 * z);
        t << line;
      }
    }
  }
}

// Shaft friction of the order we target (1e-2 N per mm inserted),
// so it is felt between punctures: 0.005-0.05 N/mm at 30 mm, 10 mm/s.
void CheckDefaultShaftFriction(const std::filesystem::path& out, std::vector<Check>* checks) {
  const double shaft_30_N = DefaultShaftLaw(out);
  const double shaft_per_mm = shaft_30_N / 30.0;
  checks->push_back({"default shaft friction at 30 mm, 10 mm/s is of order 1e-2 N per mm (0.005-0.05)",
                     shaft_per_mm >= 0.005 && shaft_per_mm <= 0.05,
                     std::to_string(shaft_30_N) + " N = " + std::to_string(shaft_per_mm) + " N/mm"});
}

// The speed sweep against the force net's design targets.
void CheckSpeedSweep(const std::vector<SweepRow>& sweep, std::vector<Check>* checks) {
  bool skin_ok = true, clamp_ok = true, fat_ok = false;
  double skin_lo = 1e9, skin_hi = 0.0, worst_peak = 0.0;
  int fat_ticks_10 = 0;
  for (const auto& r : sweep) {
    if (r.layer == 0) {
      skin_ok = skin_ok && r.indentation_mm >= 2.0 && r.indentation_mm <= 6.0;
      skin_lo = std::min(skin_lo, r.indentation_mm), skin_hi = std::max(skin_hi, r.indentation_mm);
    }
    if (r.layer == 1 && r.speed_mm_s == 10.0) fat_ticks_10 = r.contact_ticks, fat_ok = r.contact_ticks >= 20;
    clamp_ok = clamp_ok && r.peak_N < 2.5;
    worst_peak = std::max(worst_peak, r.peak_N);
  }
  checks->push_back({"skin indents 2-6 mm before it gives way, at 2-20 mm/s", skin_ok,
                     std::to_string(skin_lo) + " - " + std::to_string(skin_hi) + " mm"});
  checks->push_back(
      {"the fat's contact lasts >= 20 ticks at 10 mm/s", fat_ok, std::to_string(fat_ticks_10) + " ticks"});
  checks->push_back({"every layer's peak stays below the bridge's 2.5 N clamp, at 2-20 mm/s", clamp_ok,
                     "highest " + std::to_string(worst_peak) + " N"});
}

// summary.md and stdout: the checks, then the speed sweep's table; true if
// every check holds.
bool ReportPunctureChecks(const std::filesystem::path& out, const std::vector<Check>& checks,
                          const std::vector<SweepRow>& sweep, const PunctureLayers& layers) {
  bool all = true;
  std::ofstream md(out / "summary.md");
  md << "# puncture validation\n\nInsertion at " << 1e3 * kSpeed_m_per_s << " mm/s to " << 1e3 * kMaxDepth_m
     << " mm depth and back, 1 kHz.\n\n| claim | ok | detail |\n|---|---|---|\n";
  for (const auto& c : checks) {
    md << "| " << c.claim << " | " << (c.ok ? "yes" : "**NO**") << " | " << c.detail << " |\n";
    std::printf("%-70s %s  %s\n", c.claim.c_str(), c.ok ? "ok  " : "FAIL", c.detail.c_str());
    all = all && c.ok;
  }
  md << "\n## Speed sweep (default scene)\n\n"
        "| speed | layer | indentation at puncture | peak force | contact ticks |\n|---|---|---|---|---|\n";
  std::printf("\nspeed sweep (default scene): speed, layer, indentation at puncture, peak force, contact ticks\n");
  for (const auto& r : sweep) {
    char line[200];
    std::snprintf(line, sizeof line, "| %.0f mm/s | %s | %.3f mm | %.3f N | %d |\n", r.speed_mm_s,
                  layers[static_cast<std::size_t>(r.layer)].name.c_str(), r.indentation_mm, r.peak_N, r.contact_ticks);
    md << line;
    std::printf("  %s", line);
  }
  md << "\nTargets (the force net's design): skin indentation 2-6 mm, fat contact >= 20 ticks at 10 mm/s, every peak < "
        "2.5 N.\n";
  return all;
}

int Run(const std::filesystem::path& out) {
  // The paper's model: Table 1's viscous shaft damping alone (law 0); the
  // scene's default stick-slip friction is an extension (checked by tests).
  core::AcupunctureParams paper;
  paper.shaft_friction_law = 0;
  AcupunctureScene scene(paper);
  const InsertionRun run = InsertAndWithdraw(scene);
  WriteInsertionCsvs(out, run);
  std::vector<Check> checks;
  CheckPunctures(out, scene, run, &checks);
  CheckWithdrawal(scene.Params().layers, run.samples, &checks);
  CheckSpringback(scene, run, &checks);
  WriteNetTables(out, scene);
  CheckDefaultShaftFriction(out, &checks);
  const std::vector<SweepRow> sweep = SpeedSweep(out);
  CheckSpeedSweep(sweep, &checks);
  return ReportPunctureChecks(out, checks, sweep, scene.Params().layers) ? 0 : 1;
}

}  // namespace

HAPSIM_VALIDATE_COMMAND("puncture", "acupuncture needle insertion: force-depth curve, layered punctures, springback", &Run);

}  // namespace hapsim::validate
