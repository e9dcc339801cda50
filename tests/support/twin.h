// Helpers for twin tests (GPU vs CPU reference on one state): random drum packings and norm-scaled
// comparisons of per-particle vectors.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <random>
#include <vector>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::test {

// A drum (radius R, length L, plates rotating) with a realistic reduced-stiffness material (E*, G* of
// polypropylene divided by 1000), friction, rolling resistance and gravity; dt = 0.2 Rayleigh time.
SimParams twin_drum_params(double radius, double length, double r_min, bool periodic);

// n particles of radius in [r_lo, r_hi] on a jittered cubic lattice of spacing 0.99 (r_lo + r_hi), filled
// from the bottom of the drum, so that about half the neighbours overlap, with random velocities and spins.
// Some touch the cylinder and the plates.
SystemState random_drum_packing(const SimParams& prm, size_t n, double r_lo, double r_hi, uint64_t seed,
                                double speed = 0.02);

// Rounds positions and radii to whole multiples of the GPU's tick so that both backends see the same
// geometry (the device stores positions in fixed point).
void quantize(SystemState& s, double tick);

// max_k |a_k - b_k| / scale, scale = max(max_k |b_k|, tiny): the norm-scaled error of a per-particle field.
double norm_scaled_error(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b);

}  // namespace wetdem::test
