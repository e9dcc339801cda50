// `wetdem study collect DIR`: the study's results as tables (runs.csv, points.csv), figures (scripts/
// plot_study.py, Debian's matplotlib) and report.md. Statistics over replicates: mean, sample standard
// deviation (n - 1) and standard error of the mean sd / sqrt(n), over the runs where the value is not null
// (a flagged AoR is null in summary.json).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "study/store.h"

namespace wetdem::study {

struct Stats {
  size_t n = 0;
  double mean = 0, sd = 0, se = 0;  // sd and se NaN when n < 2, mean NaN when n = 0
};
Stats stats_of(const std::vector<double>& v);

struct PointResult {
  size_t point = 0;
  std::vector<AxisValue> values;
  size_t runs = 0, complete = 0;
  std::map<std::string, Stats> stats;  // every numeric summary key over complete replicates
  std::vector<std::string> run_dirs;   // the complete runs, relative to DIR
};

struct Collected {
  StudyIndex index;
  std::vector<nlohmann::json> summaries;  // per run (null when not complete)
  std::vector<std::string> states;        // per run: complete, failed, ...
  std::vector<PointResult> points;
  std::vector<std::string> numeric_keys;  // numeric scalars of summary.json, sorted
};

// Reads every run's summary.json; no file written.
Collected gather(const std::string& dir);

struct CollectOptions {
  bool figures = true;  // run the plotting script
  std::string python = "/usr/bin/python3";
};
// Writes DIR/runs.csv, DIR/points.csv, DIR/figures/*.png (when figures), DIR/report.md. Returns what it read.
Collected collect(const std::string& dir, const CollectOptions& opt = {});

// The plotting script: $WETDEM_PLOT_SCRIPT, else scripts/plot_study.py of the source tree.
std::string plot_script();

}  // namespace wetdem::study
