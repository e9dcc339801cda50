#include "aor.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem {

namespace {

constexpr double kPi = 3.14159265358979323846;

// 99 % quantile of χ² with df degrees of freedom: exact values for df ≤ 30, Wilson–Hilferty above
// (q ≈ df (1 - 2/(9 df) + z_0.99 sqrt(2/(9 df)))³, relative error < 0.2 % there).
double chi2_q99(int df) {
  static const double q[30] = {6.634897,  9.210340,  11.344867, 13.276704, 15.086272, 16.811894,
                               18.475307, 20.090235, 21.665994, 23.209251, 24.724970, 26.216967,
                               27.688250, 29.141238, 30.577914, 31.999927, 33.408664, 34.805306,
                               36.190869, 37.566235, 38.932173, 40.289360, 41.638398, 42.979820,
                               44.314105, 45.641683, 46.962942, 48.278236, 49.587884, 50.892181};
  if (df <= 0) return 0.0;
  if (df <= 30) return q[df - 1];
  const double a = 2.0 / (9.0 * df), z = 2.3263478740408408;
  const double c = 1.0 - a + z * std::sqrt(a);
  return df * c * c * c;
}

double mean_of(const double* v, size_t n) {
  double s = 0.0;
  for (size_t i = 0; i < n; ++i) s += v[i];
  return n ? s / static_cast<double>(n) : 0.0;
}

}  // namespace

AorSample dynamic_aor(const std::vector<glm::dvec3>& x, const std::vector<double>& mass, double drum_radius,
                      double flag_fraction) {
  if (!mass.empty() && mass.size() != x.size()) throw std::invalid_argument("dynamic_aor: sizes differ");
  AorSample s;
  glm::dvec2 mx(0.0);
  for (size_t i = 0; i < x.size(); ++i) {
    const double m = mass.empty() ? 1.0 : mass[i];
    s.mass += m;
    mx += m * glm::dvec2(x[i].x, x[i].y);
  }
  if (!(s.mass > 0.0)) return s;  // empty bed: flagged
  s.com = mx / s.mass;
  s.com_radius = glm::length(s.com);
  // Angle from the downward vertical (0, -1) to the COM direction, positive towards +x (header).
  s.signed_deg = std::atan2(s.com.x, -s.com.y) * 180.0 / kPi;
  s.abs_deg = std::fabs(s.signed_deg);
  s.flagged = s.com_radius < flag_fraction * drum_radius;
  return s;
}

AorSample dynamic_aor(const SystemState& s, double drum_radius, double flag_fraction) {
  return dynamic_aor(s.p.x, s.p.mass, drum_radius, flag_fraction);
}

double blocked_sem(const std::vector<double>& v, int* level, bool* reliable) {
  if (level) *level = 0;
  if (reliable) *reliable = false;
  if (v.size() < 2) return 0.0;
  // Flyvbjerg–Petersen levels: x_{j+1,i} = (x_{j,2i} + x_{j,2i+1}) / 2 (an odd last sample is dropped).
  struct Level {
    size_t n;
    double var;    // biased variance s_j² = Σ (x - x̄)² / n_j
    double gamma;  // lag-1 autocovariance Σ (x_i - x̄)(x_{i+1} - x̄) / n_j
  };
  std::vector<Level> lv;
  std::vector<double> x = v;
  while (x.size() >= 2) {
    const size_t n = x.size();
    const double m = mean_of(x.data(), n);
    double var = 0.0, gam = 0.0;
    for (size_t i = 0; i < n; ++i) var += (x[i] - m) * (x[i] - m);
    for (size_t i = 0; i + 1 < n; ++i) gam += (x[i] - m) * (x[i + 1] - m);
    lv.push_back({n, var / static_cast<double>(n), gam / static_cast<double>(n)});
    std::vector<double> y(n / 2);
    for (size_t i = 0; i < n / 2; ++i) y[i] = 0.5 * (x[2 * i] + x[2 * i + 1]);
    x.swap(y);
  }
  // FP estimate of the variance of the mean at level j: s_j² / (n_j - 1).
  auto sem_at = [&](size_t j) { return std::sqrt(lv[j].var / static_cast<double>(lv[j].n - 1)); };
  // Jonsson's test: M_j = Σ_{k ≥ j} n_k (γ_k / s_k²)² ~ χ²(levels - j) when blocks at level ≥ j are
  // uncorrelated.
  const size_t L = lv.size();
  std::vector<double> M(L + 1, 0.0);
  for (size_t k = L; k-- > 0;) {
    const double r = lv[k].var > 0.0 ? lv[k].gamma / lv[k].var : 0.0;
    M[k] = M[k + 1] + static_cast<double>(lv[k].n) * r * r;
  }
  for (size_t j = 0; j < L; ++j) {
    if (M[j] < chi2_q99(static_cast<int>(L - j))) {
      if (level) *level = static_cast<int>(j);
      // A level with fewer than 8 blocks estimates the SEM itself only to ±25 % or worse: not reliable.
      if (reliable) *reliable = lv[j].n >= 8;
      return sem_at(j);
    }
  }
  // No level passed: the window is short compared with the correlation time. Report the largest estimate
  // among levels that still have ≥ 4 blocks (a lower bound on the true SEM, flagged unreliable).
  double best = sem_at(0);
  int best_level = 0;
  for (size_t j = 0; j < L; ++j)
    if (lv[j].n >= 4 && sem_at(j) > best) {
      best = sem_at(j);
      best_level = static_cast<int>(j);
    }
  if (level) *level = best_level;
  return best;
}

SeriesStats series_stats(const std::vector<double>& t, const std::vector<double>& v, double t_from) {
  if (t.size() != v.size()) throw std::invalid_argument("series_stats: t and v differ in size");
  std::vector<double> w, tw;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t_from) {
      w.push_back(v[i]);
      tw.push_back(t[i]);
    }
  SeriesStats s;
  s.n = w.size();
  if (s.n == 0) return s;
  s.t_begin = tw.front();
  s.t_end = tw.back();
  s.mean = mean_of(w.data(), s.n);
  if (s.n >= 2) {
    double ss = 0.0;
    for (double x : w) ss += (x - s.mean) * (x - s.mean);
    s.stddev = std::sqrt(ss / static_cast<double>(s.n - 1));
    s.sem_naive = s.stddev / std::sqrt(static_cast<double>(s.n));
    s.sem = blocked_sem(w, &s.block_level, &s.sem_reliable);
  }
  if (s.n >= 4) {
    const size_t h = s.n / 2;
    const std::vector<double> a(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(h));
    const std::vector<double> b(w.begin() + static_cast<std::ptrdiff_t>(h), w.end());
    s.mean_first = mean_of(a.data(), a.size());
    s.mean_second = mean_of(b.data(), b.size());
    s.sem_first = blocked_sem(a);
    s.sem_second = blocked_sem(b);
    const double d = s.mean_second - s.mean_first;
    const double se = std::sqrt(s.sem_first * s.sem_first + s.sem_second * s.sem_second);
    s.drift_z = se > 0.0 ? d / se : (d == 0.0 ? 0.0 : INFINITY);
    s.stationary = std::fabs(s.drift_z) < 3.0;
  }
  return s;
}

AorSummary summarize_aor(const std::vector<double>& t, const std::vector<AorSample>& samples, double t_from) {
  if (t.size() != samples.size()) throw std::invalid_argument("summarize_aor: t and samples differ in size");
  AorSummary out;
  std::vector<double> tt, sg, ab;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] < t_from) continue;
    ++out.samples;
    if (samples[i].flagged) {
      ++out.flagged;
      continue;
    }
    tt.push_back(t[i]);
    sg.push_back(samples[i].signed_deg);
    ab.push_back(samples[i].abs_deg);
  }
  out.signed_deg = series_stats(tt, sg);
  out.abs_deg = series_stats(tt, ab);
  return out;
}

std::string AorSummary::describe() const {
  const SeriesStats& a = abs_deg;
  if (a.n == 0)
    return fmt::format(
        "dynamic AoR: no unflagged sample in the window ({} samples, {} flagged |COM| < 0.2 R)", samples,
        flagged);
  return fmt::format(
      "dynamic AoR |θ| = {:.2f}° (sd {:.2f}°, SEM {:.2f}° blocked at level {}{}), signed θ = {:.2f}°; window "
      "t = "
      "[{:.4g}, {:.4g}] s, {} samples, {} flagged; halves {:.2f}° / {:.2f}° (z = {:.2f}, {})",
      a.mean, a.stddev, a.sem, a.block_level, a.sem_reliable ? "" : ", unreliable: window too short",
      signed_deg.mean, a.t_begin, a.t_end, samples, flagged, a.mean_first, a.mean_second, a.drift_z,
      a.stationary ? "stationary" : "NOT stationary");
}

}  // namespace wetdem
