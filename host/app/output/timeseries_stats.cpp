#include "app/output/timeseries_stats.h"

#include <fmt/format.h>

#include <cmath>

namespace wetdem {

namespace {

constexpr size_t kMinSamples = 8;
constexpr double kMinNeff = 10.0;  // window ≥ 10 decorrelation times 2 τ_int
constexpr double kHalvesZ = 3.0;   // |z| < 3 between the halves' means

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}

struct MeanSem {
  double mean = 0.0, sd = 0.0, sem = 0.0, tau = 0.5;
  size_t window = 0;
  bool resolved = false;
};

MeanSem mean_sem(const std::vector<double>& v) {
  MeanSem m;
  const size_t n = v.size();
  m.mean = mean_of(v);
  if (n < 2) return m;
  double ss = 0.0;
  for (double x : v) ss += (x - m.mean) * (x - m.mean);
  m.sd = std::sqrt(ss / double(n - 1));
  m.resolved = integrated_autocorrelation_time(v, &m.tau, &m.window);
  m.sem = m.sd * std::sqrt(2.0 * m.tau / double(n));
  return m;
}

}  // namespace

bool integrated_autocorrelation_time(const std::vector<double>& v, double* tau, size_t* window, double c) {
  const size_t n = v.size();
  *tau = 0.5;
  *window = 0;
  if (n < 2) return false;
  const double m = mean_of(v);
  double c0 = 0.0;
  for (double x : v) c0 += (x - m) * (x - m);
  if (!(c0 > 0.0)) return true;  // constant: nothing to correlate
  double t = 0.5;
  const size_t w_max = n / 2;
  for (size_t w = 1; w < w_max; ++w) {
    double cw = 0.0;
    for (size_t i = 0; i + w < n; ++i) cw += (v[i] - m) * (v[i + w] - m);
    t += cw / c0;  // ρ(w) with the 1/n normalisation of both C(w) and C(0)
    if (double(w) >= c * t) {
      // Bias of the sample mean: E[ρ̂(t)] ≈ ρ(t) − 2τ/n at every lag, so τ̂(W) ≈ τ (1 − 2W/n).
      *tau = std::max(0.5, t / (1.0 - 2.0 * double(w) / double(n)));
      *window = w;
      return true;
    }
  }
  *tau = std::max(t, 0.5);
  *window = w_max > 0 ? w_max - 1 : 0;
  return false;
}

WindowStats window_stats(const std::vector<double>& v, double spacing_s) {
  WindowStats s;
  s.n = v.size();
  s.spacing_s = spacing_s;
  const MeanSem all = mean_sem(v);
  s.mean = all.mean;
  s.sd = all.sd;
  s.sem = all.sem;
  s.tau_int = all.tau;
  s.tau_int_s = all.tau * spacing_s;
  s.window = all.window;
  s.tau_resolved = all.resolved;
  s.n_eff = s.n > 0 ? double(s.n) / (2.0 * all.tau) : 0.0;
  if (s.n < kMinSamples) {
    s.stationary_reason = fmt::format("only {} samples in the window (need {})", s.n, kMinSamples);
    s.sem_reliable_reason = s.stationary_reason;
    return s;
  }
  const size_t h = s.n / 2;
  const MeanSem a = mean_sem(std::vector<double>(v.begin(), v.begin() + std::ptrdiff_t(h)));
  const MeanSem b = mean_sem(std::vector<double>(v.begin() + std::ptrdiff_t(h), v.end()));
  s.mean_first = a.mean;
  s.mean_second = b.mean;
  s.sem_first = a.sem;
  s.sem_second = b.sem;
  const double d = b.mean - a.mean, se = std::hypot(a.sem, b.sem);
  s.halves_z = se > 0.0 ? d / se : (d == 0.0 ? 0.0 : INFINITY);

  const double window_s = double(s.n) * spacing_s;
  if (!s.tau_resolved)
    s.stationary_reason = fmt::format(
        "correlation time not resolved: no Sokal window W >= 6 tau_int below n/2 = {} samples (tau_int >= "
        "{:.3g} s, window {:.3g} s)",
        h, s.tau_int_s, window_s);
  else if (s.n_eff < kMinNeff)
    s.stationary_reason = fmt::format(
        "window {:.3g} s is shorter than 10 correlation times 2 tau_int (tau_int = {:.3g} s, n_eff = {:.1f} "
        "< 10)",
        window_s, s.tau_int_s, s.n_eff);
  else if (!(std::fabs(s.halves_z) < kHalvesZ))
    s.stationary_reason =
        fmt::format("the halves of the window differ: {:.4g} vs {:.4g} (z = {:.2f}, |z| >= 3)", s.mean_first,
                    s.mean_second, s.halves_z);
  s.stationary = s.stationary_reason.empty();
  s.sem_reliable = s.stationary;
  if (!s.sem_reliable) s.sem_reliable_reason = "not stationary: " + s.stationary_reason;
  return s;
}

WindowStats window_stats_finite(const std::vector<double>& v, double spacing_s) {
  std::vector<double> x;
  for (double y : v)
    if (std::isfinite(y)) x.push_back(y);
  return window_stats(x, spacing_s);
}

}  // namespace wetdem
