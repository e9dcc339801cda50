// The diagnosis works on cells: one observed quantity (observable) at one condition (a set of case keys and
// values), with the observation and the model's prediction side by side. ../shared/spec/diagnosis.md §4.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace wetdem::diagnose {

struct Cell {
  std::map<std::string, double> condition;  // case key -> value in SI, e.g. {"liquid.content": 0.05}
  std::string observable;                   // a summary.json key, e.g. "aor_deg_mean"
  double y = 0.0;                           // observed mean
  double sigma = 0.0;                       // its standard deviation of the mean (> 0)
};

// A model's prediction of a cell: mean over replicates and its standard error (0 for one replicate with no
// window SE known; the caller should then pass the run's own window SE).
struct Prediction {
  double mean = 0.0;
  double se = 0.0;
};

// "liquid.content=0.05, drum.rpm=5": the label of a condition, canonical (keys sorted).
std::string condition_label(const std::map<std::string, double>& c);
// The distinct conditions of the cells, in order of first appearance, and each cell's index into them.
std::vector<std::string> conditions_of(const std::vector<Cell>& cells, std::vector<size_t>* cell_condition);

// z = (y - ŷ) / sqrt(σ² + SE²): the gap in units of its combined uncertainty.
double z_score(const Cell& c, const Prediction& p);
// Σ z² over the cells (indices; all when empty).
double chi2(const std::vector<Cell>& cells, const std::vector<Prediction>& pred,
            const std::vector<size_t>& idx = {});

}  // namespace wetdem::diagnose
