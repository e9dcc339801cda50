// Ensembles of drum runs (docs/ensembles.md): several prepared runs stepped together in one System, each
// bitwise the run done alone (System's ensemble constructor), each with its own samples and run folder.
// DrumEnsemble holds the phases (settle, rotate, sample, checkpoint) for all runs; run_batch is the driver
// that writes each run's folder exactly as run_case would.
//
// Checkpoints of a batch (issue 19): one for the whole ensemble, in its first run's folder,
// <run 0>/ensemble/checkpoint/ (system.bin: the System's snapshot; host.json: step, wall time and per run its
// folder relative to run 0's, samples so far, liquid at the start, fill hash, seed). Every run's folder holds
// ensemble.json naming run 0's folder and its own index. Written on the schedule of run 0's
// output.checkpoint_interval and when the batch is interrupted (SIGINT/SIGTERM: at the next step boundary),
// so a killed batch loses at most one checkpoint interval and a stopped one nothing; resumed on the same
// device it continues bitwise.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/output/checkpoint.h"
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
  // Resumed from checkpoint() (the same runs in the same order; run_batch checks their folders and fills).
  DrumEnsemble(vk::Context& ctx, std::vector<const Prepared*> runs, const Checkpoint& ck, LogFn log);

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
  // Everything needed to continue: the System's snapshot, the step, each run's samples and liquid at the
  // start, plus `extra` host fields and, per run, `member_extra[r]` (its folder, ...).
  Checkpoint checkpoint(const nlohmann::json& extra, const std::vector<nlohmann::json>& member_extra) const;

 private:
  vk::Context* ctx_ = nullptr;
  std::vector<const Prepared*> runs_;
  LogFn log_;
  Schedule sch_;
  std::unique_ptr<System> sys_;
  uint64_t step_ = 0;
  std::vector<int64_t> liquid_start_;
  std::vector<std::vector<Sample>> samples_;
  std::vector<char> dt_warned_;
  void make_system(const std::vector<SystemState>* states);
};

inline constexpr const char* kEnsembleDir = "ensemble";          // in run 0's folder: the batch's checkpoint
inline constexpr const char* kEnsembleMember = "ensemble.json";  // in every run's folder
// The folders of the batch whose checkpoint `run_dir` belongs to (run 0 first), read from that checkpoint;
// empty when the folder is no member of a batch with a checkpoint.
std::vector<std::string> ensemble_members(const std::string& run_dir);

// Runs the cases of `opts` as one ensemble: fresh runs (case_path and out_dir set), or a batch resumed from
// its checkpoint (every resume_dir set, the folders of ensemble_members in that order). stop_after_steps
// (tests) is opts[0]'s: the batch stops there with a checkpoint, as if killed, and its results are not
// completed. Every input is checked before any folder is made (CaseError). A failure fails every run of the
// batch (FAILED.txt in each folder, no summary.json; an interruption leaves "interrupted ..." there and a
// checkpoint to resume from) and throws std::runtime_error. Each summary.json is what run_case writes
// (final_state_hash included) plus "ensemble": {runs, index, particle_steps_per_s}.
std::vector<RunResult> run_batch(const std::vector<RunOptions>& opts, vk::Context& ctx);

}  // namespace wetdem::app
