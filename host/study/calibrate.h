// `wetdem calibrate DIR`: the study against its observation table. For every value of the fitted axes (a
// "fit point": the grid points that share it, one per condition),
//   chi2 = sum over observations (y_obs - y_sim)^2 / (sigma_obs^2 + SE_sim^2)
// with y_sim the replicate mean and SE_sim its standard error (0 with one replicate). An emulator (a Gaussian
// process per observation over the fitted axes, in log10 for positive axes, scaled to [0, 1]) makes chi2
// continuous: its minimum is the calibrated value, and {chi2 <= chi2_min + 1} (profiled over the other fitted
// axes) its interval.
#pragma once

#include <string>
#include <vector>

#include "study/collect.h"
#include "study/observations.h"

namespace wetdem::study {

struct FitPoint {
  std::vector<double> x_si;          // the fitted axes' values (SI)
  std::vector<std::string> written;  // as written in the study
  std::vector<double> y, se;         // per observation: simulated mean and SE (NaN: no such run)
  double chi2 = 0;
  bool complete = false;  // every observation has a simulated value
};

struct Calibration {
  std::vector<std::string> fit;
  std::vector<bool> log_axis;  // emulated in log10
  std::vector<double> lo, hi;  // sampled range per axis (SI)
  std::vector<Observation> obs;
  std::vector<FitPoint> points;
  int best = -1;                // index into points
  std::vector<double> optimum;  // emulator's minimum (SI)
  double chi2_optimum = 0;
  std::vector<double> interval_lo, interval_hi;          // Delta chi2 = 1 (SI)
  std::vector<bool> interval_open_lo, interval_open_hi;  // the interval reaches the sampled range's edge
  std::vector<double> y_optimum;                         // emulated observables at the optimum
  // The emulator on a grid (1-D: a curve; 2-D: a map): coordinates (SI) and chi2.
  std::vector<std::vector<double>> grid_x;
  std::vector<double> grid_chi2;
  std::vector<std::vector<double>> proposals;  // --refine: new fit values (SI), most promising first
};

struct CalibrateOptions {
  std::string observations;      // overrides the study's [observations].file
  std::vector<std::string> fit;  // overrides [observations].fit
  size_t propose = 0;            // how many new fit values to propose (for --refine)
};

// Reads the study and its observations; nothing written. Throws StudyError (observation rows named).
Calibration calibrate(const std::string& dir, const CalibrateOptions& opt = {});

// DIR/calibration/: calibration.md (the paper-style table and the result), calibration.json, chi2.csv,
// emulator.csv. Returns the markdown.
std::string write_calibration(const std::string& dir, const Calibration& c);

}  // namespace wetdem::study
