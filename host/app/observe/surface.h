// The free surface as a camera sees it (diagnosis.md §2): its angle from a line fit over the central 60 % of
// the chord, the downhill speed of the surface layer, and the depth of the flowing layer. Pure functions of a
// downloaded state; drum frame of app/drum/aor.h (axis z, gravity -y, signed angle atan2(com_x, -com_y)).
//
// Frame of an angle a: tangent t(a) = (cos a, sin a), normal n(a) = (-sin a, cos a); u = x.t, h = x.n. For a
// bed displaced towards +x (signed AoR a > 0) n points from the bed towards the drum centre, so h grows
// towards the free space and a surface inclined at a is the line h = const.
//
// Surface points. The particles are binned along u into columns of width w = column_width x d (d: number-mean
// particle diameter), each column spanning the whole axial extent L of the bed. A column's surface layer is
// its N_mono = max(1, round(w L / d²)) highest particles (largest h: one monolayer's worth over the column's
// top area w x L); its surface point is (column centre, median h of that layer). The median ignores the few
// particles thrown above the bed. The chord is [u_min, u_max], the extent of the bed along u (particle
// surfaces included); columns whose centre lies in the central 60 % of it are fitted by ordinary least
// squares h = a + b u. Two passes: in the frame of the bed's centre-of-mass angle θ, then in the frame of the
// angle found, α = θ + atan(b) (the second pass removes the column tilt when the surface is not at θ).
#pragma once

#include <cstddef>
#include <vector>

#include "wetdem/state.h"

namespace wetdem::observe {

struct SurfaceOptions {
  double column_width = 2.0;      // column width in mean diameters
  double central_fraction = 0.6;  // fraction of the chord whose columns are fitted
  double depth_bin = 1.0;         // depth bin of the velocity profile, in mean diameters
  double flag_fraction = 0.2;     // as dynamic_aor: |COM| < 0.2 R gives no surface (NaN everywhere)
};

struct SurfaceResult {
  bool valid = false;          // false: bed flagged (near-centred or empty) or fewer than 3 fitted columns
  double angle_deg = 0.0;      // α, signed as the AoR (> 0: surface rising towards +x)
  double angle_se_deg = 0.0;   // OLS standard error of the slope of the last pass (deg), noise of one sample
  double com_angle_deg = 0.0;  // θ of the centre of mass, the first pass's frame
  double height_m = 0.0;       // signed distance of the fitted line from the drum axis along n(α)
  double mean_diameter_m = 0.0;  // d
  size_t columns = 0;            // columns fitted
  std::vector<size_t> layer;     // surface-layer particles (indices) of the fitted columns
  // Mean over the surface layer of v . (-s t(α)), s = sign(α) (+1 when α = 0): the downhill speed (m/s),
  // > 0 for a surface flowing down, < 0 for a bed carried up (rigid rotation with the drum).
  double downhill_speed_mps = 0.0;
  // Depth below the fitted surface at which the mean downhill velocity first changes sign from > 0 to ≤ 0,
  // on the band |u| < w/2 around the line through the drum axis normal to the surface (frame α), binned in
  // depth by depth_bin x d (the first bin also holds the particles above the line), interpolated linearly
  // between the mean depths of the two bins around the change. 0 when the top bin already flows uphill or
  // stands; NaN when the velocity never changes sign in the bed.
  double flowing_layer_depth_m = 0.0;
};

// Positions, velocities and radii of the state; drum_radius for the flag; bed_length L: axial extent of the
// bed (drum length, or the period of a slice).
SurfaceResult fit_surface(const SystemState& s, double drum_radius, double bed_length,
                          const SurfaceOptions& opt = {});

}  // namespace wetdem::observe
