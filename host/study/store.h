// The run store of a study directory DIR:
//   DIR/study.toml          copy of the study file (what was asked)
//   DIR/index.json          every run: index, point, axis values (as written and SI), seed, hash, run folder
//   DIR/cases/<hash>.toml   the resolved case of each run (SI); run-one runs exactly this file
//   DIR/runs/<hash>/        a normal run folder (summary.json once complete)
//   DIR/logs/run-<i>.log    stdout/stderr of the run's process
// A run is identified by its hash, so runs survive edits of the study file: a complete run is never
// recomputed, whatever index it has in the current plan.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "study/study_file.h"

namespace wetdem::study {

struct IndexEntry {
  size_t index = 0, point = 0;
  uint64_t seed = 0;
  std::string hash;
  std::vector<AxisValue> values;
  std::string run_dir;    // relative to DIR: runs/<hash>
  std::string case_file;  // relative to DIR: cases/<hash>.toml
};

struct StudyIndex {
  std::string name, study_file, base, code_version;
  std::vector<std::string> axis_keys;  // every key that varies over points, first-seen order
  std::vector<std::string> fit;        // observations.fit
  std::string observations;            // absolute path of the observation table, or ""
  std::vector<IndexEntry> runs;
  size_t points = 0;
};

// Writes DIR/study.toml, DIR/cases/*.toml and DIR/index.json (atomically) for the planned runs.
StudyIndex write_plan(const std::string& dir, const StudySpec& s, const std::vector<PlannedRun>& runs);
StudyIndex read_index(const std::string& dir);  // throws StudyError when DIR holds no study
nlohmann::json index_to_json(const StudyIndex& ix);

// Exclusive use of a store while its plan is written and run: index.json is the plan the run-one processes
// read by index, so two processes planning into one store at once (two diagnoses sharing --store, a twin
// beside a diagnosis) would run each other's runs and find their own missing. An advisory flock on
// DIR/.lock, held from construction to destruction (close-on-exec: the run-one children do not hold it); a
// second process waits, saying so once on stderr. Released by the kernel if the holder dies.
class StoreLock {
 public:
  explicit StoreLock(const std::string& dir);
  ~StoreLock();
  StoreLock(const StoreLock&) = delete;
  StoreLock& operator=(const StoreLock&) = delete;

 private:
  int fd_ = -1;
};

enum class RunState { Missing, Partial, Resumable, Interrupted, Failed, Complete };
const char* state_name(RunState s);
// Partial: a folder without summary or checkpoint (killed before its first checkpoint): restarts fresh.
// Resumable: checkpoint (its own, or its batch's: app/run/ensemble.h), no summary (stopped); Interrupted:
// FAILED.txt saying "interrupted" + checkpoint; Failed: FAILED.txt with another reason (in *reason).
// Complete: summary.json.
RunState run_state(const std::string& run_dir, std::string* reason = nullptr);

}  // namespace wetdem::study
