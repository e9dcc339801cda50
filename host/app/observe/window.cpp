#include "app/observe/window.h"

#include <cmath>
#include <stdexcept>

#include "app/drum/aor.h"

namespace wetdem::observe {

namespace {

struct Slope {
  double b = 0.0, se = 0.0;
  bool ok = false;
};

Slope ols_slope(const std::vector<double>& t, const std::vector<double>& a) {
  Slope r;
  const size_t m = t.size();
  if (m < 3) return r;
  const double n = static_cast<double>(m);
  double mt = 0, ma = 0;
  for (size_t i = 0; i < m; ++i) mt += t[i], ma += a[i];
  mt /= n, ma /= n;
  double stt = 0, sta = 0;
  for (size_t i = 0; i < m; ++i) stt += (t[i] - mt) * (t[i] - mt), sta += (t[i] - mt) * (a[i] - ma);
  if (!(stt > 0)) return r;
  r.b = sta / stt;
  double sse = 0;
  for (size_t i = 0; i < m; ++i) sse += std::pow(a[i] - ma - r.b * (t[i] - mt), 2);
  r.se = std::sqrt(sse / (n - 2.0) / stt);
  r.ok = true;
  return r;
}

}  // namespace

Drift aor_drift(const std::vector<double>& t, const std::vector<double>& a, double omega) {
  if (t.size() != a.size()) throw std::invalid_argument("aor_drift: t and aor differ in size");
  Drift d;
  d.n = t.size();
  const Slope s0 = ols_slope(t, a);
  if (!s0.ok || omega == 0.0) {
    d.slope_deg_per_rev = d.se_deg_per_rev = d.se_ols_deg_per_rev = std::nan("");
    return d;
  }
  const double period = 2.0 * 3.14159265358979323846 / std::fabs(omega);
  d.slope_deg_per_rev = s0.b * period;
  d.se_ols_deg_per_rev = s0.se * period;
  double se = s0.se;
  std::vector<double> bt = t, ba = a;
  for (int level = 1;; ++level) {
    const size_t h = bt.size() / 2;  // an odd last sample is dropped, as in blocked_sem
    if (h < 16) break;
    for (size_t i = 0; i < h; ++i)
      bt[i] = 0.5 * (bt[2 * i] + bt[2 * i + 1]), ba[i] = 0.5 * (ba[2 * i] + ba[2 * i + 1]);
    bt.resize(h), ba.resize(h);
    const Slope s = ols_slope(bt, ba);
    if (s.ok && s.se > se) se = s.se, d.block_level = level;
  }
  d.se_deg_per_rev = se * period;
  return d;
}

}  // namespace wetdem::observe
