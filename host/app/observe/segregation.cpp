#include "app/observe/segregation.h"

#include <cmath>

namespace wetdem::observe {

double surface_size_ratio(const SystemState& s, const SurfaceResult& sf) {
  const size_t n = s.p.size();
  if (!sf.valid || sf.layer.empty() || n == 0) return std::nan("");
  double all = 0, top = 0;
  for (double r : s.p.radius) all += r;
  for (size_t k : sf.layer) top += s.p.radius[k];
  const double mean_all = all / static_cast<double>(n), mean_top = top / static_cast<double>(sf.layer.size());
  return mean_all > 0 ? mean_top / mean_all : std::nan("");
}

}  // namespace wetdem::observe
