// The drift of the angle of repose over the AoR window (diagnosis.md §2). The window mean and error bar of a
// per-sample observable: window_stats_finite (app/output/timeseries_stats.h).
#pragma once

#include <cstddef>
#include <vector>

namespace wetdem::observe {

// Ordinary least squares of the AoR a_i (deg) on time t_i (s) over the window, scaled to one drum revolution
// (2π/|ω| s): slope_deg_per_rev. AoR samples are correlated, so the plain OLS standard error of the slope is
// too small (by ≈ 4 for a lag-1 correlation of 0.9). Its error is therefore blocked as the error of a mean
// is (Flyvbjerg & Petersen 1989): the series (t, a) is halved level by level by averaging neighbours, the OLS
// slope error s_e / sqrt(Σ (t - t̄)²) is computed at each level, and the largest over the levels that keep at
// least 16 blocks is reported (level 0, the plain error, when the window has fewer than 32 samples). On AR(1)
// noise with lag-1 correlation 0.9 and 2048 samples this matches the spread of the slope within ~5 % (tests).
// NaN when fewer than 3 samples, or ω = 0.
struct Drift {
  size_t n = 0;
  double slope_deg_per_rev = 0.0;
  double se_deg_per_rev = 0.0;
  double se_ols_deg_per_rev = 0.0;  // level 0: the plain OLS error
  int block_level = 0;              // level of se_deg_per_rev (blocks of 2^level samples)
};
Drift aor_drift(const std::vector<double>& t, const std::vector<double>& aor_deg, double omega);

}  // namespace wetdem::observe
