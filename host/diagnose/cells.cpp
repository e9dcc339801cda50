#include "diagnose/cells.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem::diagnose {

std::string condition_label(const std::map<std::string, double>& c) {
  std::string s;
  for (const auto& [k, v] : c) s += (s.empty() ? "" : ", ") + fmt::format("{}={:.6g}", k, v);
  return s.empty() ? "(all)" : s;
}

std::vector<std::string> conditions_of(const std::vector<Cell>& cells, std::vector<size_t>* cell_condition) {
  std::vector<std::string> labels;
  if (cell_condition) cell_condition->clear();
  for (const Cell& c : cells) {
    const std::string l = condition_label(c.condition);
    auto it = std::find(labels.begin(), labels.end(), l);
    if (it == labels.end()) it = labels.insert(labels.end(), l);
    if (cell_condition) cell_condition->push_back(size_t(it - labels.begin()));
  }
  return labels;
}

double z_score(const Cell& c, const Prediction& p) {
  if (std::isnan(p.mean)) return std::nan("");  // no prediction (stage results may lack a cell)
  const double var = c.sigma * c.sigma + p.se * p.se;
  if (!(var > 0.0))
    throw std::invalid_argument("z_score: observation '" + c.observable + "' has no uncertainty");
  return (c.y - p.mean) / std::sqrt(var);
}

double chi2(const std::vector<Cell>& cells, const std::vector<Prediction>& pred,
            const std::vector<size_t>& idx) {
  if (pred.size() != cells.size()) throw std::invalid_argument("chi2: one prediction per cell");
  double s = 0.0;
  auto add = [&](size_t k) {
    const double z = z_score(cells[k], pred[k]);
    s += z * z;
  };
  if (idx.empty())
    for (size_t k = 0; k < cells.size(); ++k) add(k);
  else
    for (size_t k : idx) add(k);
  return s;
}

}  // namespace wetdem::diagnose
