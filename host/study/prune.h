// `wetdem study prune DIR`: what a run store holds, and the removal of the runs this binary never reuses.
//
// A store keeps every run it ever completed (store.h), and a run is found by a hash that holds the run
// version (study_file.h: a change to the code that decides what a run computes makes new hashes). Runs of
// another version stay on disk, reused only by the binaries that made them: a diagnosis store that followed
// the code for a few weeks held 900 runs, most of them never to be read again. The census groups the complete
// runs by the run version their summary.json records (since 7 Dec 2026; older summaries have none and count
// as another version); prune removes those not of this binary's version, with their cases/<hash>.toml. Runs
// without a summary (partial, resumable, failed) are left alone: their version is not recorded, and one may
// be this binary's to resume.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "wetdem/version.h"

namespace wetdem::study {

struct StoreCensus {
  struct Group {
    size_t runs = 0;
    uint64_t bytes = 0;
  };
  std::string version;                 // the run version counted as current
  Group current;                       // complete, made by that version: reused
  std::map<std::string, Group> other;  // complete, another run version recorded: never reused by this binary
  Group unrecorded;                    // complete, no run version recorded (summaries of older binaries)
  Group incomplete;                    // no summary.json: partial, resumable, interrupted or failed (kept)
  std::vector<std::string> removable;  // hashes of the complete runs not of `version` (sorted)
};

// Reads DIR/runs/*/summary.json. Throws StudyError when DIR has no runs/ folder (not a store).
StoreCensus take_census(const std::string& dir, const std::string& version = run_version());

// What the census found, one line per group, with sizes ("  312 runs, 29.1 MB: this binary's run version
// ...").
std::string describe_census(const StoreCensus& c);

// Removes the census's removable runs (DIR/runs/<hash>/ and DIR/cases/<hash>.toml) under the store's lock;
// returns the bytes freed. The census must be of DIR, taken under the same lock or with no run going on.
uint64_t prune_runs(const std::string& dir, const StoreCensus& c);

}  // namespace wetdem::study
