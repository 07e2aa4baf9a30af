#include "hapsim/core/msm/msm_forces.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "hapsim/core/msm/aligned_allocator.h"

#include "msm_kernels.h"

namespace hapsim::core {

void ComputeForces(const MsmModel& model, const MsmState& state, const Eigen::Matrix3Xd& x_m,
                   const Eigen::Matrix3Xd& v_m_per_s, Eigen::Matrix3Xd& f_N) {
  // Same two parts as the step: spring scatter, then the per-node terms.
  std::vector<double, AlignedAllocator<double, 64>> spring_f_N(
      kSpringForceStride * static_cast<std::size_t>(model.num_nodes), 0.0);
  detail::SpringForces(model, BestSpringKernel(), x_m.data(), v_m_per_s.data(), spring_f_N.data(),
                       detail::DenseRange{model.NumSprings()});
  const detail::NodeTerms terms(model, state);
  f_N.resize(3, model.num_nodes);
  for (std::int32_t i = 0; i < model.num_nodes; ++i)
    for (int c = 0; c < 3; ++c) f_N(c, i) = terms.Take(spring_f_N.data(), x_m.data(), v_m_per_s.data(), i, c);
}

double PotentialEnergy_J(const MsmModel& model, const MsmState& state, const Eigen::Matrix3Xd& x) {
  double e = 0.0;
  for (std::int32_t s = 0; s < model.NumSprings(); ++s) {
    const double stretch =
        (x.col(model.spring_j[s]) - x.col(model.spring_i[s])).norm() - model.spring_rest_m[s];
    e += 0.5 * model.spring_k_N_per_m[s] * stretch * stretch;
  }
  for (std::int32_t a = 0; a < model.NumAnchors(); ++a)
    e += 0.5 * model.anchor_k_N_per_m[a] *
         (x.col(model.anchor_node[a]) - model.anchor_point_W_m.col(a)).squaredNorm();
  // Constant forces F have potential -F·x.
  for (std::int32_t i = 0; i < model.num_nodes; ++i) {
    const Eigen::Vector3d f_const = model.mass_kg[i] * model.gravity_m_per_s2 +
                                    state.f_ext_N.col(i) + state.f_residual_N.col(i);
    e -= f_const.dot(x.col(i));
  }
  return e;
}

double KineticEnergy_J(const MsmModel& model, const Eigen::Matrix3Xd& v) {
  return 0.5 * (v.colwise().squaredNorm().transpose().array() * model.mass_kg.array()).sum();
}

Eigen::MatrixXd AssembleStiffness(const MsmModel& model, const Eigen::Matrix3Xd& x,
                                  bool clamp_compression) {
  const Eigen::Index n3 = 3 * model.num_nodes;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n3, n3);
  for (std::int32_t s = 0; s < model.NumSprings(); ++s) {
    const std::int32_t i = model.spring_i[s], j = model.spring_j[s];
    const Eigen::Vector3d d = x.col(j) - x.col(i);
    const double l = d.norm();
    const Eigen::Vector3d u = d / l;
    const double k = model.spring_k_N_per_m[s];
    double geo = 1.0 - model.spring_rest_m[s] / l;  // transverse (geometric) stiffness factor
    if (clamp_compression) geo = std::max(0.0, geo);
    const Eigen::Matrix3d uu = u * u.transpose();
    const Eigen::Matrix3d B = k * (uu + geo * (Eigen::Matrix3d::Identity() - uu));
    K.block<3, 3>(3 * i, 3 * i) += B;
    K.block<3, 3>(3 * j, 3 * j) += B;
    K.block<3, 3>(3 * i, 3 * j) -= B;
    K.block<3, 3>(3 * j, 3 * i) -= B;
  }
  for (std::int32_t a = 0; a < model.NumAnchors(); ++a) {
    const std::int32_t i = model.anchor_node[a];
    K.block<3, 3>(3 * i, 3 * i) += model.anchor_k_N_per_m[a] * Eigen::Matrix3d::Identity();
  }
  return K;
}

}  // namespace hapsim::core
