// A procedural, star-shaped "limb-like" body part to fit SH layers from: a
// rounded cylinder (superquadric, exponent p) along the body z axis with a
// smooth muscle belly. Body frame B: z = limb axis, the skin top is +y.
#pragma once
#include <Eigen/Core>

namespace hapsim::core {

struct LimbSegmentDef {
  double half_length_m = 0.20;      // along body z
  double radius_x_m = 0.075;        // cross-section semi-axis along body x
  double radius_y_m = 0.070;        // cross-section semi-axis along body y (the top)
  double squareness = 4.0;          // superquadric exponent p (2 = ellipsoid, larger = flatter ends)
  double belly_amplitude = 0.08;    // relative radius gain of the muscle belly
  double belly_center_uz = 0.0;     // belly position along the axis (direction cosine); 0 = at the site
  double belly_width_uz = 0.35;
};

// Radius of the skin surface in body direction u (any non-zero length) [m].
double LimbSegmentRadius_m(const LimbSegmentDef& def, const Eigen::Vector3d& u_B);

// n surface samples c + r(u_i) u_i along Fibonacci directions, body frame
// relative to the centre, shrunk radially by inset_m (nested layers) (3 x n).
Eigen::Matrix3Xd SampleLimbSegment_m(const LimbSegmentDef& def, int n, double inset_m = 0.0);

}  // namespace hapsim::core
