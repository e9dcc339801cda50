// Statistics of an equally spaced time series over a window, with an error bar that knows how correlated
// the samples are and a verdict on whether the window is long and steady enough to quote a mean.
//
// Integrated autocorrelation time (Sokal, "Monte Carlo methods in statistical mechanics", Cargèse lectures
// 1996, §3): with ρ(t) = C(t)/C(0), C(t) = (1/n) Σ_{i < n-t} (x_i − x̄)(x_{i+t} − x̄),
//     τ_int(W) = 1/2 + Σ_{t=1..W} ρ(t)   (in samples),
// and the window W chosen automatically as the smallest W ≥ c τ_int(W), c = 6, then corrected for the bias of
// the subtracted sample mean (E[ρ̂(t)] ≈ ρ(t) − 2τ/n at every lag): τ_int = τ_int(W) / (1 − 2W/n). Then
//     Var(x̄) ≈ 2 τ_int σ² / n,   n_eff = n / (2 τ_int),   sem = σ √(2 τ_int / n).
// For an AR(1) series x_{i+1} = φ x_i + noise, τ_int = (1 + φ) / (2 (1 − φ)); for white noise 1/2.
//
// Verdicts (both must hold for `stationary`; `sem_reliable` needs stationary too):
//  - resolved: the automatic window exists below n/2 (else τ_int is not measurable in this window);
//  - long enough: the window spans ≥ 10 correlation times 2 τ_int (the spacing of independent samples),
//    i.e. n_eff ≥ 10. Sokal's estimate stays biased low on short windows even after the correction above
//    (AR(1) with τ_int = 19.5: median estimate 11 from 100 samples), so a window of 3-5 τ_int is caught
//    most of the time, not always: measured over 200 AR(1) windows of 60 samples (3 τ_int), 90 % flagged;
//    white noise of 41 samples, 1.4 % flagged (docs/outputs.md);
//  - no trend between halves: z = (x̄₂ − x̄₁) / √(sem₁² + sem₂²), each half with its own τ_int, |z| < 3
//    (two-sided, ~0.3 % false alarms for Gaussian means).
// The reason strings name the first test that failed (empty when the verdict is true).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace wetdem {

struct WindowStats {
  size_t n = 0;            // samples
  double spacing_s = 0.0;  // sample spacing Δt (s)
  double mean = 0.0;
  double sd = 0.0;            // sample standard deviation (n − 1)
  double sem = 0.0;           // sd √(2 τ_int / n)
  double tau_int = 0.0;       // integrated autocorrelation time, samples
  double tau_int_s = 0.0;     // the same in seconds (τ_int Δt)
  double n_eff = 0.0;         // n / (2 τ_int)
  size_t window = 0;          // Sokal's automatic window W (lags)
  bool tau_resolved = false;  // W ≥ 6 τ_int(W) found with W < n/2
  double mean_first = 0.0, mean_second = 0.0, sem_first = 0.0, sem_second = 0.0;
  double halves_z = 0.0;  // (mean_second − mean_first) / √(sem_first² + sem_second²)
  bool stationary = false;
  bool sem_reliable = false;
  std::string stationary_reason;    // empty when stationary
  std::string sem_reliable_reason;  // empty when sem_reliable
};

// Integrated autocorrelation time by Sokal's automatic windowing (header). tau: τ_int in samples; window:
// the chosen W; returns whether a window W < n/2 satisfied W ≥ c τ_int(W) (else tau is τ_int(n/2 − 1)).
// A constant series has τ_int = 1/2 (no fluctuation to correlate).
bool integrated_autocorrelation_time(const std::vector<double>& v, double* tau, size_t* window,
                                     double c = 6.0);

// All of the above for v sampled every spacing_s seconds. Needs no minimum length: fewer than 8 samples
// give stationary = sem_reliable = false with a reason.
WindowStats window_stats(const std::vector<double>& v, double spacing_s);

// window_stats over the finite values of v only (NaN marks a sample without a value, e.g. a camera observable
// the bed did not show), in time order; spacing_s is the spacing of the samples kept.
WindowStats window_stats_finite(const std::vector<double>& v, double spacing_s);

}  // namespace wetdem
