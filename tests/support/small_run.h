// One run of the small drum case (small_case.h) through the whole driver on the shared GPU context, for
// the end-to-end drum tests: the case is written to a fresh temp folder, run with checkpoints off and the
// given overrides, every sample kept, and the folder removed. Tests reduce the samples their own way.
#pragma once
#ifdef WETDEM_HAVE_APP

#include <string>
#include <vector>

#include "app/run/run.h"

namespace wetdem::test {

struct SmallRun {
  app::RunResult result;
  std::vector<app::Sample> samples;  // all of them, settling included (Sample::time counts from t = 0)
};

SmallRun run_small(const std::string& tag, const std::vector<std::string>& overrides);

}  // namespace wetdem::test

#endif
