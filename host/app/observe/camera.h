// The per-sample observables a camera sees (diagnosis.md §2), computed together from one downloaded state:
// surface angle, plate and centre slab AoR, surface downhill speed, flowing-layer depth, agglomerate size and
// D / agglomerate, free liquid, clumps on the surface. NaN marks a value that does not exist for this sample
// (bed flagged, no slab angle, no liquid put in); the plate and centre angles never exist on a periodic
// slice. Definitions: surface.h, slabs.h, clusters.h and docs/outputs.md ("Camera observables").
#pragma once

#include <cstdint>
#include <limits>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::observe {

struct CameraSample {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double aor_surface_deg = kNone;            // |α| of the fitted free surface (deg)
  double aor_plate_deg = kNone;              // |mean of the two plate slabs' signed AoR| (deg)
  double aor_centre_deg = kNone;             // |AoR of the central slab| (deg)
  double surface_velocity_mps = kNone;       // mean downhill speed of the surface layer (m/s)
  double flowing_layer_depth_m = kNone;      // depth of the sign change of the downhill velocity (m)
  double agglomerate_size_mean = kNone;      // mass-weighted mean particles per bridge cluster
  double drum_to_agglomerate_ratio = kNone;  // D / equivalent diameter of the mean cluster
  double liquid_free_fraction = kNone;       // (films + bridges) / liquid put in at the start
  double surface_size_ratio = kNone;         // mean radius of the surface layer / mean radius of the bed
  double surface_agglomerate_size = kNone;   // mass-weighted mean particles per clump on the free surface
};

// One row of the table of fields: name (the timeseries.csv column and summary.json key), member, and whether
// it needs end plates (absent on a periodic slice).
struct CameraField {
  const char* name;
  double CameraSample::*value;
  bool needs_plates;
};
inline constexpr CameraField kCameraFields[] = {
    {"aor_surface_deg", &CameraSample::aor_surface_deg, false},
    {"aor_plate_deg", &CameraSample::aor_plate_deg, true},
    {"aor_centre_deg", &CameraSample::aor_centre_deg, true},
    {"surface_velocity_mps", &CameraSample::surface_velocity_mps, false},
    {"flowing_layer_depth_m", &CameraSample::flowing_layer_depth_m, false},
    {"agglomerate_size_mean", &CameraSample::agglomerate_size_mean, false},
    {"drum_to_agglomerate_ratio", &CameraSample::drum_to_agglomerate_ratio, false},
    {"liquid_free_fraction", &CameraSample::liquid_free_fraction, false},
    {"surface_size_ratio", &CameraSample::surface_size_ratio, false},
    {"surface_agglomerate_size", &CameraSample::surface_agglomerate_size, false},
};

// liquid_start: liquid put in at the start (units); ≤ 0 leaves liquid_free_fraction NaN.
CameraSample observe_camera(const SystemState& s, const SimParams& prm, int64_t liquid_start);
// The same with the free liquid (films + pair and wall bridges, units) given: from the device's reductions
// (System::sample_runs), whose slim state has positions, velocities, radii, masses and bridged pairs only.
CameraSample observe_camera(const SystemState& s, const SimParams& prm, int64_t liquid_start,
                            int64_t free_liquid_units);

// Films + pair bridges + wall bridges (units): the liquid that is free to bridge (not in pores, not
// evaporated).
int64_t free_liquid(const SystemState& s);

}  // namespace wetdem::observe
