// When a window quantity of a run may be quoted (issue 21). The AoR's own rule is in timeseries_stats.h: a
// mean is quotable when its window is stationary (correlation time resolved, n_eff >= 10, halves agree). The
// same rule is applied here to every window mean of summary.json (f_wet, the camera observables), and two
// quantities get rules of their own:
//  - the AoR drift per revolution (observe/window.h) is a slope over the window scaled to one revolution:
//  over a
//    window shorter than kDriftMinRevolutions it is an extrapolation (a tilt followed by a slump in a fifth
//    of a revolution reads as -129 °/rev), and its error bar needs the same n_eff >= 10 independent samples
//    as a mean, counted on the residuals about the fitted line (a drift itself must not make the window too
//    short to report it). It is not reported (null, with the reason) otherwise;
//  - the mean agglomerate size (bridge-network components, observe/clusters.h) on a bed whose bridge network
//    percolates is the bed itself, not an agglomerate: when the mass-weighted mean cluster holds at least
//    kSpansBedFraction of the particles the network spans the bed, and the size is labelled so and not quoted
//    as an agglomerate size.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "app/output/timeseries_stats.h"

namespace wetdem::app {

inline constexpr double kDriftMinRevolutions = 1.0;
inline constexpr double kDriftMinEffectiveSamples = 10.0;
inline constexpr double kSpansBedFraction = 0.5;

// Revolutions of a drum turning at omega (rad/s) during window_s seconds.
double window_revolutions(double window_s, double omega);

// Empty when the drift may be reported; else why not ("the window spans 0.13 revolutions; ..."). t, aor: the
// AoR samples the drift is fitted to (s, deg), spacing_s their sample spacing; window_s the window's length.
std::string drift_rule_reason(const std::vector<double>& t, const std::vector<double>& aor, double window_s,
                              double omega, double spacing_s);

// Empty when a window mean may be quoted (its window is stationary); else the reason (no samples, or the
// stationarity reason of window_stats).
std::string mean_rule_reason(const WindowStats& w);

// The bridge network spans the bed: the mass-weighted mean cluster holds >= kSpansBedFraction of the
// particles.
bool network_spans_bed(double agglomerate_size_mean, size_t particles);

}  // namespace wetdem::app
