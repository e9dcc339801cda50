// One drum run on a device, as parts a driver calls: the System in its phase (settle: drum at rest; rotate:
// the drum turns), the step counter, the samples taken so far. run_case drives it with files and progress;
// studies and ensembles drive the same parts. Files are not its business (see outputs.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/output/checkpoint.h"
#include "app/output/summary.h"
#include "app/run/run.h"
#include "app/run/schedule.h"
#include "wetdem/system.h"

namespace wetdem::app {

// The run's parameters in its phase: settling with the drum at rest, or turning.
SimParams phase_params(const SimParams& prm, bool rotating);

class DrumSession {
 public:
  using LogFn = std::function<void(const std::string&)>;
  // Fresh: the prepared state is uploaded at step 0, the drum at rest while settling.
  DrumSession(vk::Context& ctx, const Prepared& prep, LogFn log);
  // Resumed from a checkpoint written by checkpoint(): continues bitwise on the same device.
  DrumSession(vk::Context& ctx, const Prepared& prep, const Checkpoint& ck, LogFn log);

  const Schedule& schedule() const { return sch_; }
  uint64_t step() const { return step_; }
  double time() const { return double(step_) * prep_.derived.dt; }
  bool rotating() const { return sch_.rotating(step_); }
  bool done() const { return step_ >= sch_.total; }
  // Liquid in the bed when the run started (units); the conservation check compares with it.
  int64_t liquid_start() const { return liquid_start_; }
  System& system() { return *sys_; }

  // Phases "settle" and "rotate": steps to `to` (at most schedule().next_stop(step())); at n_settle the
  // drum starts turning (the state moves whole to a system with the turning drum: exact).
  void advance(uint64_t to);
  // Phase "sample": downloads the bed, checks its health (throws std::runtime_error on a blow-up, lost
  // bridges or escaped particles), appends and returns the sample.
  const Sample& sample();
  const std::vector<Sample>& samples() const { return samples_; }
  // The state at the current step (time and step set).
  SystemState state();
  // Everything needed to continue, plus `extra` host fields (wall time, ...).
  Checkpoint checkpoint(const nlohmann::json& extra) const;
  // Filled from the checkpoint on resume: what the driver stored in `extra`.
  const nlohmann::json& resumed_host() const { return resumed_host_; }

 private:
  void make_system(bool rotating);
  vk::Context& ctx_;
  const Prepared& prep_;
  LogFn log_;
  Schedule sch_;
  SystemOptions so_;
  std::unique_ptr<System> sys_;
  uint64_t step_ = 0;
  int64_t liquid_start_ = 0;
  std::vector<Sample> samples_;
  bool dt_warned_ = false;
  nlohmann::json resumed_host_;
};

}  // namespace wetdem::app
