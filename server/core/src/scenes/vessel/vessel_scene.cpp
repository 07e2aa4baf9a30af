#include "hapsim/core/scenes/vessel/vessel_scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "hapsim/core/cutting/cylinder_collision.h"
#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/scenes/scene_builders.h"

namespace hapsim::core {
namespace {

// A tool farther than this from the origin is a bad reading, not a pose.
constexpr double kToolRange_m = 1.0;
// Tip travel below this between ticks gives no tangent-stiffness sample
// (force noise over a tiny travel would swing the estimate).
constexpr double kMinTravelForStiffness_m = 1e-6;
// Weight of a new tangent-stiffness sample in the running estimate.
constexpr double kStiffnessSmoothing = 0.2;
constexpr double kMinRenderStiffness_N_per_m = 10.0;
// At a light touch the probe's contact comes and goes between ticks (the
// wall is pushed just clear, then springs back). Contact ends only after
// this many ticks without force; meanwhile the device keeps the last contact
// plane (fixed in space), so it renders the surface, not a buzz.
constexpr int kContactEndTicks = 10;

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
  MeshlessDef m;
  m.x0_m = geometry_.nodes_m;
  m.volume_m3 = geometry_.node_volume_m3;
  for (const double v : geometry_.node_volume_m3) m.mass_kg.push_back(params_.density_kg_per_m3 * v);
  m.fixed = geometry_.anchored;
  m.support_radius_m = params_.support_radius_factor * spacing_m;
  m.youngs_modulus_Pa = params_.youngs_modulus_Pa;
  m.poisson_ratio = params_.poisson_ratio;
  m.damping_per_s = params_.damping_per_s;
  model_ = BuildMeshlessModel(m);

  kind_ = static_cast<VesselModel>(params_.model);
  BuildLattice(spacing_m);
  // Independent constraints side by side: the sweeps overlap their work.
  OrderByColour(stretch_, model_.n);
  OrderByColour(springs_, model_.n);

  // Mass scaling: the critical step grows with the square root of the mass.
  // Plain PBD has no explicit forces, but its contact force is the
  // multiplier that moves the nodes (inertia over h^2): it takes the
  // meshless model's masses so the three force curves compare.
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

  tet_lambda_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tets_.size()));
  stretch_lambda_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(stretch_.size()));

  Eigen::AlignedBox3d box(geometry_.nodes_m.rowwise().minCoeff(), geometry_.nodes_m.rowwise().maxCoeff());
  rest_grid_ = UniformGrid(box, std::max(spacing_m, params_.probe_radius_m), static_cast<std::size_t>(model_.n));
  rest_grid_.Build(geometry_.nodes_m);
  candidates_.reserve(static_cast<std::size_t>(model_.n));
  contact_lambda_.assign(static_cast<std::size_t>(model_.n), 0.0);

  bed_z_m_ = geometry_.nodes_m.row(2).minCoeff();
  surface_map_ = BuildMlsSurfaceMap(geometry_.nodes_m, geometry_.surface_m, m.support_radius_m);
  x_m_ = geometry_.nodes_m;
  v_m_per_s_ = Eigen::Matrix3Xd::Zero(3, model_.n);
  x_start_m_ = x_m_;
  elastic_N_ = Eigen::Matrix3Xd::Zero(3, model_.n);
  F_.assign(static_cast<std::size_t>(model_.n), Eigen::Matrix3d::Identity());
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
  status_.layer_names = {"vessel_wall"};
}

void VesselScene::BuildLattice(double spacing_m) {
  // Lattice edges (axial, around, across) and, for the baselines, the
  // diagonals of every lattice face (shear).
  const int S = geometry_.stations, L = geometry_.layers, R = geometry_.ring;
  auto node = [&](int k, int l, int a) { return static_cast<std::int32_t>((k * L + l) * R + (a % R)); };
  auto rest = [&](std::int32_t i, std::int32_t j) { return (geometry_.nodes_m.col(i) - geometry_.nodes_m.col(j)).norm(); };
  const double k_stretch = params_.stretch_fraction * params_.youngs_modulus_Pa * spacing_m;
  auto diagonal = [&](std::int32_t i, std::int32_t j) {  // baselines only
    if (kind_ != VesselModel::kMeshlessXpbd) {
      springs_.push_back({i, j, rest(i, j), 1.0 / (params_.youngs_modulus_Pa * rest(i, j))});
    }
  };
  auto edge = [&](std::int32_t i, std::int32_t j) {  // stretching constraint, or a baseline spring
    if (kind_ == VesselModel::kMeshlessXpbd && k_stretch > 0.0) stretch_.push_back({i, j, rest(i, j), 1.0 / k_stretch});
    diagonal(i, j);
  };
  // Six tetrahedra per lattice cell around its main diagonal (Kuhn), corner
  // c = bits (station, layer, angle).
  const double k_tet = params_.tet_fraction * params_.youngs_modulus_Pa * spacing_m;
  if (kind_ == VesselModel::kMeshlessXpbd && k_tet > 0.0) {
    constexpr int kKuhn[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
    for (int k = 0; k + 1 < S; ++k)
      for (int l = 0; l + 1 < L; ++l)
        for (int a = 0; a < R; ++a) {
          auto corner = [&](int bits) { return node(k + (bits & 1), l + ((bits >> 1) & 1), a + ((bits >> 2) & 1)); };
          for (const auto& t : kKuhn) {
            tets_.push_back(MakeTetEnergyConstraint(geometry_.nodes_m, {corner(0), corner(t[0]), corner(t[1]), corner(7)}, k_tet));
          }
        }
  }
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

bool VesselScene::Advance(const ToolInput& tool, bool tool_ok, double h_s) {
  // Contact candidates: nodes whose rest position is within the probe radius
  // plus the largest displacement of any node (so none currently inside is missed).
  candidates_.clear();
  if (tool_ok) {
    const double reach_m = params_.probe_radius_m + MaxDisplacement_m(x_m_, geometry_.nodes_m, {}, model_.n);
    rest_grid_.ForEachWithin(geometry_.nodes_m, tool.tip_W_m, reach_m, [&](std::uint32_t i) {
      if (!model_.fixed[i]) candidates_.push_back(i);
    });
  }
  for (const std::uint32_t i : candidates_) contact_lambda_[i] = 0.0;

  // 1. Elastic forces (meshless, or the mass-spring baseline's springs; plain
  // PBD has none), explicit prediction.
  if (kind_ == VesselModel::kMeshlessXpbd) {
    strain_energy_J_ = ComputeMeshlessForces(model_, x_m_, F_, elastic_N_);
  } else {
    elastic_N_.setZero();
    strain_energy_J_ = 0.0;
    if (kind_ == VesselModel::kMassSpring) {
      for (const DistanceConstraint& s : springs_) {
        const Eigen::Vector3d d = x_m_.col(s.j) - x_m_.col(s.i);
        const double length = d.norm();
        if (length < 1e-15) continue;
        const double stretch = length - s.rest_m;
        const Eigen::Vector3d f = (stretch / s.compliance_m_per_N / length) * d;
        elastic_N_.col(s.i) += f;
        elastic_N_.col(s.j) -= f;
        strain_energy_J_ += 0.5 * stretch * stretch / s.compliance_m_per_N;
      }
    }
  }
  x_start_m_ = x_m_;
  const double decay = std::max(0.0, 1.0 - params_.damping_per_s * h_s);
  for (std::int32_t i = 0; i < model_.n; ++i) {
    if (model_.fixed[static_cast<std::size_t>(i)]) continue;
    v_m_per_s_.col(i) = decay * v_m_per_s_.col(i) + h_s * model_.inv_mass_per_kg[i] * elastic_N_.col(i);
    x_m_.col(i) += h_s * v_m_per_s_.col(i);
  }
  // 2. Constraint sweeps: stretching, then the tip's contact.
  stretch_lambda_.setZero();
  tet_lambda_.setZero();
  const double inv_h2 = 1.0 / (h_s * h_s);
  const double contact_alpha_tilde = inv_h2 / params_.contact_stiffness_N_per_m;
  for (int it = 0; it < params_.xpbd_iterations; ++it) {
    for (std::size_t c = 0; c < stretch_.size(); ++c) {
      const DistanceConstraint& d = stretch_[c];
      Eigen::Vector3d move_j = Eigen::Vector3d::Zero();
      ProjectDistanceXpbd(x_m_, d.i, x_m_.col(d.j), model_.inv_mass_per_kg[d.i], model_.inv_mass_per_kg[d.j],
                          d.rest_m, d.compliance_m_per_N * inv_h2, &stretch_lambda_[static_cast<Eigen::Index>(c)],
                          false, &move_j);
      x_m_.col(d.j) += move_j;
    }
    for (std::size_t t = 0; t < tets_.size(); ++t) {
      ProjectTetEnergyXpbd(x_m_, tets_[t], model_.inv_mass_per_kg, h_s, &tet_lambda_[static_cast<Eigen::Index>(t)]);
    }
    if (kind_ == VesselModel::kPlainPbd) {  // the paper's projection, scaled by k, no multiplier
      for (const DistanceConstraint& s : springs_) {
        ProjectDistancePlainPbd(x_m_, s.i, s.j, model_.inv_mass_per_kg[s.i], model_.inv_mass_per_kg[s.j], s.rest_m,
                                params_.pbd_stiffness);
      }
    }
    for (const std::uint32_t i : candidates_) {
      ProjectDistanceXpbd(x_m_, static_cast<std::int32_t>(i), tool.tip_W_m, model_.inv_mass_per_kg[i], 0.0,
                          params_.probe_radius_m, contact_alpha_tilde, &contact_lambda_[i], true, nullptr);
    }
    // The bed: a rigid, frictionless plane under the vessel (the tissue it lies on).
    for (std::int32_t i = 0; i < model_.n; ++i) x_m_(2, i) = std::max(x_m_(2, i), bed_z_m_);
  }
  // 3. Velocities; the contact force on the tool; the blow-up guard.
  double kinetic_J = 0.0;
  for (std::int32_t i = 0; i < model_.n; ++i) {
    v_m_per_s_.col(i) = (x_m_.col(i) - x_start_m_.col(i)) / h_s;
    kinetic_J += 0.5 * model_.mass_kg[i] * v_m_per_s_.col(i).squaredNorm();
  }
  tool_force_W_N_.setZero();
  for (const std::uint32_t i : candidates_) {
    if (contact_lambda_[i] <= 0.0) continue;
    const Eigen::Vector3d out = x_m_.col(i) - tool.tip_W_m;
    const double length = out.norm();
    if (length > 0.0) tool_force_W_N_ -= contact_lambda_[i] * inv_h2 * out / length;
  }
  time_s_ += h_s;
  return std::isfinite(kinetic_J) && kinetic_J <= params_.max_kinetic_energy_J;
}

void VesselScene::Step(const ToolInput& tool, double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) return;
  const bool tool_ok = tool.valid && tool.tip_W_m.allFinite() && tool.tip_W_m.norm() < kToolRange_m;
  const double h_s = dt_s / params_.substeps;
  for (int k = 0; k < params_.substeps; ++k) {
    if (!Advance(tool, tool_ok, h_s)) {
      RecoverFromBlowup();
      break;
    }
  }
  MapSurface(surface_map_, x_m_, surface_m_);
  UpdateOutputs(tool, tool_ok);
}

void VesselScene::UpdateOutputs(const ToolInput& tool, bool tool_ok) {
  const double force_N = tool_force_W_N_.norm();
  const bool touching = tool_ok && force_N > 0.0;
  ticks_without_force_ = touching ? 0 : ticks_without_force_ + 1;
  const bool in_contact = touching || (tool_ok && was_in_contact_ && ticks_without_force_ < kContactEndTicks);
  if (!touching && in_contact) {
    // Grace period: keep the last contact plane and the events quiet.
    tool_force_W_N_.setZero();
    last_tip_W_m_ = tool.tip_W_m;
    last_force_N_ = 0.0;
    status_.tip_depth_m = std::max(0.0, -tool.tip_W_m.z());
    return;
  }
  force_model_ = LocalForceModel{};
  if (in_contact) {
    const Eigen::Vector3d n = tool_force_W_N_ / force_N;  // the wall pushes the tool out along n
    if (!was_in_contact_) {
      // First touch: no travel yet; start from the contact's own stiffness
      // in series with an equally stiff wall, then learn the wall's.
      render_stiffness_N_per_m_ = 0.5 * params_.contact_stiffness_N_per_m;
    } else {
      const double travel_m = (last_tip_W_m_ - tool.tip_W_m).dot(n);  // into the wall: > 0
      if (std::abs(travel_m) > kMinTravelForStiffness_m) {
        const double tangent = (force_N - last_force_N_) / travel_m;
        if (tangent > 0.0) {
          render_stiffness_N_per_m_ += kStiffnessSmoothing * (tangent - render_stiffness_N_per_m_);
        }
      }
    }
    render_stiffness_N_per_m_ = std::clamp(render_stiffness_N_per_m_, kMinRenderStiffness_N_per_m,
                                           params_.render_stiffness_max_N_per_m);
    force_model_.state = ContactState::kContact;
    force_model_.normal_W = n;
    force_model_.stiffness_N_per_m = render_stiffness_N_per_m_;
    // Anchor such that k (anchor - tip)·n = F at the current tip.
    force_model_.anchor_W_m = tool.tip_W_m + (force_N / render_stiffness_N_per_m_) * n;
  } else {
    tool_force_W_N_.setZero();
  }
  last_tip_W_m_ = tool_ok ? tool.tip_W_m : Eigen::Vector3d::Zero();
  last_force_N_ = in_contact ? force_N : 0.0;
  status_.tip_depth_m = tool_ok ? std::max(0.0, -tool.tip_W_m.z()) : 0.0;
  status_.current_layer = in_contact ? 0 : -1;
  if (in_contact != was_in_contact_) {
    events_.Push({time_s_, in_contact ? SceneEventKind::kContactBegin : SceneEventKind::kContactEnd, 0,
                  tool_ok ? tool.tip_W_m : Eigen::Vector3d::Zero()});
    was_in_contact_ = in_contact;
  }
}

void VesselScene::RecoverFromBlowup() {
  x_m_ = geometry_.nodes_m;  // same sizes: copies, no allocation
  v_m_per_s_.setZero();
  tool_force_W_N_.setZero();
  ++status_.numerical_resets;
  events_.Push({time_s_, SceneEventKind::kReset, -1, Eigen::Vector3d::Zero()});
}

void VesselScene::Reset() {
  x_m_ = geometry_.nodes_m;
  v_m_per_s_.setZero();
  time_s_ = 0.0;
  was_in_contact_ = false;
  ticks_without_force_ = 0;
  render_stiffness_N_per_m_ = 0.0;
  last_tip_W_m_.setZero();
  last_force_N_ = 0.0;
  strain_energy_J_ = 0.0;
  surface_m_ = geometry_.surface_m;
  tool_force_W_N_.setZero();
  force_model_ = LocalForceModel{};
  status_.current_layer = -1;
  status_.tip_depth_m = 0.0;
  events_.Push({0.0, SceneEventKind::kReset, -1, Eigen::Vector3d::Zero()});
  reset_epoch_ = ResetEpoch::Now(*this);
}

std::uint64_t VesselScene::StateHash() const {
  StateHasher h;
  AddCommonSceneState(h, *this, reset_epoch_);
  // The surface is a function of x_m_; λ and the candidates are per-step scratch.
  h.Add(x_m_).Add(v_m_per_s_).Add(was_in_contact_).Add(ticks_without_force_).Add(render_stiffness_N_per_m_).Add(last_tip_W_m_).Add(last_force_N_);
  return h.Value();
}

std::unique_ptr<Scene> MakeVesselScene(const std::map<std::string, double>& params) {
  return std::make_unique<VesselScene>(ParseVesselParams(params));
}

}  // namespace hapsim::core
