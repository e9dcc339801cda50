// Initial fill of the drum: non-overlapping spheres inside the cylinder (radius R about +z, centred at the
// origin, end plates at z = ±L/2, or a periodic slice of period L), by random sequential addition.
//
// Method. Particles are placed largest first (sorting by size lets the small ones fill the gaps) at uniformly
// random centres inside the insertion region, each tried until it overlaps no placed particle and no wall.
// The insertion region is the part of the drum below a height y_top chosen so that the region's volume times
// `loose_fraction` equals the particles' volume (a loose packing that random addition reaches quickly; the
// bed then settles under gravity to ~0.6). When a particle fails `max_attempts` times, y_top is raised (the
// region grows by 5 %) and insertion goes on; a failure with the whole drum as region throws
// std::runtime_error. Overlap checks use a uniform cell grid (cell ≈ median diameter) in which each particle
// is registered in every cell its bounding box touches, so a query visits only the cells the candidate's box
// touches: O(1) per try whatever the size ratio. Periodic slices use the minimum image in z. Deterministic:
// the same radii, spec and seed give bitwise the same positions.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "psd.h"
#include "wetdem/params.h"

namespace wetdem {

struct FillSpec {
  double drum_radius = 0.07;  // R (m)
  double drum_length = 0.18;  // L (m): between the end plates, or the period of a periodic slice
  bool periodic_z = false;
  // Particle count: if count > 0, exactly `count` particles; otherwise particles are drawn from the PSD until
  // their solid volume reaches bed_fraction × V_drum × solid_fraction (V_drum = π R² L).
  size_t count = 0;
  double bed_fraction = 0.4;    // bed volume / drum volume (used when count == 0)
  double solid_fraction = 0.6;  // solid volume / bed volume of the settled bed
  bool lower_part = true;       // true: insert in the lowest part of the drum; false: anywhere in the drum
  double loose_fraction = 0.3;  // packing of the insertion region (lower_part); must be in (0, 0.45]
  double wall_gap = 0.0;        // clearance kept from walls and between particles (m)
  uint32_t max_attempts = 200;  // failed tries of one particle before the region grows
  uint64_t seed = 1;
};

struct FillResult {
  std::vector<glm::dvec3> x;   // centres (m), drum frame (y up, z along the axis)
  std::vector<double> radius;  // radii (m), in the same order (the order of the input radii / PSD draws)
  double y_top = 0.0;          // final top of the insertion region (m)
  double solid_volume = 0.0;   // Σ (4/3) π r³ (m³)
  size_t region_growths = 0;   // times the region had to be raised
};

// π R² L.
double drum_volume(double radius, double length);
inline double drum_volume(const DrumParams& d) {
  return drum_volume(d.radius, d.length);
}

// Particle count of a bed filling `bed_fraction` of the drum at `solid_fraction`, from the PSD's V̄_S:
// N = round(bed_fraction × V_drum × solid_fraction / V̄_S). And its inverse (the bed fraction N particles
// fill).
size_t particles_for_fill(const Psd& psd, double drum_radius, double drum_length, double bed_fraction,
                          double solid_fraction = 0.6);
double fill_for_particles(const Psd& psd, double drum_radius, double drum_length, size_t count,
                          double solid_fraction = 0.6);

// Places the given radii (m). Throws std::invalid_argument for radii that cannot fit (2r > R or, with end
// plates, 2r > L) or a bad spec, std::runtime_error when the drum is too full for random addition.
FillResult fill_drum(const FillSpec& spec, const std::vector<double>& radii);
// Draws diameters from the PSD (std::mt19937_64 seeded from spec.seed; count or bed_fraction decides how
// many) and places them.
FillResult fill_drum(const FillSpec& spec, const Psd& psd);

// Checks (for tests and for the run driver's sanity check): the largest overlap between two particles (m, ≤ 0
// when none touch; cell grid, not O(N²)), and the largest protrusion of a particle through a wall (m, ≤ 0
// when all are inside).
double max_pair_overlap(const std::vector<glm::dvec3>& x, const std::vector<double>& radius,
                        double drum_length, bool periodic_z);
double max_wall_overlap(const std::vector<glm::dvec3>& x, const std::vector<double>& radius,
                        double drum_radius, double drum_length, bool periodic_z);

}  // namespace wetdem
