#include "hapsim/core/scenes/vessel/vessel_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "hapsim/core/cutting/cylinder_collision.h"
#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/scenes/scene_builders.h"
#include "hapsim/core/scenes/vessel/skin_indentation.h"

namespace hapsim::core {
namespace {

// A tool farther than this from the origin is a bad reading, not a pose.
constexpr double kToolRange_m = 1.0;
constexpr double kMinRenderStiffness_N_per_m = 10.0;
// At a light touch the probe's contact comes and goes between ticks (the
// wall is pushed just clear, then springs back up to ~11 ticks later on the
// vein with a +-3 um tremor). Contact ends only after this many ticks
// without force; meanwhile the device keeps the last contact
// plane (fixed in space), so it renders the surface, not a buzz.
constexpr int kContactEndTicks = 30;
// The skin and subcutis as an incompressible solid (skin_indentation.h).
constexpr double kTissuePoissonRatio = 0.5;
// The settled curve: samples per curve, and how a sample settles (the
// force changes by less than this fraction over a window of ticks).
constexpr int kCurveSamples = 25;
constexpr double kSettledFraction = 2e-3;
constexpr int kSettleWindowTicks = 20, kMaxSettleTicks = 400;
// Ticks to press from one of the curve's depths to the next: a slow press
// (5 mm/s on the vein; friction makes the curve depend on the path: 1 and
// 5 mm/s give the same curve within 1 %, 20 mm/s 8 % stiffer at 1.6 mm).
constexpr int kCurvePressTicks = 20;
// Damping while measuring the curve [1/s]: settles in fewer ticks; 50 and
// 200 give the same curve within 2 %.
constexpr double kCurveDamping_per_s = 50.0;
// Settling the wall under the lumen pressure at build: until the largest
// displacement changes by less than this fraction over a window.
constexpr int kMaxInflateTicks = 5000;
constexpr double kInflateSettledFraction = 1e-5;

// Largest angular frequency of a node under the meshless forces, from the
// diagonal stiffness block (each node's own gradient term and the terms of
// the neighbours whose F it enters), doubled for the coupling (a Gershgorin
// style margin). The explicit step is stable below 2 / omega.
double MaxMeshlessOmega_rad_per_s(const MeshlessModel& m) {
  const double modulus = m.lambda_Pa + 2.0 * m.mu_Pa;  // P-wave modulus bounds the stress per unit strain
  std::vector<double> diag(static_cast<std::size_t>(m.n), 0.0);
  for (std::int32_t i = 0; i < m.n; ++i) {
    diag[static_cast<std::size_t>(i)] += m.volume_m3[i] * m.gradient_self.col(i).squaredNorm();
    for (std::int32_t k = m.first[static_cast<std::size_t>(i)]; k < m.first[static_cast<std::size_t>(i) + 1]; ++k) {
      diag[static_cast<std::size_t>(m.neighbour[static_cast<std::size_t>(k)])] +=
          m.volume_m3[i] * m.gradient_weight.col(k).squaredNorm();
    }
  }
  double omega2 = 0.0;
  for (std::int32_t i = 0; i < m.n; ++i) {
    if (m.fixed[static_cast<std::size_t>(i)]) continue;
    omega2 = std::max(omega2, 2.0 * modulus * diag[static_cast<std::size_t>(i)] * m.inv_mass_per_kg[i]);
  }
  return std::sqrt(omega2);
}

// Node (k, l, a) of the wall's lattice: station k, layer l, angle a (mod ring).
std::int32_t VesselLatticeNode(const VesselGeometry& g, int k, int l, int a) {
  return static_cast<std::int32_t>((k * g.layers + l) * g.ring + (a % g.ring));
}

// The same bound for springs (Gershgorin: |K_ii| + sum |K_ij| <= 2 sum k).
double MaxSpringOmega_rad_per_s(const MeshlessModel& m, const std::vector<DistanceConstraint>& springs) {
  std::vector<double> k_sum(static_cast<std::size_t>(m.n), 0.0);
  for (const DistanceConstraint& s : springs) {
    k_sum[static_cast<std::size_t>(s.i)] += 1.0 / s.compliance_m_per_N;
    k_sum[static_cast<std::size_t>(s.j)] += 1.0 / s.compliance_m_per_N;
  }
  double omega2 = 0.0;
  for (std::int32_t i = 0; i < m.n; ++i) {
    if (!m.fixed[static_cast<std::size_t>(i)]) omega2 = std::max(omega2, 2.0 * k_sum[static_cast<std::size_t>(i)] * m.inv_mass_per_kg[i]);
  }
  return std::sqrt(omega2);
}

}  // namespace

VesselScene::VesselScene(const VesselParams& params)
    : params_(params), geometry_(GenerateVessel(VesselGeometryFor(params))) {
  const VesselGeometryDef def = VesselGeometryFor(params_);
  const double spacing_m = def.node_spacing_m;
  const double support_radius_m = params_.support_radius_factor * spacing_m;
  BuildMeshlessWall(support_radius_m);
  kind_ = static_cast<VesselModel>(params_.model);
  outer_radius_m_ = def.lumen_radius_m + def.wall_thickness_m;
  skin_on_ = params_.skin == 1 || (params_.skin == -1 && def.shape == VesselShape::kStraight);
  skin_top_z_m_ = geometry_.nodes_m.row(2).maxCoeff();
  std::vector<DistanceConstraint> stretch;
  BuildLattice(spacing_m, stretch);
  BuildFoundation(def);
  ScaleMassesForStability();
  BuildWallStep(std::move(stretch));
  SizeStepScratch(spacing_m);
  bed_z_m_ = geometry_.nodes_m.row(2).minCoeff();
  probe_floor_z_m_ = bed_z_m_ + params_.probe_radius_m + 2.0 * def.wall_thickness_m;
  BuildDisplay(support_radius_m);
  outputs_.status.layer_names = {"vessel_wall"};
  OrientLumenPressure();
  Inflate();
  MeasureSettledCurve();  // ~0.4 s for the vein
  sleep_allowed_ = params_.rest_speed_m_per_s > 0.0;
  Reset();
  // The build's own press and reset are not the session's.
  outputs_.events = EventLog();
  outputs_.status.numerical_resets = 0;
  outputs_.reset_epoch = ResetEpoch::Now(*this);
}

// The wall's meshless model: the generated nodes, their volumes and masses,
// the material.
void VesselScene::BuildMeshlessWall(double support_radius_m) {
  MeshlessDef m;
  m.x0_m = geometry_.nodes_m;
  m.volume_m3 = geometry_.node_volume_m3;
  for (const double v : geometry_.node_volume_m3) m.mass_kg.push_back(params_.density_kg_per_m3 * v);
  m.fixed = geometry_.anchored;
  m.support_radius_m = support_radius_m;
  m.youngs_modulus_Pa = params_.youngs_modulus_Pa;
  m.poisson_ratio = params_.poisson_ratio;
  m.damping_per_s = params_.damping_per_s;
  model_ = BuildMeshlessModel(m);
}

// Mass scaling: the critical step grows with the square root of the mass.
// Plain PBD has no explicit forces, but its contact force is the
// multiplier that moves the nodes (inertia over h^2): it takes the
// meshless model's masses so the three force curves compare.
void VesselScene::ScaleMassesForStability() {
  const double h_s = 1e-3 / params_.substeps;  // the session's 1 kHz tick
  const double omega = kind_ == VesselModel::kMassSpring ? MaxSpringOmega_rad_per_s(model_, springs_)
                                                         : MaxMeshlessOmega_rad_per_s(model_);
  const double real_critical_s = 2.0 / omega;
  mass_scale_ =
      params_.mass_scale > 0.0 ? params_.mass_scale : std::max(1.0, pmath::Pow(2.0 * h_s / real_critical_s, 2));
  model_.mass_kg *= mass_scale_;
  model_.inv_mass_per_kg /= mass_scale_;
  const double critical_s = real_critical_s * std::sqrt(mass_scale_);
  if (h_s > 0.9 * critical_s) {
    std::ostringstream msg;
    msg << "vessel: a physics step of " << h_s * 1e3 << " ms (1 ms / 'substeps') is unstable for the elastic forces "
        << "of this wall: the estimated critical step is " << critical_s * 1e3
        << " ms (raise 'substeps' or 'mass_scale', or lower 'youngs_modulus_Pa')";
    throw std::invalid_argument(msg.str());
  }
}

// The step is StepXpbd's: the wall's nodes with the scaled masses, and
// the distance constraints of the model (the paper's stretching
// constraints, or the plain-PBD baseline's springs). Independent
// constraints side by side: the sweeps overlap their work.
void VesselScene::BuildWallStep(std::vector<DistanceConstraint> stretch) {
  XpbdDef wall;
  wall.x0_m = geometry_.nodes_m;
  wall.mass_kg.assign(model_.mass_kg.data(), model_.mass_kg.data() + model_.n);
  wall.fixed = geometry_.anchored;
  wall.iterations = params_.xpbd_iterations;
  wall.damping_per_s = params_.damping_per_s;
  if (kind_ == VesselModel::kMeshlessXpbd) wall.distance = std::move(stretch);
  if (kind_ == VesselModel::kPlainPbd) wall.distance = springs_, wall.plain_pbd_stiffness = params_.pbd_stiffness;
  OrderByColour(wall.distance, model_.n);
  wall_model_ = BuildXpbdModel(wall);
  wall_ = MakeXpbdState(wall_model_);
}

// Everything a step writes, sized once so the step never allocates: the
// multipliers, the contact broad phase over the rest positions, the
// deformation gradients.
void VesselScene::SizeStepScratch(double spacing_m) {
  tet_lambda_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tets_.size()));
  tether_lambda_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tether_node_.size()));
  Eigen::AlignedBox3d box(geometry_.nodes_m.rowwise().minCoeff(), geometry_.nodes_m.rowwise().maxCoeff());
  rest_grid_ = UniformGrid(box, std::max(spacing_m, params_.probe_radius_m), static_cast<std::size_t>(model_.n));
  rest_grid_.Build(geometry_.nodes_m);
  candidates_.reserve(static_cast<std::size_t>(model_.n));
  contact_lambda_.assign(static_cast<std::size_t>(model_.n), 0.0);
  F_.assign(static_cast<std::size_t>(model_.n), Eigen::Matrix3d::Identity());
}

// The displayed surface: the MLS map from the nodes, and its never-edited topology.
void VesselScene::BuildDisplay(double support_radius_m) {
  surface_map_ = BuildMlsSurfaceMap(geometry_.nodes_m, geometry_.surface_m, support_radius_m);
  surface_m_ = geometry_.surface_m;
  topology_ = MeshTopology({.vertex_capacity = static_cast<std::uint32_t>(geometry_.surface_m.cols()),
                            .triangle_capacity = static_cast<std::uint32_t>(geometry_.triangles.size()),
                            .part_names = {"vessel_wall", "lumen"},
                            .log_capacity = 0});  // never edited
  for (Eigen::Index v = 0; v < geometry_.surface_m.cols(); ++v) topology_.AddVertex();
  for (std::size_t t = 0; t < geometry_.triangles.size(); ++t) {
    const auto& tri = geometry_.triangles[t];
    topology_.AddTriangle(tri[0], tri[1], tri[2], geometry_.triangle_part[t]);
  }
  topology_.Seal();
}

// Which way the inner wall's tangent cross product points: out of the lumen
// at a middle-station node (AddLumenPressure).
void VesselScene::OrientLumenPressure() {
  const int k = geometry_.stations / 2, L = geometry_.layers, R = geometry_.ring;
  auto at = [&](int kk, int a) { return geometry_.nodes_m.col((kk * L) * R + ((a + R) % R)); };
  const Eigen::Vector3d n = (at(k, 1) - at(k, R - 1)).cross(at(k + 1, 0) - at(k - 1, 0));
  lumen_outward_sign_ = n.dot(at(k, 0) - geometry_.centreline_m.col(k)) >= 0.0 ? 1.0 : -1.0;
}

void VesselScene::BuildLattice(double spacing_m, std::vector<DistanceConstraint>& stretch) {
  BuildLatticeTets(spacing_m);
  // Lattice edges (axial, around, across) and, for the baselines, the
  // diagonals of every lattice face (shear).
  const int S = geometry_.stations, L = geometry_.layers, R = geometry_.ring;
  auto node = [&](int k, int l, int a) { return VesselLatticeNode(geometry_, k, l, a); };
  auto rest = [&](std::int32_t i, std::int32_t j) { return (geometry_.nodes_m.col(i) - geometry_.nodes_m.col(j)).norm(); };
  const double k_stretch = params_.stretch_fraction * params_.youngs_modulus_Pa * spacing_m;
  auto diagonal = [&](std::int32_t i, std::int32_t j) {  // baselines only
    if (kind_ != VesselModel::kMeshlessXpbd) {
      springs_.push_back({i, j, rest(i, j), 1.0 / (params_.youngs_modulus_Pa * rest(i, j))});
    }
  };
  auto edge = [&](std::int32_t i, std::int32_t j) {  // stretching constraint, or a baseline spring
    if (kind_ == VesselModel::kMeshlessXpbd && k_stretch > 0.0) stretch.push_back({i, j, rest(i, j), 1.0 / k_stretch});
    diagonal(i, j);
  };
  for (int k = 0; k < S; ++k)
    for (int l = 0; l < L; ++l)
      for (int a = 0; a < R; ++a) {
        if (k + 1 < S) edge(node(k, l, a), node(k + 1, l, a));
        edge(node(k, l, a), node(k, l, a + 1));
        if (l + 1 < L) edge(node(k, l, a), node(k, l + 1, a));
        if (k + 1 < S) diagonal(node(k, l, a), node(k + 1, l, a + 1)), diagonal(node(k, l, a + 1), node(k + 1, l, a));
        if (l + 1 < L) diagonal(node(k, l, a), node(k, l + 1, a + 1)), diagonal(node(k, l, a + 1), node(k, l + 1, a));
        if (k + 1 < S && l + 1 < L) diagonal(node(k, l, a), node(k + 1, l + 1, a)), diagonal(node(k, l + 1, a), node(k + 1, l, a));
      }
}

// The paper's energy constraints (meshless_xpbd only): six tetrahedra per
// lattice cell around its main diagonal (Kuhn), corner c = bits (station,
// layer, angle).
void VesselScene::BuildLatticeTets(double spacing_m) {
  const double k_tet = params_.tet_fraction * params_.youngs_modulus_Pa * spacing_m;
  if (kind_ != VesselModel::kMeshlessXpbd || !(k_tet > 0.0)) return;
  constexpr int kKuhn[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (int k = 0; k + 1 < geometry_.stations; ++k)
    for (int l = 0; l + 1 < geometry_.layers; ++l)
      for (int a = 0; a < geometry_.ring; ++a) {
        auto corner = [&](int bits) {
          return VesselLatticeNode(geometry_, k + (bits & 1), l + ((bits >> 1) & 1), a + ((bits >> 2) & 1));
        };
        for (const auto& t : kKuhn) {
          tets_.push_back(
              MakeTetEnergyConstraint(geometry_.nodes_m, {corner(0), corner(t[0]), corner(t[1]), corner(7)}, k_tet));
        }
      }
}

void VesselScene::BuildFoundation(const VesselGeometryDef& def) {
  if (params_.tissue_modulus_Pa <= 0.0) return;
  // Node (k, outer layer, a) carries the outer surface between its
  // neighbours: (2 pi r_out / ring) around x (its station's share of the
  // centreline) along.
  const int S = geometry_.stations, L = geometry_.layers, R = geometry_.ring;
  const double depth_m = params_.tissue_depth_m > 0.0 ? params_.tissue_depth_m : outer_radius_m_;
  const double around_m = 2.0 * std::numbers::pi * (def.lumen_radius_m + def.wall_thickness_m) / R;
  for (int k = 0; k < S; ++k) {
    const auto c = [&](int j) { return geometry_.centreline_m.col(std::clamp(j, 0, S - 1)); };
    const double along_m = 0.5 * ((c(k + 1) - c(k)).norm() + (c(k) - c(k - 1)).norm());
    const double k_N_per_m = params_.tissue_modulus_Pa * around_m * along_m / depth_m;
    for (int a = 0; a < R; ++a) {
      const auto i = static_cast<std::int32_t>((k * L + (L - 1)) * R + a);
      if (geometry_.anchored[static_cast<std::size_t>(i)]) continue;
      tether_node_.push_back(i);
      tether_compliance_m_per_N_.push_back(1.0 / k_N_per_m);
    }
  }
}

double VesselScene::DepthIntoRestWall_m(const Eigen::Vector3d& tip_W_m) const {
  // Distance from the tip to the centreline polyline, nearest segment.
  const Eigen::Matrix3Xd& c = geometry_.centreline_m;
  double nearest_m = std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k + 1 < c.cols(); ++k) {
    const Eigen::Vector3d d = c.col(k + 1) - c.col(k);
    const double t = std::clamp((tip_W_m - c.col(k)).dot(d) / d.squaredNorm(), 0.0, 1.0);
    nearest_m = std::min(nearest_m, (tip_W_m - c.col(k) - t * d).norm());
  }
  return outer_radius_m_ + params_.probe_radius_m - nearest_m;
}

void VesselScene::VesselConstraints::BeginStep() {
  VesselScene& v = scene_;
  v.tet_lambda_.setZero();
  v.tether_lambda_.setZero();
  for (const std::uint32_t i : v.candidates_) v.contact_lambda_[i] = 0.0;
}

void VesselScene::VesselConstraints::Project(Eigen::Matrix3Xd& x_m, const Eigen::VectorXd& inv_mass_per_kg,
                                             double h_s) {
  VesselScene& v = scene_;
  const double inv_h2 = 1.0 / (h_s * h_s);
  for (std::size_t t = 0; t < v.tets_.size(); ++t) {
    ProjectTetEnergyXpbd(x_m, v.tets_[t], inv_mass_per_kg, h_s, &v.tet_lambda_[static_cast<Eigen::Index>(t)]);
  }
  // The foundation: each outer node held at its rest position by a spring.
  for (std::size_t t = 0; t < v.tether_node_.size(); ++t) {
    const std::int32_t i = v.tether_node_[t];
    ProjectDistanceXpbd(x_m, i, v.geometry_.nodes_m.col(i), inv_mass_per_kg[i], 0.0, 0.0,
                        v.tether_compliance_m_per_N_[t] * inv_h2, &v.tether_lambda_[static_cast<Eigen::Index>(t)],
                        false, nullptr);
  }
  // The tip: each node pushed out of the probe sphere, then held against
  // sliding on it by Coulomb friction — the node's slip relative to the tip
  // over this step is undone up to mu times the normal correction (static
  // within it, kinetic past it).
  const double contact_alpha_tilde = inv_h2 / v.params_.contact_stiffness_N_per_m;
  const Eigen::Vector3d tip_moved_m = v.tip_W_m_ - v.tip_at_step_start_W_m_;
  for (const std::uint32_t i : v.candidates_) {
    double& lambda = v.contact_lambda_[i];
    ProjectDistanceXpbd(x_m, static_cast<std::int32_t>(i), v.tip_W_m_, inv_mass_per_kg[i], 0.0,
                        v.params_.probe_radius_m, contact_alpha_tilde, &lambda, true, nullptr);
    if (lambda <= 0.0 || v.params_.contact_friction <= 0.0) continue;
    const Eigen::Vector3d out = x_m.col(i) - v.tip_W_m_;
    const double length = out.norm();
    if (length < 1e-15) continue;
    const Eigen::Vector3d n = out / length;
    const Eigen::Vector3d slip = (x_m.col(i) - v.wall_.x_start_m.col(i)) - tip_moved_m;
    const Eigen::Vector3d slip_t = slip - slip.dot(n) * n;
    const double slip_m = slip_t.norm();
    const double limit_m = v.params_.contact_friction * inv_mass_per_kg[i] * lambda;  // mu x the normal correction
    if (slip_m > 0.0) x_m.col(i) -= std::min(1.0, limit_m / slip_m) * slip_t;
  }
  // The bed: a rigid, frictionless plane under the vessel.
  for (Eigen::Index i = 0; i < x_m.cols(); ++i) x_m(2, i) = std::max(x_m(2, i), v.bed_z_m_);
}

bool VesselScene::Advance(bool tool_ok, double h_s) {
  FindContactCandidates(tool_ok, MaxDisplacement_m(wall_.x_m, geometry_.nodes_m, {}, model_.n));
  // 1. Elastic forces as the step's external forces, and the lumen's pressure.
  ComputeElasticForces();
  AddLumenPressure();
  // 2-3. Prediction, the sweeps (the model's constraints, then this scene's), velocities.
  VesselConstraints extra(*this);
  StepXpbd(wall_model_, wall_, h_s, &extra);
  // The contact force on the tool; the blow-up guard.
  SumToolContactForce(h_s);
  const WallMotion motion = MeasureWallMotion();
  time_s_ += h_s;
  if (!(std::isfinite(motion.kinetic_J) && motion.kinetic_J <= params_.max_kinetic_energy_J)) return false;
  CountQuietStep(motion);
  return true;
}

// A step is quiet when every node moved slower than rest_speed_m_per_s and
// the tip either stood still or touched nothing: the next step would then
// move the wall by less than that as well, as long as the tip does not
// move within reach.
void VesselScene::CountQuietStep(const WallMotion& motion) {
  if (!sleep_allowed_) return;
  const bool tip_moved = tip_W_m_ != tip_at_step_start_W_m_;
  const bool quiet =
      motion.max_speed_m_per_s < params_.rest_speed_m_per_s && (!tip_moved || outputs_.tool_force_W_N.isZero(0.0));
  quiet_steps_ = quiet ? quiet_steps_ + 1 : 0;
  if (quiet_steps_ >= kQuietStepsToSleep) FallAsleep();
}

// The wall stands still from here (velocities zero, like a resting node),
// and keeps the contact force of its last step.
void VesselScene::FallAsleep() {
  asleep_ = true;
  quiet_steps_ = 0;
  wall_.v_m_per_s.setZero();
  sleep_tip_W_m_ = tip_W_m_;
  sleep_contact_force_W_N_ = outputs_.tool_force_W_N;
  sleep_max_displacement_m_ = MaxDisplacement_m(wall_.x_m, geometry_.nodes_m, {}, model_.n);
}

// Asleep in a contact, the wall wakes when the tip moves or the tool is
// lost (the contact changes); asleep without one, when the probe sphere
// reaches a node (the step would push it out).
bool VesselScene::StaysAsleep(bool tool_ok) {
  if (AsleepInContact()) return tool_ok && tip_W_m_ == sleep_tip_W_m_;
  FindContactCandidates(tool_ok, sleep_max_displacement_m_);
  const double r2 = params_.probe_radius_m * params_.probe_radius_m;
  for (const std::uint32_t i : candidates_) {
    if ((wall_.x_m.col(i) - tip_W_m_).squaredNorm() < r2) return false;
  }
  return true;
}

// Contact candidates: nodes whose rest position is within the probe radius
// plus the largest displacement of any node (so none currently inside is missed).
void VesselScene::FindContactCandidates(bool tool_ok, double max_displacement_m) {
  candidates_.clear();
  if (!tool_ok) return;
  const double reach_m = params_.probe_radius_m + max_displacement_m;
  rest_grid_.ForEachWithin(geometry_.nodes_m, tip_W_m_, reach_m, [&](std::uint32_t i) {
    if (!model_.fixed[i]) candidates_.push_back(i);
  });
}

// The meshless forces, or the mass-spring baseline's springs (plain PBD has
// none), into wall_.f_ext_N; their strain energy.
void VesselScene::ComputeElasticForces() {
  if (kind_ == VesselModel::kMeshlessXpbd) {
    strain_energy_J_ = ComputeMeshlessForces(model_, wall_.x_m, F_, wall_.f_ext_N);
    return;
  }
  wall_.f_ext_N.setZero();
  strain_energy_J_ = 0.0;
  if (kind_ != VesselModel::kMassSpring) return;
  for (const DistanceConstraint& s : springs_) {
    const Eigen::Vector3d d = wall_.x_m.col(s.j) - wall_.x_m.col(s.i);
    const double length = d.norm();
    if (length < 1e-15) continue;
    const double stretch = length - s.rest_m;
    const Eigen::Vector3d f = (stretch / s.compliance_m_per_N / length) * d;
    wall_.f_ext_N.col(s.i) += f;
    wall_.f_ext_N.col(s.j) -= f;
    strain_energy_J_ += 0.5 * stretch * stretch / s.compliance_m_per_N;
  }
}

// Each contact's multiplier over h² along its node's push off the tip.
void VesselScene::SumToolContactForce(double h_s) {
  const double inv_h2 = 1.0 / (h_s * h_s);
  outputs_.tool_force_W_N.setZero();
  for (const std::uint32_t i : candidates_) {
    if (contact_lambda_[i] <= 0.0) continue;
    const Eigen::Vector3d out = wall_.x_m.col(i) - tip_W_m_;
    const double length = out.norm();
    if (length > 0.0) outputs_.tool_force_W_N -= contact_lambda_[i] * inv_h2 * out / length;
  }
}

VesselScene::WallMotion VesselScene::MeasureWallMotion() const {
  double kinetic_J = 0.0, max_speed2 = 0.0;
  for (std::int32_t i = 0; i < model_.n; ++i) {
    const double speed2 = wall_.v_m_per_s.col(i).squaredNorm();
    kinetic_J += 0.5 * model_.mass_kg[i] * speed2;
    max_speed2 = std::max(max_speed2, speed2);
  }
  return {kinetic_J, std::sqrt(max_speed2)};
}

void VesselScene::Step(const ToolInput& tool, double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) return;
  const bool tool_ok = tool.valid && tool.tip_W_m.allFinite() && tool.tip_W_m.norm() < kToolRange_m;
  if (tool_ok && !tip_placed_) tip_W_m_ = tool.tip_W_m, tip_placed_ = true;

  const double h_s = dt_s / params_.substeps;
  bool stepped = false;
  for (int k = 0; k < params_.substeps; ++k) {
    tip_at_step_start_W_m_ = tip_W_m_;
    if (tool_ok) {  // toward the device's tip, at most kMaxTipTravelPerStep_m
      const Eigen::Vector3d to_device = tool.tip_W_m - tip_W_m_;
      const double gap_m = to_device.norm();
      tip_W_m_ += gap_m > kMaxTipTravelPerStep_m ? (kMaxTipTravelPerStep_m / gap_m) * to_device : to_device;
      // What lies under the vessel stops the probe where the flattened
      // vessel's two walls lie on it: deeper, the wall would have to pass
      // through the sphere (it did: the probe ended in the lumen).
      tip_W_m_.z() = std::max(tip_W_m_.z(), probe_floor_z_m_);
    }
    if (asleep_ && StaysAsleep(tool_ok)) {
      time_s_ += h_s;
      continue;
    }
    asleep_ = false;
    stepped = true;
    if (!Advance(tool_ok, h_s)) {
      RecoverFromBlowup();
      break;
    }
  }
  surface_stale_ = surface_stale_ || stepped;
  if (asleep_) outputs_.tool_force_W_N = sleep_contact_force_W_N_;
  UpdateOutputs(tool, tool_ok);
}

const Eigen::Matrix3Xd& VesselScene::Vertices_m() const {
  if (surface_stale_) MapSurface(surface_map_, wall_.x_m, surface_m_);
  surface_stale_ = false;
  return surface_m_;
}

double VesselScene::SkinForce_N(const Eigen::Vector3d& tip_W_m) const {
  if (!skin_on_) return 0.0;
  const double depth_m = skin_top_z_m_ - (tip_W_m.z() - params_.probe_radius_m);
  return SkinIndentationForce_N(depth_m, params_.probe_radius_m, params_.tissue_modulus_Pa, kTissuePoissonRatio);
}

void VesselScene::UpdateOutputs(const ToolInput& tool, bool tool_ok) {
  if (tool_ok) outputs_.tool_force_W_N.z() += SkinForce_N(tip_W_m_);
  const double force_N = outputs_.tool_force_W_N.norm();
  const bool touching = tool_ok && force_N > 0.0;
  ticks_without_force_ = touching ? 0 : ticks_without_force_ + 1;
  const bool in_contact = touching || (tool_ok && was_in_contact_ && ticks_without_force_ < kContactEndTicks);
  const double depth_m = tool_ok ? DepthIntoRestWall_m(tip_W_m_) : 0.0;
  outputs_.status.tip_depth_m = std::max(0.0, depth_m);
  if (!touching && in_contact) return;  // grace period: keep the last contact plane and the events quiet
  outputs_.force_model = LocalForceModel{};
  if (in_contact) {
    // The device renders a plane through the physics' tip along the force,
    // as stiff as the settled wall at this depth: k (anchor - tip)·n = F.
    const Eigen::Vector3d n = outputs_.tool_force_W_N / force_N;  // the wall pushes the tool out along n
    // The curve is the crest's; off it the wall is stiffer at the same
    // depth, so the slope is read where the crest's curve carries this
    // force (0.6 mm off the crest: within 16 % of the local slope, 19 %
    // read at the same depth; docs/validation.md#vessel).
    const double at_m = settled_curve_.DepthAtForce_m(force_N);
    const double stiffness = std::min(settled_curve_.SlopeAt_N_per_m(at_m, kMinRenderStiffness_N_per_m),
                                      params_.render_stiffness_max_N_per_m);
    outputs_.force_model.state = ContactState::kContact;
    outputs_.force_model.normal_W = n;
    outputs_.force_model.stiffness_N_per_m = stiffness;
    outputs_.force_model.anchor_W_m = tip_W_m_ + (force_N / stiffness) * n;
  } else {
    outputs_.tool_force_W_N.setZero();
  }
  outputs_.status.current_layer = in_contact ? 0 : -1;
  if (in_contact != was_in_contact_) {
    outputs_.events.Push({time_s_, in_contact ? SceneEventKind::kContactBegin : SceneEventKind::kContactEnd, 0,
                          tool_ok ? tool.tip_W_m : Eigen::Vector3d::Zero()});
    was_in_contact_ = in_contact;
  }
}

void VesselScene::AddLumenPressure() {
  if (params_.lumen_pressure_Pa <= 0.0) return;
  // Inner-layer node (k, 0, a): its share of the lumen's surface, oriented
  // out of the lumen, is a quarter of the cross product of the tangents
  // spanning its neighbours (around a-1 -> a+1, along k-1 -> k+1).
  const int S = geometry_.stations, L = geometry_.layers, R = geometry_.ring;
  const Eigen::Matrix3Xd& x = wall_.x_m;
  auto node = [&](int k, int a) { return static_cast<Eigen::Index>((k * L) * R + ((a + R) % R)); };
  const double scale = 0.25 * params_.lumen_pressure_Pa * lumen_outward_sign_;
  for (int k = 1; k + 1 < S; ++k) {
    for (int a = 0; a < R; ++a) {
      const Eigen::Index i = node(k, a);
      if (model_.fixed[static_cast<std::size_t>(i)]) continue;
      const Eigen::Vector3d around = x.col(node(k, a + 1)) - x.col(node(k, a - 1));
      const Eigen::Vector3d along = x.col(node(k + 1, a)) - x.col(node(k - 1, a));
      wall_.f_ext_N.col(i) += scale * around.cross(along);
    }
  }
}

void VesselScene::Inflate() {
  // Settle the wall under the lumen pressure alone (damped as for the
  // curve), and keep that state as the scene's rest state.
  inflated_m_ = geometry_.nodes_m;
  wall_.x_m = inflated_m_;
  if (params_.lumen_pressure_Pa > 0.0) {
    const double damping = wall_model_.damping_per_s;
    wall_model_.damping_per_s = std::max(damping, kCurveDamping_per_s);
    ToolInput none;
    double before = 0.0;
    for (int tick = 0; tick < kMaxInflateTicks; ++tick) {
      Step(none, 1e-3);
      if (tick % kSettleWindowTicks != kSettleWindowTicks - 1) continue;
      const double moved = MaxDisplacement_m(wall_.x_m, geometry_.nodes_m, {}, model_.n);
      if (std::abs(moved - before) <= kInflateSettledFraction * moved) break;
      before = moved;
    }
    wall_model_.damping_per_s = damping;
    inflated_m_ = wall_.x_m;
  }
  wall_.v_m_per_s.setZero();
}

void VesselScene::MeasureSettledCurve() {
  // Press the middle station's crest from above, slowly, to each depth and
  // hold it there until the force settles. The wall's damping is raised
  // meanwhile (statics do not depend on it; it only shortens the settling).
  const Eigen::Vector3d crest =
      geometry_.centreline_m.col(geometry_.stations / 2) + Eigen::Vector3d(0.0, 0.0, outer_radius_m_);
  const double max_depth_m = 1.5 * outer_radius_m_;  // three quarters of the outer diameter
  settled_curve_.step_m = max_depth_m / kCurveSamples;
  settled_curve_.force_N.assign(1, 0.0);
  const double damping = wall_model_.damping_per_s;
  wall_model_.damping_per_s = std::max(damping, kCurveDamping_per_s);
  ToolInput tool;
  tool.valid = true;
  for (int k = 1; k <= kCurveSamples; ++k) {
    const double depth_m = k * settled_curve_.step_m;
    const Eigen::Vector3d target = crest + Eigen::Vector3d(0.0, 0.0, params_.probe_radius_m - depth_m);
    for (int tick = 1; k > 1 && tick < kCurvePressTicks; ++tick) {  // press down to it
      tool.tip_W_m.z() -= settled_curve_.step_m / kCurvePressTicks;
      Step(tool, 1e-3);
    }
    tool.tip_W_m = target;
    double before = 0.0, now = 0.0;
    for (int tick = 0; tick < kMaxSettleTicks; ++tick) {
      Step(tool, 1e-3);
      now = outputs_.tool_force_W_N.z();
      if (tick % kSettleWindowTicks != kSettleWindowTicks - 1) continue;
      if (tip_W_m_ == tool.tip_W_m && std::abs(now - before) <= kSettledFraction * std::abs(now)) break;
      before = now;
    }
    settled_curve_.force_N.push_back(std::max(0.0, now));
  }
  wall_model_.damping_per_s = damping;
}

void VesselScene::RecoverFromBlowup() {
  wall_.x_m = inflated_m_;  // same sizes: copies, no allocation
  wall_.v_m_per_s.setZero();
  asleep_ = false;
  quiet_steps_ = 0;
  outputs_.tool_force_W_N.setZero();
  LogNumericalReset(time_s_);
}

void VesselScene::Reset() {
  wall_.x_m = inflated_m_;
  wall_.v_m_per_s.setZero();
  tip_W_m_.setZero();
  tip_at_step_start_W_m_.setZero();
  tip_placed_ = false;
  time_s_ = 0.0;
  was_in_contact_ = false;
  ticks_without_force_ = 0;
  asleep_ = false;
  quiet_steps_ = 0;
  strain_energy_J_ = 0.0;
  surface_stale_ = true;  // the inflated wall's
  FinishReset();
}

std::uint64_t VesselScene::StateHash() const {
  StateHasher h;
  AddCommonSceneState(h, *this, outputs_.reset_epoch);
  // The surface is a function of the nodes; λ and the candidates are per-step scratch.
  h.Add(wall_.x_m).Add(wall_.v_m_per_s).Add(tip_W_m_).Add(tip_placed_).Add(was_in_contact_).Add(ticks_without_force_);
  h.Add(asleep_).Add(quiet_steps_);
  if (asleep_)
    h.Add(AsleepInContact()).Add(sleep_tip_W_m_).Add(sleep_contact_force_W_N_).Add(sleep_max_displacement_m_);
  return h.Value();
}

std::unique_ptr<Scene> MakeVesselScene(const std::map<std::string, double>& params) {
  return std::make_unique<VesselScene>(ParseVesselParams(params));
}

}  // namespace hapsim::core
