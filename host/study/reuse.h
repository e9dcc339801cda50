// `study plan|run --reuse OTHER`: runs of OTHER are copied when they have this study's hash, i.e. the same
// resolved case, seed and run version (study_file.h). A run of OTHER with the same case and seed but computed
// by another run version is not reused: the code that computes it changed. Saying so before any run matters
// where device time is short: the paper's extended stage recomputed four runs of its grid unawares (27 Nov
// 2026), and they came out bitwise the same. The check names the version that computed them, so that binaries
// of it can be built to reuse them (docs/paper.md).
#pragma once

#include <set>
#include <string>
#include <vector>

#include "study/study_file.h"

namespace wetdem::study {

struct OtherVersionRuns {
  size_t runs = 0;  // complete runs of OTHER that are a planned run in all but the version
  std::set<std::string> code_versions;  // their summaries' code_version (git describe of the binary)
};

// Among `todo` (runs not complete here nor reusable by hash), those that OTHER holds complete under another
// run version. Identity without the version: run_hash(case, seed, "") of OTHER's stored case file. Nothing
// when OTHER holds no study.
OtherVersionRuns other_version_runs(const std::string& other, const std::vector<PlannedRun>& todo);

// The note printed by plan and run, or "" when there is none.
std::string other_version_note(const std::string& other, const OtherVersionRuns& o);

}  // namespace wetdem::study
