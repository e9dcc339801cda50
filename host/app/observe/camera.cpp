#include "app/observe/camera.h"

#include <cmath>

#include "app/observe/clusters.h"
#include "app/observe/segregation.h"
#include "app/observe/slabs.h"
#include "app/observe/surface.h"

namespace wetdem::observe {

int64_t free_liquid(const SystemState& s) {
  const LiquidBudget b = s.liquid_budget();
  return b.films + b.bridges;  // pair and wall bridges; pores and evaporated liquid are not free
}

CameraSample observe_camera(const SystemState& s, const SimParams& prm, int64_t liquid_start) {
  return observe_camera(s, prm, liquid_start, free_liquid(s));
}

CameraSample observe_camera(const SystemState& s, const SimParams& prm, int64_t liquid_start,
                            int64_t free_liquid_units) {
  CameraSample c;
  const SurfaceResult sf = fit_surface(s, prm.drum.radius, prm.drum.length);
  if (sf.valid) {
    // Reported in the sense of the bed's tilt: |α| whenever the surface leans the way the bed does.
    c.aor_surface_deg = sf.com_angle_deg >= 0 ? sf.angle_deg : -sf.angle_deg;
    c.surface_velocity_mps = sf.downhill_speed_mps;
    c.flowing_layer_depth_m = sf.flowing_layer_depth_m;
    c.surface_size_ratio = surface_size_ratio(s, sf);
    c.surface_agglomerate_size = surface_cluster_size(s, sf.layer);
  }
  const SlabAor sl = slab_aor(s, prm.drum);
  if (sl.present) {
    c.aor_plate_deg = sl.plate_deg();
    c.aor_centre_deg = sl.centre_abs_deg();
  }
  const Clusters cl = bridge_clusters(s);
  if (cl.count > 0) {
    c.agglomerate_size_mean = cl.size_mean;
    c.drum_to_agglomerate_ratio = 2.0 * prm.drum.radius / cl.equivalent_diameter_m;
  }
  if (liquid_start > 0)
    c.liquid_free_fraction = static_cast<double>(free_liquid_units) / static_cast<double>(liquid_start);
  return c;
}

}  // namespace wetdem::observe
