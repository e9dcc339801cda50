// Observables computed from a downloaded state (either backend), §5 "Reported quantities".
#pragma once

#include <cstdint>
#include <vector>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

struct Observables {
  uint64_t contacts = 0;          // touching particle pairs, overlap > 0
  uint64_t bridges = 0;           // particle pairs with V_b > 0, touching or not
  uint64_t wet_or_touching = 0;   // |touching ∪ bridged| particle pairs
  double f_wet = 0.0;             // bridges / |touching ∪ bridged| (0 when the union is empty)
  uint64_t wall_contacts = 0;     // touching particle-wall contacts
  uint64_t wall_bridges = 0;      // particle-wall bridges
  double max_overlap = 0.0;       // largest particle-particle or particle-wall overlap (m)
  double kinetic_energy = 0.0;    // translational + rotational (J)
  int64_t liquid_films = 0;       // Σ V_f (units)
  int64_t liquid_bridges = 0;     // Σ V_b over pair and wall bridges (units)
  int64_t liquid_pores = 0;       // Σ pore liquid (units), absorption
  int64_t liquid_evaporated = 0;  // Σ evaporated (units)
  glm::dvec3 com{0.0};            // centre of mass (m)
};

// Definition string written next to f_wet in every output.
inline constexpr const char* kFwetDefinition =
    "f_wet = bridged particle pairs / (touching particle pairs ∪ bridged particle pairs)";

// Touching pairs are found by brute-force-free cell search over the state's positions.
Observables compute_observables(const SystemState& s, const SimParams& prm);

// Liquid per particle (units): V_f + Σ particle bridges V_b/2 + Σ wall bridges V_b, §5.
std::vector<double> liquid_per_particle(const SystemState& s);

// Count of liquid events since the counter was last read.
struct EventCounts {
  uint64_t formations = 0, ruptures = 0;
};

}  // namespace wetdem
