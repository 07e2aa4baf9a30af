// The one place where the device's units and axes become ours. The HD API
// reports the stylus in millimetres in the device frame D (x to the user's
// right, y up, z towards the user); hapsim's world frame W has z up and y
// away from the user (the tissue surface is z = 0, pressing is -z). So
//   p_W [m] = scale * R_WD * p_D [mm] * 1e-3 + offset_W [m]
//   v_W     = scale * R_WD * v_D * 1e-3,   q_W = R_WD * q_D
//   F_D [N] = R_WD^T * F_W                  (forces are not scaled)
// with R_WD: x_W = x_D, y_W = -z_D, z_W = y_D. `scale` (world metres per
// device metre) maps a small workspace onto a bigger scene or the reverse;
// it multiplies the stiffness the hand feels (k_D = scale * k_W), so the
// device's stiffness and damping caps divide by it (see Limits()).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapsim::bridge {

struct WorkspaceMap {
  double scale = 1.0;                                    // world m per device m
  Eigen::Vector3d offset_W_m = Eigen::Vector3d::Zero();  // where the device origin sits in W
  Eigen::Matrix3d R_WD = (Eigen::Matrix3d() << 1, 0, 0,  //
                          0, 0, -1,                      //
                          0, 1, 0)
                             .finished();

  Eigen::Vector3d Position_W_m(const Eigen::Vector3d& p_D_mm) const {
    return scale * 1e-3 * (R_WD * p_D_mm) + offset_W_m;
  }
  Eigen::Vector3d Velocity_W_m_per_s(const Eigen::Vector3d& v_D_mm_per_s) const {
    return scale * 1e-3 * (R_WD * v_D_mm_per_s);
  }
  Eigen::Quaterniond Orientation_W(const Eigen::Matrix3d& R_D) const {
    return Eigen::Quaterniond(R_WD * R_D).normalized();
  }
  Eigen::Vector3d Force_D_N(const Eigen::Vector3d& f_W_N) const { return R_WD.transpose() * f_W_N; }
  // A stiffness or damping limit of the device, in world terms.
  double WorldCap(double device_cap) const { return device_cap / scale; }
};

}  // namespace hapsim::bridge
