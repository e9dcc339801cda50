#include "diagnose/measurement_noise.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "diagnose/baseline.h"

namespace wetdem::diagnose {

namespace {

// For each assay the file names ([assays]): the calibrated model's seed spread over its runs' own window
// SE at the table's conditions (as the baseline measures it for the table's observables, baseline.cpp), so
// that an assay's model error is the seed-to-seed one. 1 where fewer than two seeds report it.
std::map<std::string, double> assays_inflation(const Procedure& p) {
  std::map<std::string, double> f;
  const Variant base = p.variant("", 0);
  for (const auto& [obs, sd] : p.d.assays) {
    std::vector<Cell> cells;
    std::vector<std::vector<Prediction>> per_seed(p.base_seeds.size());
    for (const Condition& c : p.tab.conditions) {
      Cell cell;
      cell.observable = obs;
      cells.push_back(cell);
      for (size_t s = 0; s < p.base_seeds.size(); ++s)
        per_seed[s].push_back(p.book.reports(c, base, {p.base_seeds[s]}, obs)
                                  ? p.book.predict(c, base, {p.base_seeds[s]}, obs, 1.0)
                                  : Prediction{std::nan(""), std::nan("")});
    }
    f[obs] = within_inflation(cells, per_seed)[obs];
  }
  return f;
}

}  // namespace

std::map<std::string, double> median_sigma(const std::vector<Cell>& cells) {
  std::map<std::string, std::vector<double>> sig;
  for (const Cell& c : cells) sig[c.observable].push_back(c.sigma);
  std::map<std::string, double> sigma;
  for (auto& [o, v] : sig) {
    std::sort(v.begin(), v.end());
    sigma[o] = v[v.size() / 2];
  }
  return sigma;
}

MeasurementNoise measurement_noise(const Procedure& p) {
  MeasurementNoise n;
  n.sigma = median_sigma(p.tab.cells);
  for (const Cell& c : p.tab.cells) n.inflation[c.observable] = p.inflation(c.observable);
  const std::map<std::string, double> assay_inflation = assays_inflation(p);
  for (const auto& [obs, sd] : p.d.assays) n.sigma[obs] = sd, n.inflation[obs] = assay_inflation.at(obs);
  if (!p.baselines.empty() && p.baselines[0].size() == p.tab.cells.size()) {
    std::vector<Cell> se2 = p.tab.cells;  // median_sigma over the baseline's squared SEs
    for (size_t k = 0; k < se2.size(); ++k) se2[k].sigma = p.baselines[0][k].se * p.baselines[0][k].se;
    for (const auto& [obs, v] : median_sigma(se2))
      if (!p.d.assays.count(obs) && std::isfinite(v)) n.typical_se2[obs] = v;
  }
  return n;
}

double sigma_at(const MeasurementNoise& n, const std::string& obs, double se_x, double se_y) {
  const double s = n.sigma.at(obs);
  const auto t = n.typical_se2.find(obs);
  if (t == n.typical_se2.end()) return s;
  const double excess = 0.5 * (se_x * se_x + se_y * se_y) - t->second;
  return std::isfinite(excess) && excess > 0 ? std::sqrt(s * s + excess) : s;
}

double separation_of(const MeasurementNoise& n, const std::string& obs, const Prediction& x,
                     const Prediction& y) {
  const double s = sigma_at(n, obs, x.se, y.se);
  return std::fabs(x.mean - y.mean) / std::sqrt(s * s + x.se * x.se + y.se * y.se);
}

size_t repeats_for(double delta, double sigma, double se2, double target) {
  // |delta|² / target² = σ²/k + se²  =>  k = σ² / (delta²/target² − se²).
  const double room = delta * delta / (target * target) - se2;
  if (!(room > 0) || !(sigma > 0)) return 0;
  const double k = std::ceil(sigma * sigma / room * (1 - 1e-12));
  return k <= double(kMaxRepeats) ? std::max<size_t>(1, size_t(k)) : 0;
}

}  // namespace wetdem::diagnose
