// Liquid events of the CPU reference (§5 of ../shared/spec/physics.md): rupture, migration and
// formation of liquid bridges at the end of a step, on integer volumes (liquid units) so that
// Σ films + Σ bridges is conserved exactly. Two rules: the deterministic two-phase rule of §5
// "Simultaneous events" (what wetdem runs), and the MercuryDPM-style sequential rule (tests only).
#pragma once

#include <cstdint>
#include <vector>

#include "wetdem/observables.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::ref {

// Integer proportional split, bit-identical on every device (ARCHITECTURE.md "Liquid"):
//   q      = (a << 16) / (a + b)                                   (uint64; a, b >= 0, a + b > 0, a < 2^47)
//   part_a = (V >> 16) * q + (((V & 0xFFFF) * q) >> 16)            (~ V a / (a + b), rounded down)
//   part_a clamped to [max(0, V - b_cap), min(V, a_cap)]           (neither side gives/takes beyond its cap)
// Returns part_a; the caller gives part_b = V - part_a to the other side. V = 0 or a + b = 0 gives 0.
int64_t split_proportional(int64_t V, int64_t a, int64_t b, int64_t a_cap, int64_t b_cap);

// §5 "d_c h" as an integer: the part of a received volume h that a particle shares over its bridges
// (floor(h q / 65536) with q = round(65536 d_c), the same integer on every device); the rest stays in its
// film.
int64_t distribution_give(int64_t h, double d_c);

// One particle pair examined in the step: stable ids i < j, surface gap S at the end of the step, its record.
struct PairSlot {
  uint32_t i = 0, j = 0;
  double gap = 0.0;
  PairRecord* rec = nullptr;
};

// What the event pass reads and writes. Pairs must be sorted by (i, j) and hold every pair that touches
// (delta >= 0) or has a record; wall_gap[k * kNumWalls + w] is +infinity for a wall that is absent.
struct LiquidView {
  const SimParams* prm = nullptr;
  std::vector<int64_t>* film = nullptr;
  std::vector<WallRecord>* wall = nullptr;
  std::vector<PairSlot> pairs;
  std::vector<double> wall_gap;
  // Liquid sinks (params.h LiquidSinkParams); may be null when the sinks are off.
  std::vector<int64_t>* pore = nullptr;
  std::vector<int64_t>* evaporated = nullptr;
  const std::vector<double>* radius = nullptr;  // for the pore capacity
  bool sinks = true;  // false for the events at upload: the sinks act per step (over dt), not at rest
};

// The liquid sinks on the films after the rupture phase (what the two-phase rule runs between its phases):
// each particle moves min(floor(V_f a_k), capacity - pore) (all of V_f when instantaneous) into its pores;
// then films, pair bridges (credited to the lower id) and wall bridges lose floor(V e_t) to `evaporated`.
void liquid_sinks(LiquidView& view);

// §5 two-phase rule: ruptures (received halves summed per particle, then shared), then formations.
EventCounts liquid_events_two_phase(LiquidView& view);
// MercuryDPM-style rule: each pair in (i, j) order, then each particle's walls in (id, wall) order, applies
// rupture / formation immediately on the current films and bridges.
EventCounts liquid_events_sequential(LiquidView& view);

}  // namespace wetdem::ref
