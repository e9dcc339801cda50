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

  void set_state(const SystemState& s);  // takes particles, pair and wall records, time
  SystemState state() const;             // canonical (sorted, no empty records)

  // One velocity-Verlet step (§0): half kick, drift, forces at x^{n+1}, half kick, liquid events (§5,
  // two-phase rule), time += dt.
  void step();

  // Forces/torques computed by the last step (same as state().p.f / .t), stable-id order.
  const std::vector<glm::dvec3>& forces() const;
  const std::vector<glm::dvec3>& torques() const;

  EventCounts read_events();
  const SimParams& params() const;

  // Liquid-event rule switch for tests: the MercuryDPM-style sequential rule (events applied one pair
  // after another in (id_i, id_j) order, walls after pairs) instead of the two-phase rule.
  void set_sequential_events(bool on);
};

}  // namespace wetdem::ref
