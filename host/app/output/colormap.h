// What the snapshot writers (glTF, VTK) receive, and the liquid colour map of the paper's snapshots.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "wetdem/state.h"

namespace wetdem {

// One frame of particles, in the drum frame (x, y up, z along the axis), SI units.
struct ParticleFrame {
  double time = 0.0;  // s
  uint64_t step = 0;
  std::vector<glm::dvec3> x;   // centre (m)
  std::vector<glm::dvec3> v;   // velocity (m/s); may be empty (written as zeros)
  std::vector<double> radius;  // m
  std::vector<double>
      liquid_m3;  // liquid per particle (m³), physics.md §5: V_f + Σ V_b/2 + Σ wall V_b; may be empty
  std::vector<uint32_t> id;  // stable ids; may be empty (0..n-1)
  // Agglomerate of each particle (app/observe/clusters.h): label = smallest stable id of its bridge cluster,
  // and the cluster's particle count; both may be empty (not written).
  std::vector<uint32_t> cluster, cluster_size;
  size_t size() const { return x.size(); }
};

// Frame from a downloaded state (stable-id order, so id = index), with the bridge clusters of its pair
// records. liquid_m3: liquid per particle in m³ (liquid_per_particle(s) × SimParams::liquid_unit_m3), or
// empty.
ParticleFrame frame_from_state(const SystemState& s, const std::vector<double>& liquid_m3);

// sRGB (0..1, as in colour pickers) to the linear RGB that glTF COLOR_0 and shading expect (IEC 61966-2-1).
double srgb_to_linear(double c);

// Liquid colour: white (dry, value ≤ 0) through light blue to dark blue at value ≥ vmax, as the paper's
// snapshots. Stops are ColorBrewer "Blues" (#ffffff, #c6dbef, #6baed6, #2171b5, #08306b) at 0, ¼, ½, ¾, 1 of
// vmax, interpolated linearly in sRGB. Returned in sRGB (for VTK/ParaView) or linear RGB (for glTF).
// vmax ≤ 0: every particle is white.
glm::dvec3 liquid_color_srgb(double value, double vmax);
glm::dvec3 liquid_color_linear(double value, double vmax);

}  // namespace wetdem
