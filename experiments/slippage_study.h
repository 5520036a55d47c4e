// The slippage model's stability bound found by running past it (the
// tests and the speed-against-error report): a collapse stepped with one
// sweep a step at exactly a chosen Courant number v dt / d, which may be
// beyond kMaxSlideCourant, measuring how far the result breaks the discrete
// maximum principle.
#pragma once

#include "terrain/flow_law.h"

namespace skidsim::terrain {

struct SlideOvershoot {
  // A 1 m block on a strip of 60 cells (two faces a cell, so its own bound
  // is Cr = 1): the largest one-step rise of the surface's total variation.
  double strip_variation_rise_m = 0.0;
  // A 1 m column, 0.25 m in radius, on a 61 x 61 yard (four faces, the
  // grid's bound 1/2): the largest one-step rise of the highest surface.
  double yard_top_rise_m = 0.0;
};

// `soil` is run in the slippage model at 5 cm cells; 400 steps at most.
SlideOvershoot slide_overshoot_at(const SoilFlowParameters& soil, double courant);

}  // namespace skidsim::terrain
