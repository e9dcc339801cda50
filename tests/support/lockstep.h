// The twin tests' lockstep: both backends take one step from the same state (the reference's state after the
// previous step), so that differences cannot accumulate and a failure names the step where they appear.
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "reference/reference.h"
#include "wetdem/state.h"
#include "wetdem/system.h"

namespace wetdem::test {

struct StepPair {
  SystemState ref, gpu;  // each backend's state after the step
};

// Uploads s to both backends, steps each once and downloads both.
StepPair step_both(ref::ReferenceSystem& ref_sys, System& gpu_sys, const SystemState& s);

// The pairs that hold a bridge or a flag, as (id_i, id_j, volume, flags) in stored order: both backends store
// the owner entries in canonical order, so the lists compare exactly (pairs with only springs are compared
// through the forces).
using BridgeRow = std::tuple<uint32_t, uint32_t, int64_t, uint32_t>;
std::vector<BridgeRow> bridges_and_flags(const SystemState& s);

}  // namespace wetdem::test
