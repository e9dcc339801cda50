// Ensembles of drum runs (docs/ensembles.md): several prepared runs stepped together in one System, each
// bitwise the run done alone (System's ensemble constructor), each with its own samples and run folder.
// DrumEnsemble holds the phases (settle, rotate, sample) for all runs; run_batch is the driver that writes
// each run's folder exactly as run_case would (no checkpoints: a failed batch is run again).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/output/summary.h"
#include "app/run/run.h"
#include "app/run/schedule.h"
#include "wetdem/system.h"

namespace wetdem::app {

class DrumEnsemble {
 public:
  using LogFn = std::function<void(size_t run, const std::string&)>;
  // Throws CaseError naming the key when the runs cannot be stepped together: they must share dt, the drum
  // (diameter, length, slice or plates) and the schedule (settle, duration, sample and snapshot intervals).
  DrumEnsemble(vk::Context& ctx, std::vector<const Prepared*> runs, LogFn log);

  size_t size() const { return runs_.size(); }
  const Schedule& schedule() const { return sch_; }
  uint64_t step() const { return step_; }
  double time() const;
  bool rotating() const { return sch_.rotating(step_); }
  bool done() const { return step_ >= sch_.total; }
  int64_t liquid_start(size_t r) const { return liquid_start_[r]; }
  System& system() { return *sys_; }

  // Steps every run to `to` (at most schedule().next_stop(step())); at n_settle every drum starts turning.
  void advance(uint64_t to);
  // Samples every run (one download); throws std::runtime_error if any run is unhealthy.
  void sample();
  const std::vector<Sample>& samples(size_t r) const { return samples_[r]; }
  // Every run's state at the current step (time and step set).
  std::vector<SystemState> states();

 private:
  std::vector<const Prepared*> runs_;
  LogFn log_;
  Schedule sch_;
  std::unique_ptr<System> sys_;
  uint64_t step_ = 0;
  std::vector<int64_t> liquid_start_;
  std::vector<std::vector<Sample>> samples_;
  std::vector<char> dt_warned_;
};

// Runs the cases of `opts` (fresh runs: case_path and out_dir set; no resume, no stop_after_steps) as one
// ensemble. Every input is checked before any folder is made (CaseError). A failure fails every run of the
// batch (FAILED.txt in each folder, no summary.json) and throws std::runtime_error. Each summary.json is
// what run_case writes (final_state_hash included) plus "ensemble": {runs, index, particle_steps_per_s}.
std::vector<RunResult> run_batch(const std::vector<RunOptions>& opts, vk::Context& ctx);

}  // namespace wetdem::app
