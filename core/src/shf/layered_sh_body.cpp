#include "hapsim/core/shf/layered_sh_body.h"

#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace hapsim::core {

namespace {
int CheckedLmax(const LayeredShBodyDef& def) {
  if (def.surfaces.empty()) throw std::invalid_argument("LayeredShBody: no surfaces");
  const int lmax = def.surfaces.front().lmax;
  for (std::size_t i = 0; i < def.surfaces.size(); ++i) {
    const auto& s = def.surfaces[i];
    if (s.lmax != lmax || s.coeffs_m.rows() != (lmax + 1) * (lmax + 1))
      throw std::invalid_argument("LayeredShBody: surface " + std::to_string(i) +
                                  " has a different Lmax or coefficient count than surface 0");
    if (!s.coeffs_m.allFinite())
      throw std::invalid_argument("LayeredShBody: surface " + std::to_string(i) + " has non-finite coefficients");
  }
  const Eigen::Matrix3d should_be_identity = def.R_BW * def.R_BW.transpose();
  if (!should_be_identity.isIdentity(1e-9) || def.R_BW.determinant() < 0.0)
    throw std::invalid_argument("LayeredShBody: R_BW must be a proper rotation");
  if (!def.center_W_m.allFinite()) throw std::invalid_argument("LayeredShBody: centre is not finite");
  return lmax;
}
}  // namespace

LayeredShBody::LayeredShBody(LayeredShBodyDef def)
    : def_(std::move(def)), basis_(CheckedLmax(def_)), scratch_(basis_.Size()) {}

void LayeredShBody::Depths_m(const Eigen::Vector3d& p_W_m, Eigen::Ref<Eigen::VectorXd> depth_m) {
  const Eigen::Vector3d d_B = def_.R_BW * (p_W_m - def_.center_W_m);
  const double dist_m = d_B.norm();
  const Eigen::Vector3d u_B = dist_m > 0.0 ? Eigen::Vector3d(d_B / dist_m) : Eigen::Vector3d::UnitZ();
  basis_.EvaluateDirection(u_B, scratch_);
  for (int i = 0; i < NumSurfaces(); ++i) {
    const double r_m = ShSurfacePoint(def_.surfaces[static_cast<std::size_t>(i)], scratch_).dot(u_B);
    depth_m[i] = r_m - dist_m;
  }
}

double LayeredShBody::Radius_m(int surface, const Eigen::Vector3d& dir_W) {
  const Eigen::Vector3d u_B = (def_.R_BW * dir_W).normalized();
  basis_.EvaluateDirection(u_B, scratch_);
  return ShSurfacePoint(def_.surfaces.at(static_cast<std::size_t>(surface)), scratch_).dot(u_B);
}

Eigen::Vector3d LayeredShBody::SurfacePoint_W_m(int surface, const Eigen::Vector3d& dir_W) {
  const Eigen::Vector3d u_W = dir_W.normalized();
  return def_.center_W_m + Radius_m(surface, u_W) * u_W;
}

Eigen::Vector3d LayeredShBody::OutwardNormal_W(int surface, const Eigen::Vector3d& dir_W) {
  const Eigen::Vector3d u = dir_W.normalized();
  // Two tangents of the unit sphere at u.
  const Eigen::Vector3d t1 = u.unitOrthogonal();
  const Eigen::Vector3d t2 = u.cross(t1);
  constexpr double kStep = 1e-4;  // rad: central differences, error O(kStep²)
  auto point = [&](const Eigen::Vector3d& v) { return SurfacePoint_W_m(surface, v); };
  const Eigen::Vector3d d1 = point(u + kStep * t1) - point(u - kStep * t1);
  const Eigen::Vector3d d2 = point(u + kStep * t2) - point(u - kStep * t2);
  Eigen::Vector3d n = d1.cross(d2).normalized();
  if (n.dot(u) < 0.0) n = -n;
  return n;
}

}  // namespace hapsim::core
