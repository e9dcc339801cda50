// The interface fluctuation of rotating-drum testers (diagnosis.md §2: "a cohesive index = interface
// fluctuation"): instruments such as the GranuDrum film the drum through its end plate, detect the free
// surface in every image and report the standard deviation of the interface position over the images,
// averaged along the interface. A cohesive powder moves by intermittent avalanches: its interface jumps.
//
// Per sample, the interface is found on a grid fixed in the laboratory frame (not in the frame of the bed's
// angle, which moves with it): the drum section is cut into vertical columns of width w = column_width x d
// (d: number-mean diameter) spanning the whole axial extent L of the bed, and a column's interface height is
// the median y of its N = max(1, round(w L / d²)) highest particle centres (one monolayer's worth, as in
// surface.h); NaN when the column holds fewer than N particles. Over the window, a column counts when it has
// a height in at least `coverage` of the samples; the chord is the span of the counted columns and the
// columns whose centre lies in its central `central_fraction` are averaged:
//   cohesive_index_m = mean over those columns of the standard deviation (over the samples) of their height.
// NaN when fewer than 3 samples or no column qualifies.
#pragma once

#include <vector>

#include "wetdem/state.h"

namespace wetdem::observe {

struct InterfaceOptions {
  double column_width = 2.0;      // in mean diameters
  double coverage = 0.9;          // fraction of the window's samples a column must have a height in
  double central_fraction = 0.6;  // of the chord
};

// The interface heights (m) of one sample on the fixed grid of columns centred at x_k = -R + (k + 1/2) w,
// k = 0 .. floor(2R / w) - 1, with w from the state's own mean diameter. NaN where a column is not full.
std::vector<double> interface_profile(const SystemState& s, double drum_radius, double bed_length,
                                      const InterfaceOptions& opt = {});

// The window's cohesive index (m) from the profiles of its samples (all on the same grid).
double interface_fluctuation(const std::vector<std::vector<double>>& profiles,
                             const InterfaceOptions& opt = {});

}  // namespace wetdem::observe
