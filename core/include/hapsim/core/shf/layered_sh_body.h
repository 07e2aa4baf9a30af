// Nested star-shaped SH surfaces around one centre: the radial inside/outside
// and depth query of the acupuncture paper's SHF tissue layers. For a
// star-shaped layer fitted with the radial parametrisation (sh_fit.h), the
// surface radius in direction u is r(u) = x̂(u)·u and a point p is inside
// when |p - c| < r(u_p); its radial depth below the surface is
// r(u_p) - |p - c|. One basis evaluation serves every layer, so a query costs
// O(k) per layer, independent of any mesh.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "hapsim/core/shf/real_spherical_harmonics.h"
#include "hapsim/core/shf/sh_surface.h"

namespace hapsim::core {

struct LayeredShBodyDef {
  Eigen::Vector3d center_W_m = Eigen::Vector3d::Zero();  // c: every layer is star-shaped about it
  Eigen::Matrix3d R_BW = Eigen::Matrix3d::Identity();    // body-from-world rotation (SH frame)
  // Surfaces, outermost first; coefficients describe p_B - c_B (body frame,
  // relative to the centre), fitted with RadialAngles about the origin.
  std::vector<ShSurface> surfaces;
};

class LayeredShBody {
 public:
  // Throws std::invalid_argument when surfaces are missing, have different
  // Lmax or coefficient shapes, or R_BW is not a rotation.
  explicit LayeredShBody(LayeredShBodyDef def);

  int NumSurfaces() const { return static_cast<int>(def_.surfaces.size()); }
  int Lmax() const { return basis_.Lmax(); }
  const LayeredShBodyDef& Def() const { return def_; }

  // depth_m[i] = r_i(u_p) - |p - c| for every surface (> 0: inside surface i).
  // Non-const only because it reuses an internal basis buffer; never allocates.
  void Depths_m(const Eigen::Vector3d& p_W_m, Eigen::Ref<Eigen::VectorXd> depth_m);
  // r_i in world direction dir_W (any non-zero length) [m].
  double Radius_m(int surface, const Eigen::Vector3d& dir_W);
  // c + r_i(u) u: the surface point seen from the centre along dir_W.
  Eigen::Vector3d SurfacePoint_W_m(int surface, const Eigen::Vector3d& dir_W);
  // Outward unit normal of surface i at SurfacePoint_W_m(i, dir_W), by central
  // differences of the radial map (4 extra basis evaluations).
  Eigen::Vector3d OutwardNormal_W(int surface, const Eigen::Vector3d& dir_W);

 private:
  LayeredShBodyDef def_;
  RealShBasis basis_;
  Eigen::VectorXd scratch_;  // basis values (k)
};

}  // namespace hapsim::core
