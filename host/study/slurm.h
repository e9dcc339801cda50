// `wetdem study slurm`: a Slurm job array with one task per missing run; each task runs
// `wetdem study run-one DIR --index $SLURM_ARRAY_TASK_ID`, which depends on no other task. With --batch K
// (issue 19): one task per batch of up to K runs (plan_batches, the batches `study run --batch K` steps),
// each running `wetdem study run-batch DIR --index i,j,k` as one ensemble; a batch stopped with a checkpoint
// (the task's time limit: Slurm's SIGTERM makes it write one) is a task of its own and resumes.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace wetdem::study {

struct SlurmOptions {
  std::string partition;      // --partition (empty: the cluster's default)
  std::string time;           // --time per task, e.g. "02:00:00" (empty: the partition's default)
  int gpus_per_task = 0;      // --gpus-per-task (0: not requested, e.g. CPU/lavapipe nodes)
  int max_parallel = 0;       // %K throttle of the array (0: none)
  std::string device;         // passed to run-one --device
  std::string exe;            // the wetdem binary the tasks run (default: this one)
  bool retry_failed = false;  // include runs whose FAILED.txt is not an interruption
  size_t batch = 1;           // > 1: one task per batch of up to this many runs (run-batch, ensembles)
};

struct SlurmScript {
  std::string path;             // DIR/slurm/study.sbatch
  std::vector<size_t> indices;  // the array's task ids (missing runs; with batches: 0..batches-1)
  std::vector<std::vector<size_t>> batches;  // with --batch: the runs of each task
  std::string sbatch_line;                   // the command that submits it
};

// "0-3,7,9-10" from sorted indices.
std::string array_spec(const std::vector<size_t>& idx);

// Writes DIR/slurm/study.sbatch for the runs of DIR/index.json that are not complete. indices is empty (and
// no script is written) when every run is complete.
SlurmScript write_slurm(const std::string& dir, const SlurmOptions& opt);

// Runs sbatch --parsable on the script; returns the job id. Throws std::runtime_error.
std::string submit_slurm(const SlurmScript& s);

}  // namespace wetdem::study
