// Runs a study's missing runs: each in its own process (`wetdem study run-one DIR --index i`, isolation: a
// crash or device loss fails one run), N at a time, with one progress line for the study. The same run-one is
// what a Slurm array task executes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "app/run/run.h"
#include "study/store.h"

namespace wetdem::study {

struct OneResult {
  bool skipped = false;    // already complete: nothing computed
  bool completed = false;  // summary.json written
  bool resumed = false;    // continued from a checkpoint
  std::string error;       // why it failed or stopped
};

// Runs run `index` of the study in DIR in this process: skips a complete run, resumes one with a checkpoint
// (a run stopped inside a batch resumes with its batch: run_batch_of), restarts a partial one. `configure`
// may adjust the RunOptions (tests: stop_after_steps, on_sample, context).
OneResult run_one(const std::string& dir, size_t index, const std::string& device, bool quiet,
                  const std::function<void(const IndexEntry&, app::RunOptions&)>& configure = {});

// Runs `indices` of the study in DIR in this process as ensembles (docs/ensembles.md): complete runs are
// skipped, runs with their own checkpoint resume alone (run_one), runs of a batch stopped with a checkpoint
// resume with that batch (all its runs, also those not in `indices`); the fresh ones are grouped by what an
// ensemble's runs must share (dt, drum, schedule) and each group is stepped together in one System
// (app::run_batch), each run bitwise what it computes alone. One result per index, in order.
std::vector<OneResult> run_batch_of(
    const std::string& dir, const std::vector<size_t>& indices, const std::string& device, bool quiet,
    const std::function<void(const IndexEntry&, app::RunOptions&)>& configure = {});

// How the runs `todo` (indices, in order) are handed out: first every batch stopped with a checkpoint (all
// its runs, in the order they were stepped: app/run/ensemble.h), then the others in batches of at most
// `batch`. With `jobs` > 1 processes at a time, the others are split evenly over a number of batches that is
// a multiple of `jobs` where there are runs enough, so that no process idles through a last round (12 runs,
// batch 4, 2 jobs: four batches of 3, not three of 4). Used by run_study and `study slurm --batch` (jobs 1)
// alike, so a cluster runs the same ensembles.
std::vector<std::vector<size_t>> plan_batches(const std::string& dir, const std::vector<size_t>& todo,
                                              size_t batch, size_t jobs = 1);

struct ExecOptions {
  int jobs = 1;
  size_t batch = 1;  // > 1: hand up to this many runs at a time to one process as ensembles (run_batch_of)
  std::string device;
  bool retry_failed = false;  // rerun runs whose FAILED.txt gives a reason other than an interruption
  bool quiet = false;         // no progress line
  // The wetdem binary for run processes; empty: run in this process, one at a time (tests).
  std::string exe;
  std::function<void(const IndexEntry&, app::RunOptions&)> configure;  // in-process runs only
};

struct ExecReport {
  size_t total = 0, already_complete = 0, skipped_failed = 0;
  size_t started = 0, completed = 0, failed = 0, stopped = 0;
  double wall_s = 0;                  // the whole `study run`
  double process_wall_s = 0;          // sum over started runs of their process (or run_one call) wall time
  double run_wall_s = 0;              // sum of wall_time_s in the summaries of the runs completed now
  std::vector<std::string> failures;  // "index hash: reason"
  bool interrupted = false;
};

ExecReport run_study(const std::string& dir, const ExecOptions& opt);

// Asks run_study to stop launching and to interrupt its running runs (async-signal-safe).
void request_study_interrupt();

// The path of the running executable (/proc/self/exe).
std::string self_exe();

}  // namespace wetdem::study
