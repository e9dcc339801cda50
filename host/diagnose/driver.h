// `wetdem diagnose D.toml --out DIR` (diagnosis.md §4; docs/diagnosis.md). Every simulation goes through the
// study run store (runbook.h). The twin command is twin.h.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "diagnose/files.h"

namespace wetdem::diagnose {

struct DiagnoseOptions {
  std::string out;    // DIR: diagnosis.json, report.md, figures/
  std::string store;  // run store (a study directory); default DIR/store
  int jobs = 1;
  size_t batch = 1;  // > 1: runs handed to one process as ensembles (study --batch); the CLI's 0 (auto) is
                     // resolved before (auto_batch.h)
  std::string device;
  std::string exe;  // the wetdem binary for run processes; empty: in this process (tests)
  bool quiet = false;
  bool figures = true;
  bool check = false;  // --check: validate the files and every run's case, run nothing, write nothing
};

// Baseline, where, screen, fit, verdict, shrink, next experiment, report. Returns what diagnosis.json holds.
// Reads only the files D.toml names (never a twin's truth.json). Throws DiagnoseError on bad input (before
// any run), std::runtime_error when the calibrated model itself cannot run. A probe that fails never stops
// it: the candidate's range is cut there and the report says so. With o.check it stops after those checks
// (nothing run or written) and returns {"checked": true, "conditions", "cells", "candidates"}.
nlohmann::json run_diagnosis(const DiagnosisSpec& d, const DiagnoseOptions& o);

}  // namespace wetdem::diagnose
