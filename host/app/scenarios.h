// Ready-made systems shared by tests and benchmarks (not used by case files).
#pragma once

#include <cstdint>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

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
