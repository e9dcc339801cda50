// `wetdem diagnose D.toml --out DIR` and `wetdem twin T.toml --out DIR` (diagnosis.md §4-5; README,
// "Sim-to-real diagnosis"). Every simulation goes through the study run store (runbook.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "diagnose/files.h"

namespace wetdem::diagnose {

struct DiagnoseOptions {
  std::string out;    // DIR: diagnosis.json, report.md, figures/
  std::string store;  // run store (a study directory); default DIR/store
  int jobs = 1;
  size_t batch = 1;  // > 1: up to this many runs stepped together as ensembles (study run --batch)
  std::string device;
  std::string exe;  // the wetdem binary for run processes; empty: in this process (tests)
  bool quiet = false;
  bool figures = true;
};

// The observables a diagnosis accepts in its table: the scalar outputs of every run (summary.json).
const std::vector<std::string>& known_observables();

// Baseline, where, screen, fit and select, shrink, report. Returns what diagnosis.json holds.
// Reads only the files D.toml names (never a twin's truth.json). Throws DiagnoseError on bad input (before
// any run), std::runtime_error when runs fail.
nlohmann::json run_diagnosis(const DiagnosisSpec& d, const DiagnoseOptions& o);

// The truth runs, then observations.csv (noisy means, sigma) and, apart, truth.json. Returns truth.json.
nlohmann::json run_twin(const TwinSpec& t, const DiagnoseOptions& o);

}  // namespace wetdem::diagnose
