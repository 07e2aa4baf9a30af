// The cutting scene: contact, the cut state machine and haptics. The skin
// and the three-stage cut live in core/cutting/.
#include "hapsim/core/scenes/cutting/cutting_scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "hapsim/core/msm/stability.h"
#include "hapsim/core/scenes/scene_builders.h"

namespace hapsim::core {

namespace {

constexpr double kSubstep_s = 1e-3;     // the largest step; a longer tick sub-steps
constexpr int kMaxSubsteps = 10;
constexpr int kMaxCommitsPerStep = 4;   // bounds a step's cost if the blade jumps far
constexpr double kParkedTipZ_m = 0.05;  // where the blade is drawn while there is no tool
const IntegratorChoice kIntegrator{IntegratorKind::kSymplecticEuler, 0.5};

bool CuttingToolUsable(const ToolInput& t) {
  return t.valid && t.tip_W_m.allFinite() && t.orientation_W.coeffs().allFinite() && t.velocity_W_m_per_s.allFinite();
}

void LimitCuttingToolSpeed(ToolInput& tool) {
  const double speed = tool.velocity_W_m_per_s.norm();
  if (speed > kMaxToolSpeed_m_per_s) tool.velocity_W_m_per_s *= kMaxToolSpeed_m_per_s / speed;
}

// The skin patch of these parameters. One material: the lattice is the
// membrane of E and t (nu = 1/3), and it carries the residual stress
// sigma_r = E eps_r as a uniform pre-stress.
SkinDef CuttingSkinDef(const CuttingParams& p) {
  SkinDef d;
  d.length_m = p.patch_length_m;
  d.width_m = p.patch_width_m;
  d.spacing_m = p.spacing_m;
  d.spring_k_N_per_m = LatticeSpringStiffness_N_per_m(p.youngs_modulus_Pa, p.skin_thickness_m);
  d.bending_k_N_per_m = 0.25 * d.spring_k_N_per_m;
  d.prestrain = LatticePrestrainForStress(p.youngs_modulus_Pa * p.residual_strain, p.youngs_modulus_Pa);
  d.node_damping_Ns_per_m = p.damping_Ns_per_m;
  d.areal_density_kg_per_m2 = p.node_mass_kg / (p.spacing_m * p.spacing_m);
  d.min_node_mass_kg = 0.25 * p.node_mass_kg;  // a sliver of area must not make a node stiff for its mass
  d.anchor_k_N_per_m = p.anchor_stiffness_N_per_m;
  d.extra_parts = {"blade"};
  return d;
}

}  // namespace

CuttingScene::CuttingScene(const CuttingParams& p) : params_(p) {
  const SkinDef d = CuttingSkinDef(p);
  skin_ = BuildSkinMesh(d);
  AddBladeToMesh();
  CheckStepIsStable(d.min_node_mass_kg);
  skin_.model.max_kinetic_energy_J = p.max_kinetic_energy_J;
  initial_model_ = skin_.model;
  initial_state_ = skin_.state;
  initial_on_lip_ = skin_.on_lip;
  workspace_ = MakeMsmWorkspace(skin_.model);
  resting_ = RestingNodes(skin_.model, RestConfig{.force_N = p.rest_force_N, .speed_m_per_s = p.rest_speed_m_per_s});
  cutter_ = SkinCutter(skin_);
  cut_config_.sweep_radius_m = p.sweep_radius_m;
  cut_config_.wound_anchor_k_N_per_m = p.anchor_stiffness_N_per_m;
  curve_ =
      IncisionCurve(static_cast<std::size_t>(4.0 * (p.patch_length_m + p.patch_width_m) / p.segment_length_m) + 64);
  const Eigen::Vector3d margin(0.01, 0.01, 0.005);  // nodes farther out are clamped into border cells
  skin_box_ = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5 * p.patch_length_m, -0.5 * p.patch_width_m, 0.0) - margin,
                                  Eigen::Vector3d(0.5 * p.patch_length_m, 0.5 * p.patch_width_m, 0.0) + margin);
  rest_grid_ = UniformGrid(skin_box_, std::max(2.0 * p.blade_radius_m, 2.0 * p.spacing_m),
                           static_cast<std::size_t>(skin_.model.num_nodes));
  colliding_.reserve(static_cast<std::size_t>(skin_.model.num_nodes));
  loaded_nodes_.reserve(static_cast<std::size_t>(skin_.model.num_nodes));
  outputs_.status.layer_names = {"skin"};
}

// The blade: eight fixed slots (dormant MSM nodes, which nothing moves but
// UpdateBladeMesh) and twelve triangles, drawn parked; then the mesh as
// built is sealed (what Reset() returns to).
void CuttingScene::AddBladeToMesh() {
  MeshTopology& topo = skin_.topology;
  for (auto& slot : blade_slots_) slot = topo.AddVertex();
  const auto& b = blade_slots_;
  constexpr std::uint16_t kBladePart = 2;
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t k1 = (k + 1) % 4;
    topo.AddTriangle(b[k], b[k1], b[4 + k1], kBladePart);
    topo.AddTriangle(b[k], b[4 + k1], b[4 + k], kBladePart);
  }
  topo.AddTriangle(b[0], b[2], b[1], kBladePart);
  topo.AddTriangle(b[0], b[3], b[2], kBladePart);
  topo.AddTriangle(b[4], b[5], b[6], kBladePart);
  topo.AddTriangle(b[4], b[6], b[7], kBladePart);
  ToolInput parked;
  UpdateBladeMesh(BladeOf(parked));
  topo.Seal();
}

// The explicit step must stay below the critical step with the contact and
// support springs on a node, for the lightest node too (the mass floor).
void CuttingScene::CheckStepIsStable(double min_node_mass_kg) const {
  const CuttingParams& p = params_;
  const double extra_k = p.contact_stiffness_N_per_m + p.support_stiffness_N_per_m;
  const double critical_s = CriticalTimeStep_s(EstimateModeBounds(skin_.model, extra_k, p.contact_damping_Ns_per_m), kIntegrator);
  MsmModel lightest = skin_.model;
  for (Eigen::Index i = 0; i < lightest.mass_kg.size(); ++i)
    lightest.mass_kg[i] = std::min(lightest.mass_kg[i], min_node_mass_kg);
  const double critical_light_s =
      CriticalTimeStep_s(EstimateModeBounds(lightest, extra_k, p.contact_damping_Ns_per_m), kIntegrator);
  if (!(kSubstep_s <= 0.9 * std::min(critical_s, critical_light_s))) {
    std::ostringstream msg;
    msg << "cutting: a 1 ms step is unstable for these parameters (critical step "
        << std::min(critical_s, critical_light_s)
        << " s): raise 'node_mass_kg' or lower 'youngs_modulus_Pa', 'contact_stiffness_N_per_m', "
           "'support_stiffness_N_per_m' or 'damping_Ns_per_m'";
    throw std::invalid_argument(msg.str());
  }
}

Cylinder CuttingScene::BladeOf(const ToolInput& tool) const {
  Cylinder c;
  c.radius_m = params_.blade_radius_m;
  if (!CuttingToolUsable(tool)) {
    c.p0_W_m = Eigen::Vector3d(0.0, 0.0, kParkedTipZ_m);
    c.p1_W_m = c.p0_W_m + params_.blade_length_m * Eigen::Vector3d::UnitZ();
    return c;
  }
  const Eigen::Vector3d up = (tool.orientation_W.normalized() * Eigen::Vector3d::UnitZ()).normalized();
  c.p0_W_m = tool.tip_W_m;
  c.p1_W_m = tool.tip_W_m + params_.blade_length_m * up;
  return c;
}

void CuttingScene::Step(const ToolInput& tool, double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  const int n = std::min(kMaxSubsteps, static_cast<int>(std::ceil(dt_s / kSubstep_s - 1e-9)));
  // Never a sub-step longer than the one the constructor checked for
  // stability: a tick beyond kMaxSubsteps ms simulates only that much.
  const double h_s = std::min(dt_s / n, kSubstep_s);
  for (int k = 0; k < n; ++k) StepOnce(tool, h_s);
}

void CuttingScene::StepOnce(const ToolInput& tool_in, double h_s) {
  ToolInput tool = tool_in;
  const bool usable = CuttingToolUsable(tool);
  if (usable) LimitCuttingToolSpeed(tool);
  const Cylinder blade = BladeOf(tool);
  UpdateBladeMesh(blade);
  HoldSkinOnTissue();
  ClearStepContact();
  if (usable) {
    FindNodesInBlade(blade);
    UpdateCut(tool, blade);
    ApplyContact(tool, blade);
  } else if (cutting_) {
    const Eigen::Vector2d end = curve_.LastPoint();
    EndCut(Eigen::Vector3d(end.x(), end.y(), 0.0));
  }
  const bool contact = usable && (cutting_ || !loaded_nodes_.empty());
  if (contact != in_contact_) {
    Log(contact ? SceneEventKind::kContactBegin : SceneEventKind::kContactEnd, tool.tip_W_m);
    in_contact_ = contact;
  }
  ApplyResidualStress(skin_, ResidualStress_Pa(), params_.skin_thickness_m);
  const StepReport r = StepSkin(h_s);
  if (!r.ok) {
    NumericalReset();
    return;
  }
  UpdateForceModel(tool);
  outputs_.status.current_layer = contact ? 0 : -1;
  outputs_.status.tip_depth_m = usable ? std::max(0.0, -tool.tip_W_m.z()) : 0.0;
}

// The skin's MSM step: every node, or (rest_force_N > 0) the awake ones —
// the loaded nodes, every node a cut left unbalanced, and the resting
// neighbours the last step pulled.
StepReport CuttingScene::StepSkin(double h_s) {
  if (params_.rest_force_N <= 0.0) return StepMsm(skin_.model, skin_.state, h_s, kIntegrator, workspace_);
  if (rest_checked_version_ != skin_.topology.Version()) {
    resting_.AfterTopologyEdit(skin_.model, skin_.state, cut_box_);
    rest_checked_version_ = skin_.topology.Version();
    recut_box_.extend(cut_box_);
    cut_box_.setEmpty();
  }
  for (const std::uint32_t v : loaded_nodes_) resting_.Wake(skin_.model, static_cast<std::int32_t>(v));
  const StepReport r = resting_.Step(skin_.model, skin_.state, h_s, kIntegrator, workspace_);
  for (const std::int32_t i : resting_.JustRested()) {  // where they stand from now on
    HoldNode(i);
    resting_shift_bound_m_ =
        std::max(resting_shift_bound_m_, (skin_.state.x_m.col(i) - skin_.model.x0_m.col(i)).norm());
  }
  return r;
}

std::int32_t CuttingScene::AwakeNodes() const {
  if (params_.rest_force_N > 0.0) return resting_.AwakeCount();
  std::int32_t n = 0;
  for (Eigen::Index i = 0; i < skin_.model.num_nodes; ++i) n += skin_.model.node_live[i] && !skin_.model.fixed[i];
  return n;
}

// The tissue underneath holds every node at its rest height (contact adds
// to it); in the plane, the skin's own tension balanced where it lies (hold_N).
// With resting skin only the step's region is refreshed: a resting node's
// hold changes only with its own position, refreshed when it came to rest,
// or with a cut, after which every node is (and the cut's box judged again).
void CuttingScene::HoldSkinOnTissue() {
  const bool resting = params_.rest_force_N > 0.0;
  if (resting && hold_version_ == skin_.topology.Version()) {
    for (const std::int32_t i : resting_.Region(skin_.model).touched_nodes) HoldNode(i);
    return;
  }
  const Eigen::Index n = skin_.state.f_ext_N.cols();
  for (Eigen::Index i = 0; i < n; ++i) HoldNode(i);
  hold_version_ = skin_.topology.Version();
  if (!resting) return;
  resting_.WakeUnbalancedIn(skin_.model, skin_.state, recut_box_);
  recut_box_.setEmpty();
  resting_shift_bound_m_ = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!resting_.Awake(static_cast<std::int32_t>(i)) && skin_.model.node_live[static_cast<std::size_t>(i)])
      resting_shift_bound_m_ =
          std::max(resting_shift_bound_m_, (skin_.state.x_m.col(i) - skin_.model.x0_m.col(i)).norm());
}

void CuttingScene::HoldNode(Eigen::Index i) {
  MsmState& st = skin_.state;
  st.f_ext_N(0, i) = skin_.hold_N(0, i);
  st.f_ext_N(1, i) = skin_.hold_N(1, i);
  st.f_ext_N(2, i) = -params_.support_stiffness_N_per_m * (st.x_m(2, i) - skin_.model.x0_m(2, i));
}

// The broad phase's query margin: the largest node displacement from rest —
// with resting skin, over the awake nodes and the resting ones' bound.
double CuttingScene::LargestShiftFromRest_m() {
  const MsmState& st = skin_.state;
  if (params_.rest_force_N <= 0.0) {
    const Eigen::Index used = std::min<Eigen::Index>(st.x_m.cols(), skin_.topology.Vertices().HighWater());
    return MaxDisplacement_m(st.x_m, skin_.model.x0_m, skin_.model.node_live, used);
  }
  double max2 = resting_shift_bound_m_ * resting_shift_bound_m_;
  for (const std::int32_t i : resting_.Region(skin_.model).active_nodes)  // the awake nodes
    max2 = std::max(max2, (st.x_m.col(i) - skin_.model.x0_m.col(i)).squaredNorm());
  return std::sqrt(max2);
}

// No contact yet this step: nothing loaded or colliding, no force on the tool.
void CuttingScene::ClearStepContact() {
  loaded_nodes_.clear();
  colliding_.clear();
  outputs_.tool_force_W_N.setZero();
  cut_normal_N_ = 0.0;
}

// Broad and narrow phase (colliding_): the rest grid, rebuilt after a cut,
// queried with the largest node displacement.
void CuttingScene::FindNodesInBlade(const Cylinder& blade) {
  if (!Bounds(blade).intersects(skin_box_)) return;
  const MsmState& st = skin_.state;
  if (rest_grid_version_ != skin_.topology.Version()) {
    rest_grid_.Build(skin_.model.x0_m, skin_.model.node_live);
    rest_grid_version_ = skin_.topology.Version();
  }
  CollideWithShiftedGrid(blade, st.x_m, rest_grid_, LargestShiftFromRest_m(), colliding_);
}

// Where the blade crosses the skin plane, if it does (tip below, blade not
// lying flat); the incision follows this point.
void CuttingScene::UpdateCut(const ToolInput& tool, const Cylinder& blade) {
  const Eigen::Vector3d up = (blade.p1_W_m - blade.p0_W_m).normalized();
  const double depth = -tool.tip_W_m.z();
  const bool crosses = up.z() > 0.2 && depth > 0.0;
  const Eigen::Vector3d q = crosses ? Eigen::Vector3d(tool.tip_W_m + (depth / up.z()) * up) : tool.tip_W_m;
  const bool on_patch =
      std::abs(q.x()) < 0.5 * params_.patch_length_m && std::abs(q.y()) < 0.5 * params_.patch_width_m;
  if (!cutting_) {
    if (crosses && on_patch && depth > params_.cut_depth_m) {
      cutting_ = true;
      curve_.Start(q.head<2>());
      Log(SceneEventKind::kCutStart, Eigen::Vector3d(q.x(), q.y(), 0.0));
    }
    return;
  }
  if (!crosses || !on_patch) {
    EndCut(Eigen::Vector3d(q.x(), q.y(), 0.0));
    return;
  }
  // One segment per segment_length of travel, in equal steps towards q.
  for (int k = 0; k < kMaxCommitsPerStep; ++k) {
    const Eigen::Vector2d from = curve_.LastPoint(), to = q.head<2>();
    const double gap = (to - from).norm();
    if (gap < params_.segment_length_m) break;
    if (!curve_.Extend(from + (to - from) * (params_.segment_length_m / gap))) break;  // the curve is full
    cut_totals_ += cutter_.CutAlongLastSegment(skin_, curve_, cut_config_);
    // Where the cut changed springs: the swept disc around the segment and
    // the nodes matched to it, well within two sweep radii and two spacings.
    const double reach = 2.0 * (params_.sweep_radius_m + params_.spacing_m);
    for (const Eigen::Vector2d& p : curve_.Controls(curve_.Segments() - 1)) {
      cut_box_.extend(Eigen::Vector3d(p.x() - reach, p.y() - reach, -reach));
      cut_box_.extend(Eigen::Vector3d(p.x() + reach, p.y() + reach, reach));
    }
  }
}

void CuttingScene::EndCut(const Eigen::Vector3d& where) {
  cutting_ = false;
  Log(SceneEventKind::kCutEnd, where, curve_.Length_m());
}

// Pressing: the tip on the skin surface (bilinear over the rest grid cell
// under the tip, while its four nodes are intact) pushes the tool up and the
// nodes down. Always: nodes inside the blade cylinder are pushed out from
// its axis (the paper: force from N along N -> p), the tool gets the reaction.
void CuttingScene::ApplyContact(const ToolInput& tool, const Cylinder& blade) {
  PushNodesOffBlade(blade);
  if (cutting_) {
    ResistCuttingDeeper(tool);
  } else {
    PressSkinUnderTip(tool);
  }
}

// While cutting, the blade's edge parts the skin ahead of it (the drag law
// is that resistance) and its sides push the wound's lips apart, across
// the incision and into their own tissue. The skin between the wound's
// last committed point and the blade is cut already (the mesh catches up
// at the next segment): pushing it, or pushing along the incision, would
// wedge and plough it, folding its triangles.
void CuttingScene::PushNodesOffBlade(const Cylinder& blade) {
  MsmState& st = skin_.state;
  const double k = params_.contact_stiffness_N_per_m;
  Eigen::Vector3d along = Eigen::Vector3d::Zero();
  if (cutting_ && curve_.Segments() > 0) {
    const Eigen::Vector2d t = curve_.Tangent(curve_.Segments());
    along = Eigen::Vector3d(t.x(), t.y(), 0.0);
  }
  for (const std::uint32_t v : colliding_) {
    if (cutting_ && !skin_.on_lip[v]) continue;
    const Eigen::Vector3d n = st.x_m.col(v), p = ClosestAxisPoint(blade, n);
    Eigen::Vector3d out = n - p;
    const double d = out.norm();
    if (!(d > 1e-12)) continue;
    out /= d;
    out -= out.dot(along) * along;
    // On the incision line the axis's side is a matter of rounding; a lip
    // pushed across the wound folds its triangles.
    if (cutting_) {
      const Eigen::Vector3d into = IntoTissue(v);
      if (out.dot(into) < 0.0) out -= 2.0 * out.dot(into) * into;
    }
    const Eigen::Vector3d f = k * (blade.radius_m - d) * out;
    st.f_ext_N.col(v) += f;
    outputs_.tool_force_W_N -= f;
    loaded_nodes_.push_back(v);
  }
}

// In the wound the blade has no skin surface under it; the tissue around
// and below it resists pressing deeper with the pressing law's stiffness
// from the rest surface z = 0 (so it is continuous with the press that
// started the cut), carried by the tissue underneath.
void CuttingScene::ResistCuttingDeeper(const ToolInput& tool) {
  const double depth_m = -tool.tip_W_m.z();
  if (depth_m > 0.0) {
    cut_normal_N_ = std::max(0.0, params_.contact_stiffness_N_per_m * depth_m -
                                      params_.contact_damping_Ns_per_m * tool.velocity_W_m_per_s.z());
    outputs_.tool_force_W_N.z() += cut_normal_N_;
  }
}

// The tip against the skin surface of the rest grid cell under it: a
// penalty push up on the tool, down on the cell's four nodes.
void CuttingScene::PressSkinUnderTip(const ToolInput& tool) {
  MsmState& st = skin_.state;
  const double k = params_.contact_stiffness_N_per_m;
  const Eigen::Vector3d& tip = tool.tip_W_m;
  const double fx = (tip.x() + 0.5 * params_.patch_length_m) / (params_.patch_length_m / (skin_.nx - 1));
  const double fy = (tip.y() + 0.5 * params_.patch_width_m) / (params_.patch_width_m / (skin_.ny - 1));
  if (!(fx >= 0.0 && fy >= 0.0 && fx < skin_.nx - 1 && fy < skin_.ny - 1)) return;
  const int i = static_cast<int>(fx), j = static_cast<int>(fy);
  const double u = fx - i, w = fy - j;
  const std::array<std::uint32_t, 4> nodes = {
      static_cast<std::uint32_t>(j * skin_.nx + i), static_cast<std::uint32_t>(j * skin_.nx + i + 1),
      static_cast<std::uint32_t>((j + 1) * skin_.nx + i), static_cast<std::uint32_t>((j + 1) * skin_.nx + i + 1)};
  const std::array<double, 4> weights = {(1 - u) * (1 - w), u * (1 - w), (1 - u) * w, u * w};
  double surface_z = 0.0, surface_vz = 0.0;
  for (int a = 0; a < 4; ++a) {
    if (!skin_.model.node_live[nodes[static_cast<std::size_t>(a)]]) return;  // a cut went through this cell
    surface_z += weights[static_cast<std::size_t>(a)] * st.x_m(2, nodes[static_cast<std::size_t>(a)]);
    surface_vz += weights[static_cast<std::size_t>(a)] * st.v_m_per_s(2, nodes[static_cast<std::size_t>(a)]);
  }
  const double penetration = surface_z - tip.z();
  if (penetration <= 0.0) return;
  const double push = std::max(0.0, k * penetration - params_.contact_damping_Ns_per_m * (tool.velocity_W_m_per_s.z() - surface_vz));
  outputs_.tool_force_W_N.z() += push;
  for (int a = 0; a < 4; ++a) {
    st.f_ext_N(2, nodes[static_cast<std::size_t>(a)]) -= weights[static_cast<std::size_t>(a)] * push;
    loaded_nodes_.push_back(nodes[static_cast<std::size_t>(a)]);
  }
}

// The in-plane unit normal from lip node v into its tissue (the wound edges
// have their tissue on the left); zero if v has no wound edge.
Eigen::Vector3d CuttingScene::IntoTissue(std::uint32_t v) const {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (const auto& [a, b] : skin_.wound_edges) {
    if (a != v && b != v) continue;
    const Eigen::Vector3d e = skin_.model.x0_m.col(b) - skin_.model.x0_m.col(a);
    n += Eigen::Vector3d(-e.y(), e.x(), 0.0).normalized();
  }
  const double length = n.norm();
  return length > 0.0 ? Eigen::Vector3d(n / length) : n;
}

// The device's model: pressing -> kContact on the plane under the tip,
// reproducing the physics force at the current tip; cutting -> kCutting,
// the drag along the incision's current direction; the blade-side
// reactions ride along as feed-forward.
void CuttingScene::UpdateForceModel(const ToolInput& tool) {
  LocalForceModel m;
  if (!CuttingToolUsable(tool)) {
    outputs_.force_model = m;
    outputs_.tool_force_W_N.setZero();
    return;
  }
  const Eigen::Vector3d& tip = tool.tip_W_m;
  if (cutting_) {
    // The drag along the incision, and the normal law of the depth: k (0 - z) - b v_z.
    m.state = ContactState::kCutting;
    m.anchor_W_m = Eigen::Vector3d(tip.x(), tip.y(), 0.0);
    m.normal_W = Eigen::Vector3d::UnitZ();
    m.stiffness_N_per_m = std::min(params_.contact_stiffness_N_per_m, params_.render_stiffness_max_N_per_m);
    m.damping_Ns_per_m = params_.contact_damping_Ns_per_m;
    const Eigen::Vector2d t = curve_.Segments() > 0 ? curve_.Tangent(curve_.Segments()) : Eigen::Vector2d::UnitX();
    m.drag_direction_W = Eigen::Vector3d(t.x(), t.y(), 0.0);
    m.drag_N = params_.cut_force_N;
    m.drag_damping_Ns_per_m = params_.cut_damping_Ns_per_m;
    m.feedforward_W_N =
        outputs_.tool_force_W_N - cut_normal_N_ * Eigen::Vector3d::UnitZ();  // the blade sides' reactions
    outputs_.tool_force_W_N = EvaluateLocalForce(m, tip, tool.velocity_W_m_per_s);
  } else if (outputs_.tool_force_W_N.z() > 0.0 || !loaded_nodes_.empty()) {
    m.state = ContactState::kContact;
    m.normal_W = Eigen::Vector3d::UnitZ();
    m.stiffness_N_per_m = std::min(params_.contact_stiffness_N_per_m, params_.render_stiffness_max_N_per_m);
    m.damping_Ns_per_m = params_.contact_damping_Ns_per_m;
    // k p - b v_z = push at the current tip: p = (push + b v_z) / k (without
    // the damper if that would put the plane below the tip); no push: the
    // plane at the tip.
    const double push = std::max(0.0, outputs_.tool_force_W_N.z());
    if (push + m.damping_Ns_per_m * tool.velocity_W_m_per_s.z() <= 0.0) m.damping_Ns_per_m = 0.0;
    const double p = push > 0.0 ? (push + m.damping_Ns_per_m * tool.velocity_W_m_per_s.z()) / m.stiffness_N_per_m : 0.0;
    m.anchor_W_m = tip + Eigen::Vector3d(0.0, 0.0, p);
    m.feedforward_W_N = outputs_.tool_force_W_N - push * Eigen::Vector3d::UnitZ();  // what the normal law does not give
  }
  outputs_.force_model = m;
}

void CuttingScene::UpdateBladeMesh(const Cylinder& blade) {
  const Eigen::Vector3d axis = (blade.p1_W_m - blade.p0_W_m).normalized();
  const Eigen::Vector3d any = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = axis.cross(any).normalized(), e2 = axis.cross(e1);
  const double r = blade.radius_m;
  const std::array<Eigen::Vector3d, 4> ring = {r * e1, r * e2, -r * e1, -r * e2};
  for (std::size_t k = 0; k < 4; ++k) {
    skin_.state.x_m.col(blade_slots_[k]) = blade.p0_W_m + ring[k];
    skin_.state.x_m.col(blade_slots_[4 + k]) = blade.p1_W_m + ring[k];
  }
}

void CuttingScene::Log(SceneEventKind kind, const Eigen::Vector3d& where, double value) {
  SceneEvent e;
  e.t_s = skin_.state.t_s;
  e.kind = kind;
  e.layer = 0;  // the skin (resets are logged by FinishReset)
  e.where_W_m = where;
  e.value = value;
  outputs_.events.Push(e);
}

void CuttingScene::Reset() {
  skin_.model = initial_model_;  // same sizes and reserved capacities: no allocation
  skin_.state = initial_state_;
  skin_.topology.Reset();
  std::copy(initial_on_lip_.begin(), initial_on_lip_.end(), skin_.on_lip.begin());
  skin_.lip_nodes.clear();
  skin_.wound_edges.clear();
  UpdatePrestressHold(skin_);
  curve_.Clear();
  cutting_ = false;
  in_contact_ = false;
  colliding_.clear();
  loaded_nodes_.clear();
  cut_totals_ = {};
  resting_.RestAll();  // the initial state is at rest
  rest_checked_version_ = skin_.topology.Version();
  cut_box_.setEmpty();
  recut_box_.setEmpty();
  hold_version_ = ~std::uint64_t{0};  // the next step holds every node again
  FinishReset();
}

void CuttingScene::NumericalReset() {
  const std::uint64_t resets = outputs_.status.numerical_resets + 1;
  const double t = skin_.state.t_s;
  Reset();
  skin_.state.t_s = t;
  outputs_.status.numerical_resets = resets;
}

std::uint64_t CuttingScene::StateHash() const {
  StateHasher h;
  AddCommonSceneState(h, *this, outputs_.reset_epoch);
  // Node columns up to the last slot ever used (the rest never held state).
  const MsmState& s = skin_.state;
  const std::size_t used = 3 * static_cast<std::size_t>(skin_.topology.Vertices().HighWater()) * sizeof(double);
  h.AddBytes(s.x_m.data(), used).AddBytes(s.v_m_per_s.data(), used).AddBytes(s.f_residual_N.data(), used);
  h.Add(s.t_s).Add(s.blowups);
  // The skin's springs, masses and liveness change only with the topology:
  // their digest is recomputed when the topology version moved.
  if (digest_version_ != skin_.topology.Version()) {
    StateHasher d;
    d.Add(skin_.model.spring_i).Add(skin_.model.spring_j).Add(skin_.model.spring_rest_m).Add(skin_.model.mass_kg);
    d.Add(skin_.model.node_live).Add(skin_.topology.Triangles().LiveFlags());
    topology_digest_ = d.Value();
    digest_version_ = skin_.topology.Version();
  }
  h.Add(topology_digest_);
  h.Add(cutting_).Add(in_contact_).Add(curve_.Segments());
  // Which nodes rest decides the next steps as much as x and v do.
  const auto slots =
      static_cast<std::size_t>(std::min<Eigen::Index>(skin_.model.num_nodes, skin_.topology.Vertices().HighWater()));
  if (params_.rest_force_N > 0.0) {
    h.AddBytes(resting_.AwakeFlags().data(), slots)
        .AddBytes(resting_.QuietSteps().data(), slots * sizeof(std::int32_t));
    h.Add(resting_.StepsSinceRestCheck());
    for (int a = 0; a < 3; ++a) h.Add(recut_box_.min()[a]).Add(recut_box_.max()[a]);
  }
  for (int k = 0; k < curve_.Segments(); ++k)
    for (const auto& p : curve_.Controls(k)) h.Add(p.x()).Add(p.y());
  return h.Value();
}

std::unique_ptr<Scene> MakeCuttingScene(const std::map<std::string, double>& params) {
  return std::make_unique<CuttingScene>(ParseCuttingParams(params));
}

}  // namespace hapsim::core
