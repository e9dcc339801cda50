// The CPU reference: a short, serial, double-precision implementation of one wetdem step, written
// independently of the GPU kernels (own neighbour search, own history carry-over, own integration, own
// liquid events). Tests hold the GPU system to it. Formulas: ../shared/spec/physics.md (§N).
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "wetdem/observables.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::ref {

// Result of one contact evaluation (for analytic tests): force on i, torques on i and j.
struct PairForce {
  glm::dvec3 force{0.0};
  glm::dvec3 torque_i{0.0}, torque_j{0.0};
  double overlap = 0.0;
  double normal_force = 0.0;  // F_n of §1 (signed, unclipped), 0 when not touching
};

class ReferenceSystem {
 public:
  explicit ReferenceSystem(const SimParams& prm);

  // Takes particles, pair and wall records, time; when liquid is on, applies the §5 events of the state as
  // given (touching pairs bridge at t = 0, as MercuryDPM's initialiseSolve does).
  void set_state(const SystemState& s);
  SystemState state() const;  // canonical (sorted, no empty records)

  // One velocity-Verlet step (§0): half kick, drift, forces at x^{n+1}, half kick, liquid events (§5,
  // two-phase rule), time += dt.
  void step();

  // Forces/torques computed by the last step (same as state().p.f / .t), stable-id order.
  const std::vector<glm::dvec3>& forces() const;
  const std::vector<glm::dvec3>& torques() const;

  EventCounts read_events();
  const SimParams& params() const;
  // Replaces the physics between steps (the drum starts turning), as System::set_run_params.
  void set_params(const SimParams& prm) { prm_ = prm; }

  // Liquid-event rule switch for tests: the MercuryDPM-style sequential rule (events applied one pair
  // after another in (id_i, id_j) order, walls after pairs) instead of the two-phase rule.
  void set_sequential_events(bool on);

  // Investigations (issue 22, docs/closed-slice.md): store some fields as the GPU passes do, in float32,
  // rounding them after every half kick (velocities, angular velocities) or at the end of every step (pair
  // and wall springs). Off by default; the reference is double precision everywhere.
  enum RoundField : uint32_t { kRoundVelocities = 1u, kRoundSprings = 2u };
  void set_float32_storage(uint32_t fields) { round_ = fields; }

 private:
  using PairKey = std::pair<uint32_t, uint32_t>;  // (id_i, id_j), id_i < id_j

  void kick(double half_dt);                            // §0 half kick with the stored F, T and gravity
  void drift();                                         // §0 x += dt v, periodic wrap of z
  void compute_forces();                                // §1-4 at the current x, all pairs and walls
  void liquid_events(bool sinks = true);                // §5 at the end of the step (sinks: per step only)
  void events_at_rest();                                // §5 at set_state, on the positions as given
  std::vector<PairKey> touching_pairs() const;          // pairs with delta >= 0 (sweep along x)
  glm::dvec3 separation(uint32_t i, uint32_t j) const;  // x_i - x_j, minimum image in periodic z

  SimParams prm_;
  ParticleArrays p_;
  std::map<PairKey, PairRecord> pairs_;  // persistent pair history by stable ids
  std::vector<double> pair_gap_;         // gap S of each examined pair at the last force pass
  std::vector<PairKey> examined_;        // pairs examined at the last force pass, sorted
  std::vector<double> wall_gap_;         // gap S per particle and wall (+inf when absent)
  double time_ = 0.0;
  uint64_t step_ = 0;
  bool sequential_ = false;
  uint32_t round_ = 0;  // RoundField bits
  EventCounts events_;
};

}  // namespace wetdem::ref
