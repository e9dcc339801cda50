#include "diagnose/baseline.h"

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
  p.seed1 = {p.predict(base, p.probe_seed)};
  const double r = double(p.base_seeds.size());
  p.spread.clear();
  for (size_t k = 0; k < p.tab.cells.size(); ++k)
    p.spread.push_back(std::max(p.baselines[0][k].se * std::sqrt(r), p.seed1[0][k].se));
}

}  // namespace wetdem::diagnose
