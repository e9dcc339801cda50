#include "app/output/window_rules.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace wetdem::app {

double window_revolutions(double window_s, double omega) {
  return window_s * std::fabs(omega) / (2.0 * 3.14159265358979323846);
}

std::string drift_rule_reason(const std::vector<double>& t, const std::vector<double>& aor, double window_s,
                              double omega, double spacing_s) {
  if (omega == 0.0) return "the drum does not turn";
  const double rev = window_revolutions(window_s, omega);
  if (rev < kDriftMinRevolutions)
    return fmt::format("the window spans {:.2f} revolutions; a drift per revolution needs >= {:g}", rev,
                       kDriftMinRevolutions);
  const size_t n = std::min(t.size(), aor.size());
  if (n < 8) return fmt::format("{} AoR samples in the window; a drift needs more", n);
  // Residuals about the least-squares line: their correlation decides how many independent samples the
  // slope rests on.
  double mt = 0, ma = 0;
  for (size_t i = 0; i < n; ++i) mt += t[i], ma += aor[i];
  mt /= double(n), ma /= double(n);
  double stt = 0, sta = 0;
  for (size_t i = 0; i < n; ++i) stt += (t[i] - mt) * (t[i] - mt), sta += (t[i] - mt) * (aor[i] - ma);
  const double b = stt > 0 ? sta / stt : 0.0;
  std::vector<double> res(n);
  for (size_t i = 0; i < n; ++i) res[i] = aor[i] - ma - b * (t[i] - mt);
  const WindowStats w = window_stats(res, spacing_s);
  if (!w.tau_resolved)
    return "the correlation time of the AoR about its trend is not resolved in the window (window too short)";
  if (w.n_eff < kDriftMinEffectiveSamples)
    return fmt::format(
        "the window holds {:.1f} independent AoR samples about the trend (n_eff); a drift needs >= {:g}",
        w.n_eff, kDriftMinEffectiveSamples);
  return "";
}

std::string mean_rule_reason(const WindowStats& w) {
  if (w.n == 0) return "no sample of the window has a value";
  return w.stationary_reason;
}

bool network_spans_bed(double agglomerate_size_mean, size_t particles) {
  return particles > 1 && std::isfinite(agglomerate_size_mean) &&
         agglomerate_size_mean >= kSpansBedFraction * double(particles);
}

}  // namespace wetdem::app
