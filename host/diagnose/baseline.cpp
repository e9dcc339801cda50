#include "diagnose/baseline.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem::diagnose {

void run_baseline(Procedure& p) {
  p.run();
  const Variant base = p.variant("", 0);
  if (const std::string why = p.failure(base, p.base_seeds); !why.empty())
    throw std::runtime_error("the calibrated model itself failed: " + why +
                             " (a diagnosis needs the model at every condition of the table)");
  p.baselines = {p.predict(base, p.base_seeds)};
  // A cell the calibrated model does not report in any baseline run (the AoR drift of windows that cannot
  // carry it) cannot be compared: it is left out, and the report says so.
  std::vector<size_t> keep;
  for (size_t k = 0; k < p.tab.cells.size(); ++k) {
    if (std::isfinite(p.baselines[0][k].mean)) {
      keep.push_back(k);
      continue;
    }
    p.notes.push_back(fmt::format(
        "baseline: the model does not report {} at {} in any baseline run; the cell "
        "(line {}) is left out",
        p.tab.cells[k].observable, p.tab.conditions[p.tab.cell_condition[k]].label, p.tab.cell_line[k]));
  }
  if (keep.size() < p.tab.cells.size()) {
    Table t = p.tab;
    t.cells.clear(), t.cell_condition.clear(), t.cell_line.clear();
    for (size_t k : keep)
      t.cells.push_back(p.tab.cells[k]), t.cell_condition.push_back(p.tab.cell_condition[k]),
          t.cell_line.push_back(p.tab.cell_line[k]);
    p.tab = t;
    if (conditions_of(p.tab.cells, nullptr).size() < 2)
      throw std::runtime_error("fewer than two conditions have cells the model reports: nothing to diagnose");
    p.baselines = {p.predict(base, p.base_seeds)};
  }
  p.seed1 = {p.predict(base, p.probe_seeds)};
  // A run's sd: the SE of each mean times the square root of its seeds.
  const double r = double(p.base_seeds.size()), np = double(p.probe_seeds.size());
  p.spread.clear();
  for (size_t k = 0; k < p.tab.cells.size(); ++k)
    p.spread.push_back(std::max(p.baselines[0][k].se * std::sqrt(r), p.seed1[0][k].se * std::sqrt(np)));
  std::vector<std::vector<Prediction>> per_seed;
  for (uint64_t s : p.base_seeds) per_seed.push_back(p.predict(base, {s}));
  p.within_inflation = within_inflation(p.tab.cells, per_seed);
}

std::map<std::string, double> within_inflation(const std::vector<Cell>& cells,
                                               const std::vector<std::vector<Prediction>>& per_seed) {
  std::map<std::string, std::pair<double, double>> sums;  // observable -> (Σ between variance, Σ own SE²)
  for (size_t k = 0; k < cells.size(); ++k) {
    std::vector<Prediction> x;
    for (const auto& seed : per_seed)
      if (k < seed.size() && std::isfinite(seed[k].mean) && std::isfinite(seed[k].se)) x.push_back(seed[k]);
    if (x.size() < 2) continue;
    double mean = 0.0, own2 = 0.0;
    for (const Prediction& a : x) mean += a.mean / double(x.size()), own2 += a.se * a.se / double(x.size());
    double var = 0.0;
    for (const Prediction& a : x) var += (a.mean - mean) * (a.mean - mean) / double(x.size() - 1);
    auto& [between, own] = sums[cells[k].observable];
    between += var, own += own2;
  }
  std::map<std::string, double> f;
  for (const Cell& c : cells) f[c.observable] = 1.0;
  for (const auto& [obs, s] : sums)
    if (s.second > 0.0) f[obs] = std::max(1.0, std::sqrt(s.first / s.second));
  return f;
}

}  // namespace wetdem::diagnose
