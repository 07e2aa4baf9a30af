#include "hapsim/wire/topics_wire.h"

namespace hapsim::wire {

namespace {

void Put(const Eigen::Vector3d& v, double (&out)[3]) {
  for (int i = 0; i < 3; ++i) out[i] = v[i];
}
Eigen::Vector3d Get(const double (&in)[3]) { return {in[0], in[1], in[2]}; }

}  // namespace

void PackForceModel(const core::LocalForceModel& m, const Eigen::Vector3d& tool_force_W_N,
                    hapsim_dds_LocalForceModel* out) {
  out->state = static_cast<std::uint8_t>(m.state);
  Put(m.anchor_W_m, out->anchor_m);
  Put(m.normal_W, out->normal);
  out->stiffness_n_per_m = m.stiffness_N_per_m;
  out->damping_ns_per_m = m.damping_Ns_per_m;
  Put(m.feedforward_W_N, out->feedforward_n);
  Put(tool_force_W_N, out->tool_force_n);
  Put(m.drag_direction_W, out->drag_direction);
  out->drag_n = m.drag_N;
  out->drag_damping_ns_per_m = m.drag_damping_Ns_per_m;
  Put(m.stick_W_m, out->stick_m);
  out->stick_stiffness_n_per_m = m.stick_stiffness_N_per_m;
  Put(m.tip_anchor_W_m, out->tip_anchor_m);
  out->tip_stiffness_n_per_m = m.tip_stiffness_N_per_m;
  out->release_penetration_m = m.release_penetration_m;
  out->release_stiffness_n_per_m = m.release_stiffness_N_per_m;
  out->release_damping_ns_per_m = m.release_damping_Ns_per_m;
  out->tip_release_penetration_m = m.tip_release_penetration_m;
}

core::LocalForceModel UnpackForceModel(const hapsim_dds_LocalForceModel& in) {
  core::LocalForceModel c;
  c.state = in.state <= 3 ? static_cast<core::ContactState>(in.state) : core::ContactState::kFree;
  c.anchor_W_m = Get(in.anchor_m);
  c.normal_W = Get(in.normal);
  c.stiffness_N_per_m = in.stiffness_n_per_m;
  c.damping_Ns_per_m = in.damping_ns_per_m;
  c.feedforward_W_N = Get(in.feedforward_n);
  c.drag_direction_W = Get(in.drag_direction);
  c.drag_N = in.drag_n;
  c.drag_damping_Ns_per_m = in.drag_damping_ns_per_m;
  c.stick_W_m = Get(in.stick_m);
  c.stick_stiffness_N_per_m = in.stick_stiffness_n_per_m;
  c.tip_anchor_W_m = Get(in.tip_anchor_m);
  c.tip_stiffness_N_per_m = in.tip_stiffness_n_per_m;
  c.release_penetration_m = in.release_penetration_m;
  c.release_stiffness_N_per_m = in.release_stiffness_n_per_m;
  c.release_damping_Ns_per_m = in.release_damping_ns_per_m;
  c.tip_release_penetration_m = in.tip_release_penetration_m;
  return c;
}

Eigen::Vector3d UnpackToolForce_W_N(const hapsim_dds_LocalForceModel& in) { return Get(in.tool_force_n); }

void PackPose(const core::ToolInput& tool, hapsim_dds_StylusPose* out) {
  Put(tool.tip_W_m, out->pos_m);
  Put(tool.velocity_W_m_per_s, out->vel_m_per_s);
  out->quat_wxyz[0] = tool.orientation_W.w();
  out->quat_wxyz[1] = tool.orientation_W.x();
  out->quat_wxyz[2] = tool.orientation_W.y();
  out->quat_wxyz[3] = tool.orientation_W.z();
  out->buttons = tool.buttons;
}

core::ToolInput UnpackPose(const hapsim_dds_StylusPose& in) {
  core::ToolInput tool;
  tool.valid = true;
  tool.tip_W_m = Get(in.pos_m);
  tool.velocity_W_m_per_s = Get(in.vel_m_per_s);
  tool.orientation_W = Eigen::Quaterniond(in.quat_wxyz[0], in.quat_wxyz[1], in.quat_wxyz[2], in.quat_wxyz[3]);
  tool.buttons = in.buttons;
  return tool;
}

}  // namespace hapsim::wire
