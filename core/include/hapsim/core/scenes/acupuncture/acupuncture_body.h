// The acupuncture scene's tissue body: nested SH surfaces fitted from the
// procedural limb segment (shf/limb_segment.h), outermost first: skin top,
// fat top, muscle top, muscle bottom (radial insets by the cumulative layer
// thicknesses). Body frame: limb axis (body z) = world x, skin top (body +y)
// = world +z; the centre is placed so the fitted skin top is at the world
// origin.
#pragma once
#include <array>

#include "hapsim/core/needle/tissue_layers.h"
#include "hapsim/core/shf/layered_sh_body.h"
#include "hapsim/core/shf/limb_segment.h"

namespace hapsim::core {

// Throws std::invalid_argument from the fit if samples are too few for lmax.
LayeredShBody MakeAcupunctureBody(const std::array<TissueLayer, kNumTissueLayers>& layers, int lmax, int samples,
                                  const LimbSegmentDef& limb = {});

}  // namespace hapsim::core
