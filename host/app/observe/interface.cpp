#include "app/observe/interface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wetdem::observe {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

std::vector<double> interface_profile(const SystemState& s, double drum_radius, double bed_length,
                                      const InterfaceOptions& opt) {
  const size_t n = s.p.size();
  if (n == 0 || !(drum_radius > 0)) return {};
  double d = 0;
  for (size_t k = 0; k < n; ++k) d += 2.0 * s.p.radius[k];
  d /= double(n);
  const double w = opt.column_width * d;
  const size_t cols = size_t(std::floor(2.0 * drum_radius / w));
  if (cols == 0) return {};
  const size_t per_layer = std::max<size_t>(1, size_t(std::llround(w * bed_length / (d * d))));
  std::vector<std::vector<double>> ys(cols);
  for (size_t k = 0; k < n; ++k) {
    const double c = std::floor((s.p.x[k].x + drum_radius) / w);
    if (c < 0 || c >= double(cols)) continue;
    ys[size_t(c)].push_back(s.p.x[k].y);
  }
  std::vector<double> h(cols, kNaN);
  for (size_t c = 0; c < cols; ++c) {
    std::vector<double>& y = ys[c];
    if (y.size() < per_layer) continue;
    // The per_layer highest, then their median (a few thrown particles above the bed do not move it).
    std::nth_element(y.begin(), y.begin() + long(per_layer - 1), y.end(), std::greater<double>());
    std::vector<double> top(y.begin(), y.begin() + long(per_layer));
    std::sort(top.begin(), top.end());
    const size_t m = top.size();
    h[c] = m % 2 ? top[m / 2] : 0.5 * (top[m / 2 - 1] + top[m / 2]);
  }
  return h;
}

double interface_fluctuation(const std::vector<std::vector<double>>& profiles, const InterfaceOptions& opt) {
  if (profiles.size() < 3) return kNaN;
  size_t cols = 0;
  for (const auto& p : profiles) cols = std::max(cols, p.size());
  std::vector<double> sd(cols, kNaN);
  std::vector<bool> counted(cols, false);
  for (size_t c = 0; c < cols; ++c) {
    std::vector<double> v;
    for (const auto& p : profiles)
      if (c < p.size() && std::isfinite(p[c])) v.push_back(p[c]);
    if (v.size() < 3 || double(v.size()) < opt.coverage * double(profiles.size())) continue;
    double mean = 0;
    for (double x : v) mean += x;
    mean /= double(v.size());
    double ss = 0;
    for (double x : v) ss += (x - mean) * (x - mean);
    sd[c] = std::sqrt(ss / double(v.size() - 1));
    counted[c] = true;
  }
  size_t lo = cols, hi = 0;
  for (size_t c = 0; c < cols; ++c)
    if (counted[c]) lo = std::min(lo, c), hi = std::max(hi, c);
  if (lo > hi) return kNaN;
  // Central fraction of the chord [lo, hi + 1) in column units.
  const double mid = 0.5 * (double(lo) + double(hi) + 1.0),
               half = 0.5 * opt.central_fraction * double(hi + 1 - lo);
  double sum = 0;
  size_t m = 0;
  for (size_t c = lo; c <= hi; ++c) {
    const double centre = double(c) + 0.5;
    if (counted[c] && std::fabs(centre - mid) <= half) sum += sd[c], ++m;
  }
  return m ? sum / double(m) : kNaN;
}

}  // namespace wetdem::observe
