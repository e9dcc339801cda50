// Phase "sample" of one drum run from its downloaded state: the observables, what a camera sees, the health
// checks. DrumSession (one run) and DrumEnsemble (many runs in one System) both call it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "app/output/summary.h"
#include "app/run/run.h"
#include "wetdem/state.h"
#include "wetdem/system.h"

namespace wetdem::app {

struct SampleContext {
  const Prepared* prep = nullptr;
  const SimParams* prm = nullptr;  // the run's current parameters (drum speed of its phase)
  uint64_t step = 0;
  double time = 0.0;
  int64_t liquid_start = 0;
  SystemCounters counters;  // of the System that holds the run
};

// Throws std::runtime_error on a blow-up (kinetic energy not finite), lost bridges or escaped particles.
// `dt_warned`: the capillary time-step warning is logged once per run.
// From what System::sample_runs brings back: the device's reductions and the slim state (what runs use).
Sample take_sample(const RunSample& rs, const SampleContext& x, bool& dt_warned,
                   const std::function<void(const std::string&)>& log);
// From a whole downloaded state, the reductions made on the host (compute_observables): the CPU reference of
// the above (tests compare the two).
Sample take_sample(const SystemState& st, const SampleContext& x, bool& dt_warned,
                   const std::function<void(const std::string&)>& log);

}  // namespace wetdem::app
