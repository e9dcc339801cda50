// Host-side image of a system's full dynamic state, in stable-id order, double precision.
// The GPU system and the CPU reference both read and write it: it is how tests put the same
// state into both backends, how checkpoints are written, and how results are downloaded.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "wetdem/params.h"

namespace wetdem {

// Flag bits of a pair or wall record.
enum ContactFlags : uint32_t {
  kFlagWasInContact = 1u << 0,  // §5: set on first touch, cleared on rupture or on separation without bridge
};

// Persistent state of one particle pair (id_i < id_j). A pair with all-zero state need not be stored.
struct PairRecord {
  uint32_t id_i = 0, id_j = 0;
  glm::dvec3 spring_t{0.0};  // tangential spring xi (m), §2
  glm::dvec3 spring_r{0.0};  // rolling spring xi_r (m), §3
  int64_t bridge = 0;        // bridge volume V_b (liquid units), §4
  uint32_t flags = 0;        // ContactFlags
  bool empty() const {
    return bridge == 0 && flags == 0 && spring_t == glm::dvec3(0.0) && spring_r == glm::dvec3(0.0);
  }
};

// Persistent state of one particle-wall contact (one per particle per wall).
struct WallRecord {
  glm::dvec3 spring_t{0.0};
  glm::dvec3 spring_r{0.0};
  int64_t bridge = 0;
  uint32_t flags = 0;
};

// Particles in stable-id order: index k holds the particle whose id is k.
struct ParticleArrays {
  std::vector<glm::dvec3> x, v, w;  // position (m), velocity (m/s), angular velocity (rad/s)
  std::vector<glm::dvec3> f, t;     // last computed force (N) and torque (N m), used by the next half kick
  std::vector<double> radius, mass, inertia;
  std::vector<int64_t> film;        // film volume V_f (liquid units)
  std::vector<int64_t> pore;        // liquid absorbed into the particle's pores (units); never bridges
  std::vector<int64_t> evaporated;  // liquid evaporated from its film and the bridges it owns (units)
  std::vector<WallRecord> wall;     // kNumWalls records per particle: wall[k * kNumWalls + w]

  size_t size() const { return x.size(); }
  void resize(size_t n);
};

// Where the liquid is (liquid units). films + bridges + pores + evaporated is conserved exactly.
struct LiquidBudget {
  int64_t films = 0, bridges = 0, pores = 0, evaporated = 0;  // bridges: pair and wall bridges
  int64_t total() const { return films + bridges + pores + evaporated; }
};

struct SystemState {
  ParticleArrays p;
  std::vector<PairRecord> pairs;  // sorted by (id_i, id_j), no empty records
  double time = 0.0;
  uint64_t step = 0;

  // Σ films + Σ pair bridges + Σ wall bridges + Σ pores + Σ evaporated (liquid units): conserved exactly
  // (§5).
  int64_t total_liquid() const;
  LiquidBudget liquid_budget() const;
  // Sorts pairs by (id_i, id_j) and drops empty records: the canonical form both backends produce.
  void canonicalize();
};

// Ensembles (docs/ensembles.md): several runs' states as one, run r's particle k getting the stable id
// (first id of run r) + k, and back. Times and steps are run 0's (runs stepped together share them).
SystemState concat_states(const std::vector<SystemState>& runs);
std::vector<SystemState> split_state(const SystemState& all, const std::vector<size_t>& sizes);

// Builds a particle of solid density rho (kg/m^3): mass and inertia (solid sphere, 2/5 m r^2).
void set_sphere(ParticleArrays& p, size_t k, glm::dvec3 x, double radius, double density);

}  // namespace wetdem
