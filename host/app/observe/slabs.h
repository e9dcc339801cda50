// Angle of repose next to the end plates and in the middle of the drum (diagnosis.md §2): a camera looks
// through the plate, where wall friction holds the bed differently from the bulk. The angle of each slab is
// the dynamic AoR of app/drum/aor.h (centre of mass of the slab's particles, signed atan2(c_x, -c_y)).
//
// Slab thickness t = min(thickness x d, L/3), d the number-mean particle diameter, L the drum length: a
// particle belongs to the low plate's slab when its centre is within t of the plate (z < -L/2 + t), to the
// high plate's slab when z > L/2 - t, and to the central slab when |z| < t/2. The three slabs are equally
// thick and never overlap.
#pragma once

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::observe {

struct SlabAor {
  bool present = false;  // false on a periodic slice (no plates): no slab angle exists
  double thickness_m = 0.0;
  double plate_lo_deg = 0.0, plate_hi_deg = 0.0, centre_deg = 0.0;   // signed, as dynamic_aor
  bool lo_flagged = true, hi_flagged = true, centre_flagged = true;  // empty or |COM| < 0.2 R
  // |(θ_lo + θ_hi)/2| and |θ_centre| (deg); NaN when a slab they use is flagged.
  double plate_deg() const;
  double centre_abs_deg() const;
};

SlabAor slab_aor(const SystemState& s, const DrumParams& drum, double thickness = 3.0);

}  // namespace wetdem::observe
