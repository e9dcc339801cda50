// `wetdem calibrate DIR --refine K`: iterative calibration. The emulator proposes K new values of the fitted
// axes; they are added to the study as [[points]] (one per observed condition) in DIR/refine/round-N.toml
// (the study file with absolute paths and the new points), and the new runs are run. The run store keeps
// every earlier run: only the new points are computed.
#pragma once

#include <string>

#include "study/calibrate.h"

namespace wetdem::study {

struct RefineOptions {
  size_t k = 1;
  int jobs = 1;
  std::string device;
  std::string exe;  // wetdem binary for the runs (default: this one)
  CalibrateOptions calibrate;
};

// Returns a description of what was added and run. Throws StudyError.
std::string refine(const std::string& dir, const RefineOptions& opt);

}  // namespace wetdem::study
