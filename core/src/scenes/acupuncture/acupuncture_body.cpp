#include "hapsim/core/scenes/acupuncture/acupuncture_body.h"

#include "hapsim/core/shf/sh_fit.h"

namespace hapsim::core {

// Departure from the paper (docs/validation.md#acupuncture): the paper reads
// the ring deformations Z_j from the change of the SHF radius. These SH
// surfaces stay rigid and only answer depth queries (where each layer's top
// is along the needle); the force net placed at the contact point deforms
// instead — refitting the coefficients each tick would cost the build's
// least-squares fit for a dimple the net already describes.
LayeredShBody MakeAcupunctureBody(const std::array<TissueLayer, kNumTissueLayers>& layers, int lmax, int samples,
                                  const LimbSegmentDef& limb) {
  LayeredShBodyDef def;
  // Rows: body x = world y, body y = world z, body z = world x (cyclic, det +1).
  def.R_BW << 0, 1, 0,  //
      0, 0, 1,          //
      1, 0, 0;
  double inset_m = 0.0;
  for (int s = 0; s <= kNumTissueLayers; ++s) {
    const Eigen::Matrix3Xd p = SampleLimbSegment_m(limb, samples, inset_m);
    def.surfaces.push_back(FitShSurface(lmax, RadialAngles(p, Eigen::Vector3d::Zero()), p).surface);
    if (s < kNumTissueLayers) inset_m += layers[static_cast<std::size_t>(s)].thickness_m;
  }
  // Put the fitted skin top (world +z from the centre) at the origin.
  LayeredShBody probe(def);
  def.center_W_m = Eigen::Vector3d(0, 0, -probe.Radius_m(0, Eigen::Vector3d::UnitZ()));
  return LayeredShBody(def);
}

}  // namespace hapsim::core
