// acupuncture scene: insertion state machine, forces and the local force
// model. Display mesh updates live in acupuncture_display.cpp.
#include "hapsim/core/scenes/acupuncture/acupuncture_scene.h"

#include <algorithm>
#include <cmath>

#include "hapsim/core/scenes/acupuncture/acupuncture_body.h"
#include "hapsim/core/scenes/scene_builders.h"
#include "hapsim/core/shape_matching/shape_matching.h"

namespace hapsim::core {

namespace {

ForceNetDef NetDef(const AcupunctureParams& p, const TissueLayer& layer) {
  ForceNetDef d = ForceNetDefFor(layer);
  d.surface_ratio = p.net_surface_ratio;
  d.prestretch = p.net_prestretch;
  // A thicker needle needs more force to cut its way in: in proportion to
  // its diameter (an assumption; docs/validation.md#acupuncture).
  d.puncture_force_N = layer.puncture_force_N * (2.0 * p.needle_radius_m / kReferenceNeedleDiameter_m);
  return d;
}

bool AcupunctureToolUsable(const ToolInput& tool) {
  return tool.valid && tool.tip_W_m.allFinite() && tool.orientation_W.coeffs().allFinite() &&
         tool.orientation_W.norm() > 0.0 && tool.velocity_W_m_per_s.allFinite();
}

constexpr int kMaxTransitionsPerTick = 8;  // bounds event spam from a pathological pose
constexpr double kNeedleRestHeight_m = 0.05;  // initial needle: tip this far above the skin, pointing down

}  // namespace

AcupunctureScene::AcupunctureScene(const AcupunctureParams& params)
    : params_(params),
      body_(MakeAcupunctureBody(params.layers, params.shf_lmax, params.shf_samples)),
      depth_m_(Eigen::VectorXd::Zero(kNumTissueLayers + 1)) {
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    nets_[i] = BuildForceNet(NetDef(params_, params_.layers[i]));
    net_states_[i] = MakeForceNetState(nets_[i]);
    eta_[i] = Eigen::VectorXd::Zero(nets_[i].topology.NumNodes());
    unit_mass_[i] = Eigen::VectorXd::Ones(nets_[i].topology.NumNodes());
    outputs_.status.layer_names.push_back(params_.layers[i].name);
  }
  BuildDisplay();
  ResetState();
}

void AcupunctureScene::ResetState() {
  pressing_ = false;
  punctured_ = 0;
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    PlaceForceNet(nets_[i], Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), net_states_[i]);
    eta_[i].setZero();
    HideNet(static_cast<int>(i));
    springing_back_[i] = punctured_once_[i] = false;
    puncture_tip_W_m_[i].setZero();
  }
  entry_W_m_.setZero();
  entry_axis_W_ = -Eigen::Vector3d::UnitZ();
  depth_m_.setZero();
  shaft_damping_Ns_per_m_ = 0.0;
  shaft_coulomb_N_ = 0.0;
  stick_W_m_.setZero();
  t_s_ = 0.0;
  ClearStepOutputs();
  UpdateNeedleMesh(Eigen::Vector3d(0, 0, kNeedleRestHeight_m), -Eigen::Vector3d::UnitZ());
}

void AcupunctureScene::Reset() {
  ResetState();
  FinishReset();
}

std::uint64_t AcupunctureScene::StateHash() const {
  StateHasher h;
  AddCommonSceneState(h, *this, outputs_.reset_epoch);
  h.Add(pressing_).Add(punctured_).Add(entry_W_m_).Add(entry_axis_W_).Add(depth_m_).Add(shaft_damping_Ns_per_m_);
  h.Add(shaft_coulomb_N_).Add(stick_W_m_);
  // Left out as pure functions of what is hashed: each net's rest lattice
  // (placement n1_rest + normal) and the patch vertices' ring coordinates q.
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    const ForceNetState& s = net_states_[i];
    h.Add(s.n1_rest_W_m).Add(s.normal_W).Add(s.x_W_m).Add(s.ring_Z_m).Add(s.anchored);
    h.Add(eta_[i]).Add(net_shown_[i]).Add(net_moved_[i]).Add(springing_back_[i]);
    h.Add(punctured_once_[i]).Add(puncture_tip_W_m_[i]);
    // Displayed patch: only the vertices near a placed net ever leave rest.
    h.Add(patch_near_net_[i].size()).Add(patch_near_net_[i]);
    for (const std::int32_t v : patch_near_net_[i]) h.AddBytes(vertices_m_.col(v).data(), 3 * sizeof(double));
  }
  const Eigen::Index needle_first = static_cast<Eigen::Index>(kNumTissueLayers) * patch_vertices_;
  h.AddBytes(vertices_m_.col(needle_first).data(),
             3 * sizeof(double) * static_cast<std::size_t>(vertices_m_.cols() - needle_first));
  return h.Value();
}

void AcupunctureScene::NumericalReset() {
  const double t = t_s_;
  ResetState();
  t_s_ = t;
  LogNumericalReset(t);
}

void AcupunctureScene::Log(SceneEventKind kind, int layer, const Eigen::Vector3d& where) {
  outputs_.events.Push({t_s_, kind, layer, where});
}

std::optional<double> AcupunctureScene::PuncturePointOffset_m(int layer) const {
  const auto i = static_cast<std::size_t>(layer);
  if (layer < 0 || layer >= kNumTissueLayers || !punctured_once_[i]) return std::nullopt;
  const ForceNetState& s = net_states_[i];
  return (s.x_W_m.col(0) - puncture_tip_W_m_[i]).dot(s.normal_W);
}

void AcupunctureScene::Step(const ToolInput& tool, double dt_s) {
  if (std::isfinite(dt_s) && dt_s > 0.0) t_s_ += dt_s;
  if (AcupunctureToolUsable(tool)) {
    FollowTool(tool);
  } else {
    LoseTool(tool);
  }
  AdvanceSpringback();
  // Blow-up guard: anything non-finite in what we publish resets the scene.
  if (!PublishedStateFinite()) {
    NumericalReset();
    return;
  }
  UpdatePatches();
}

// No (usable) tool: the needle is out of the tissue.
void AcupunctureScene::LoseTool(const ToolInput& tool) {
  if (pressing_ || punctured_ > 0) {
    const Eigen::Vector3d where = tool.tip_W_m.allFinite() ? tool.tip_W_m : Eigen::Vector3d::Zero();
    Log(SceneEventKind::kContactEnd, outputs_.status.current_layer, where);
  }
  if (pressing_) HideNet(punctured_);  // an unpunctured dimple relaxes
  pressing_ = false;
  punctured_ = 0;
  ClearStepOutputs();
}

// The needle at the tool's pose: the insertion state, the force, its local
// model, the status and the needle mesh.
void AcupunctureScene::FollowTool(const ToolInput& tool) {
  const Eigen::Vector3d tip = tool.tip_W_m;
  const Eigen::Vector3d axis = (tool.orientation_W.normalized() * Eigen::Vector3d(0, 0, -1)).normalized();
  body_.Depths_m(tip, depth_m_);
  UpdateInsertion(tip, axis);
  ComputeForce(tip, tool.velocity_W_m_per_s);
  ComputeForceModel(tip, tool.velocity_W_m_per_s);
  outputs_.status.current_layer = pressing_ ? punctured_ : punctured_ - 1;
  outputs_.status.tip_depth_m = std::max(0.0, depth_m_[0]);
  UpdateNeedleMesh(tip, axis);
}

// One shape-matching step for every net still springing back.
void AcupunctureScene::AdvanceSpringback() {
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    if (!springing_back_[i]) continue;
    // Once η is 0 everywhere, this step puts every particle on its goal, a
    // fixed point of shape matching: the springback is over.
    if (eta_[i].maxCoeff() == 0.0) springing_back_[i] = false;
    SpringbackStep(net_states_[i].rest_W_m, unit_mass_[i], params_.springback_eta_rate_per_step,
                   net_states_[i].x_W_m, eta_[i]);
    UpdateRingDeflections(nets_[i], net_states_[i]);
    net_moved_[i] = true;
  }
}

bool AcupunctureScene::PublishedStateFinite() const {
  bool finite = outputs_.tool_force_W_N.allFinite();
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) finite = finite && net_states_[i].ring_Z_m.allFinite();
  return finite;
}

void AcupunctureScene::UpdateInsertion(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis) {
  for (int guard = 0; guard < kMaxTransitionsPerTick; ++guard) {
    const int layer = punctured_;
    if (pressing_) {
      ForceNetState& s = net_states_[static_cast<std::size_t>(layer)];
      // One contact rule: contact with a layer begins and ends at its rest
      // surface (depth 0), so no position between two surfaces toggles it.
      if (depth_m_[layer] < 0.0) {  // tip lifted off the layer
        pressing_ = false;
        HideNet(layer);
        Log(SceneEventKind::kContactEnd, layer, tip);
        continue;
      }
      // Above where the net was placed yet still below the rest surface: a
      // surface that the layer above carried down follows the tip back up,
      // unloaded, until it is home.
      if ((s.n1_rest_W_m - tip).dot(s.normal_W) < 0.0)
        PlaceForceNet(nets_[static_cast<std::size_t>(layer)], tip, s.normal_W, s);
      SolveForceNet(nets_[static_cast<std::size_t>(layer)], tip, s);
      net_moved_[static_cast<std::size_t>(layer)] = true;
      if (PunctureForceReached(nets_[static_cast<std::size_t>(layer)], s)) {
        Puncture(layer, tip, axis);
        continue;
      }
      return;
    }
    if (layer < kNumTissueLayers && depth_m_[layer] >= 0.0) {
      StartContact(layer, tip);
      continue;
    }
    if (layer > 0 && depth_m_[layer - 1] < 0.0) {  // withdrawn above the top of the layer it was in
      --punctured_;
      if (punctured_ == 0) Log(SceneEventKind::kContactEnd, 0, tip);
      continue;
    }
    return;
  }
}

void AcupunctureScene::StartContact(int layer, const Eigen::Vector3d& tip) {
  const auto i = static_cast<std::size_t>(layer);
  const Eigen::Vector3d dir = tip - body_.Def().center_W_m;
  const Eigen::Vector3d normal = body_.OutwardNormal_W(layer, dir);
  Eigen::Vector3d n1 = body_.SurfacePoint_W_m(layer, dir);
  // The layer above, pressed millimetres deep before it gave way, carried
  // this surface down with it: the layer starts unloaded at the tip.
  if ((n1 - tip).dot(normal) > 0.0) n1 = tip;
  HideNet(layer);
  PlaceForceNet(nets_[i], n1, normal, net_states_[i]);
  springing_back_[i] = false;
  punctured_once_[i] = false;
  ShowNet(layer);
  pressing_ = true;
  Log(SceneEventKind::kContactBegin, layer, n1);
}

void AcupunctureScene::Puncture(int layer, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis) {
  const auto i = static_cast<std::size_t>(layer);
  Log(SceneEventKind::kPuncture, layer, tip);
  net_states_[i].anchored = false;  // virtual springs removed at puncture
  eta_[i].setConstant(params_.springback_eta0);
  springing_back_[i] = true;
  punctured_once_[i] = true;
  puncture_tip_W_m_[i] = tip;
  if (layer == 0) {
    entry_W_m_ = tip;
    entry_axis_W_ = axis;
    stick_W_m_ = tip;  // the shaft starts sticking where it entered, unloaded
  }
  pressing_ = false;
  punctured_ = layer + 1;
}

void AcupunctureScene::ComputeForce(const Eigen::Vector3d& tip, const Eigen::Vector3d& v) {
  outputs_.tool_force_W_N.setZero();
  if (pressing_) {
    const auto i = static_cast<std::size_t>(punctured_);
    outputs_.tool_force_W_N += NetReactionOnTip_W_N(nets_[i], net_states_[i]);
  }
  const bool coulomb = params_.shaft_friction_law == 1;
  shaft_damping_Ns_per_m_ = ::hapsim::core::ShaftDamping_Ns_per_m(params_.layers, depth_m_.data(), punctured_) *
                            (coulomb ? params_.shaft_viscous_scale : 1.0);
  shaft_coulomb_N_ = coulomb ? ::hapsim::core::ShaftCoulomb_N(params_.layers, depth_m_.data(), punctured_) : 0.0;
  if (punctured_ > 0) {
    const Eigen::Vector3d& a = entry_axis_W_;
    const Eigen::Vector3d r = tip - entry_W_m_;
    outputs_.tool_force_W_N -= shaft_damping_Ns_per_m_ * v.dot(a) * a;                 // Table 1 (scaled in law 1)
    outputs_.tool_force_W_N -= params_.tunnel_stiffness_N_per_m * (r - r.dot(a) * a);  // tunnel
    if (coulomb) {
      // Stick-slip: an axial spring to the stick point, saturating at the
      // Coulomb level; past it the shaft slips and the stick point follows.
      const double k = params_.shaft_stick_stiffness_N_per_m;
      const double e_m = (tip - stick_W_m_).dot(a);
      const double held_m = std::clamp(e_m, -shaft_coulomb_N_ / k, shaft_coulomb_N_ / k);
      stick_W_m_ += (e_m - held_m) * a;  // slips by the excess, along the axis
      outputs_.tool_force_W_N -= k * held_m * a;
    }
  }
}

void AcupunctureScene::ComputeForceModel(const Eigen::Vector3d& tip, const Eigen::Vector3d& v) {
  LocalForceModel m;
  if (punctured_ > 0) {
    m = TunnelForceModel(tip);
  } else if (pressing_) {
    m = SkinPressForceModel(tip, v);
  }
  outputs_.force_model = m;
}

// A layer's net's tangent stiffness at its depth (it stiffens as it
// deepens), capped at what the device renders stably.
double AcupunctureScene::RenderedNetStiffness_N_per_m(std::size_t layer) const {
  return std::min(std::max(NetStiffnessAtDepth_N_per_m(nets_[layer], net_states_[layer].depth_m), 1.0),
                  params_.render_stiffness_max_N_per_m);
}

// After skin puncture: the tunnel (lateral spring to the entry axis), the
// shaft's damping and friction, and the next layer if the tip presses it.
LocalForceModel AcupunctureScene::TunnelForceModel(const Eigen::Vector3d& tip) const {
  LocalForceModel m;
  m.state = ContactState::kPunctured;
  m.anchor_W_m = entry_W_m_;
  m.normal_W = -entry_axis_W_;  // out of the tissue
  m.stiffness_N_per_m = params_.tunnel_stiffness_N_per_m;
  m.damping_Ns_per_m = shaft_damping_Ns_per_m_;
  if (params_.shaft_friction_law == 1) {
    m.drag_N = shaft_coulomb_N_;
    m.stick_W_m = stick_W_m_;
    m.stick_stiffness_N_per_m = params_.shaft_stick_stiffness_N_per_m;
  }
  if (pressing_) {
    // The tip presses the next layer: its net's tangent stiffness along the
    // axis (capped as for a first touch), with the surface placed so the
    // law gives the net's push at this tip; what is across the axis rides
    // along as feed-forward.
    const auto i = static_cast<std::size_t>(punctured_);
    const Eigen::Vector3d push = NetReactionOnTip_W_N(nets_[i], net_states_[i]);
    const double along_N = std::max(0.0, push.dot(m.normal_W));
    m.tip_stiffness_N_per_m = RenderedNetStiffness_N_per_m(i);
    const double tip_penetration_m = along_N / m.tip_stiffness_N_per_m;
    m.tip_anchor_W_m = tip + tip_penetration_m * m.normal_W;
    m.feedforward_W_N = push - along_N * m.normal_W;
    m.tip_release_penetration_m = tip_penetration_m + DepthToPuncture_m(i);
  }
  return m;
}

// Pressing the skin: a contact plane along the net's normal at N1, placed
// so the law gives this tick's force at this tip.
LocalForceModel AcupunctureScene::SkinPressForceModel(const Eigen::Vector3d& tip, const Eigen::Vector3d& v) const {
  LocalForceModel m;
  const Eigen::Vector3d& n = net_states_[0].normal_W;
  m.state = ContactState::kContact;
  m.normal_W = n;
  m.stiffness_N_per_m = RenderedNetStiffness_N_per_m(0);
  m.damping_Ns_per_m = params_.contact_damping_Ns_per_m;
  const double fn_N = outputs_.tool_force_W_N.dot(n);
  // Penetration p with k p - b (v·n) = F·n, so the law gives F at this tip.
  double p_m = (fn_N + m.damping_Ns_per_m * v.dot(n)) / m.stiffness_N_per_m;
  if (p_m <= 0.0) {  // fast press: the damper alone would exceed F; drop it this tick
    m.damping_Ns_per_m = 0.0;
    p_m = std::max(0.0, fn_N) / m.stiffness_N_per_m;
  }
  m.anchor_W_m = tip + p_m * n;
  m.feedforward_W_N = outputs_.tool_force_W_N - std::max(0.0, fn_N) * n;
  // Where the skin will give way, and the tunnel the needle is in after it
  // (what Puncture and ComputeForce will do), so the device pops there.
  m.release_penetration_m = p_m + DepthToPuncture_m(0);
  m.release_stiffness_N_per_m = params_.tunnel_stiffness_N_per_m;
  const bool coulomb = params_.shaft_friction_law == 1;
  m.release_damping_Ns_per_m = ::hapsim::core::ShaftDamping_Ns_per_m(params_.layers, depth_m_.data(), 1) *
                               (coulomb ? params_.shaft_viscous_scale : 1.0);
  return m;
}

// How much deeper the tip can press a layer's net before it punctures: the
// net's table reaches the puncture force at puncture_depth_m (pressing along
// the normal, as the insertion does). Never 0, so a model always says where
// the layer gives (0 would mean "never").
double AcupunctureScene::DepthToPuncture_m(std::size_t layer) const {
  return std::max(nets_[layer].puncture_depth_m - net_states_[layer].depth_m, 1e-9);
}

std::unique_ptr<Scene> MakeAcupunctureScene(const std::map<std::string, double>& params) {
  return std::make_unique<AcupunctureScene>(ParseAcupunctureParams(params));
}

}  // namespace hapsim::core
