// Ready-made systems shared by tests and benchmarks (not used by case files).
#pragma once

#include <cstdint>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

// The paper's polypropylene contact set on every interaction (particle-particle and all walls): E = 1325 MPa,
// G = 400 MPa reduced 1000-fold (nu = 0.656, accepted as in the paper, physics.md §1), e = 0.5, the given
// friction; dt = 0.2 Rayleigh time of the smallest particle (radius r_min, density rho), physics.md §6.
void set_polypropylene_contacts(SimParams& prm, double mu_s, double mu_r, double r_min, double rho = 900.0);

struct Scenario {
  SimParams prm;
  SystemState state;
};

// A wet packing agitated in a fast-turning periodic slice of a small drum: random initial velocities of up to
// `speed` m/s, particle-particle and cylinder bridges with V_min = 0 and a small V_max (short rupture
// distance), so that bridges form and rupture every step (the liquid-conservation soak of physics.md §7.8).
// `n` particles of 0.9-1.1 mm radius; films of 2 % of each particle's volume.
Scenario tumbling_wet_slice(size_t n, uint64_t seed, double speed = 1.5);

}  // namespace wetdem
