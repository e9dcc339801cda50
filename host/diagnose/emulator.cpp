#include "diagnose/emulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem::diagnose {

Emulator::Emulator(const std::vector<Prediction>& baseline, const Response& r) {
  if (r.strengths.empty() || r.strengths.size() != r.pred.size())
    throw std::invalid_argument("Emulator: response of '" + r.effect +
                                "' needs predictions at >= 1 strength");
  for (size_t s = 0; s < r.strengths.size(); ++s) {
    if (!(r.strengths[s] > 0))
      throw std::invalid_argument("Emulator: strengths must be > 0 ('" + r.effect + "')");
    if (s && !(r.strengths[s] > r.strengths[s - 1]))
      throw std::invalid_argument("Emulator: strengths must ascend ('" + r.effect + "')");
    if (r.pred[s].size() != baseline.size())
      throw std::invalid_argument("Emulator: one prediction per cell at every strength ('" + r.effect + "')");
  }
  u_.push_back(std::log10(r.strengths.front()) - 1.0);
  for (double s : r.strengths) u_.push_back(std::log10(s));
  for (size_t k = 0; k < baseline.size(); ++k) {
    std::vector<double> m{baseline[k].mean}, e{baseline[k].se};
    for (const auto& p : r.pred) m.push_back(p[k].mean), e.push_back(p[k].se);
    mean_.push_back(m);
    se_.push_back(e);
  }
}

Prediction Emulator::at(size_t cell, double u) const {
  u = std::clamp(u, u_.front(), u_.back());
  size_t i = 0;
  while (i + 2 < u_.size() && u > u_[i + 1]) ++i;
  const double t = u_.size() < 2 ? 0.0 : (u - u_[i]) / (u_[i + 1] - u_[i]);
  const auto lerp = [&](const std::vector<double>& y) {
    return u_.size() < 2 ? y[0] : y[i] + t * (y[i + 1] - y[i]);
  };
  // The SE of the interpolated mean: the knots' noises are independent, so var = (1-t)² se_i² + t² se_i+1².
  // (Interpolating the SE itself overstated it between knots, by up to √2 at the midpoint, while the mean
  // there averages two knots' noise: χ² dipped between knots and fits landed there. Measured on the flowing
  // matrix: knots at 0.0211 and 0.0333 J/m², the fit at 0.0236, the truth 0.02.)
  const auto se = [&](const std::vector<double>& e) {
    return u_.size() < 2 ? e[0] : std::hypot((1.0 - t) * e[i], t * e[i + 1]);
  };
  return {lerp(mean_[cell]), se(se_[cell])};
}

Emulator Emulator::redrawn(std::mt19937_64& rng) const {
  return redrawn(rng, {});
}

Emulator Emulator::redrawn(std::mt19937_64& rng, const std::vector<double>& anchor_z) const {
  std::normal_distribution<double> n01(0.0, 1.0);
  Emulator e = *this;
  for (size_t k = 0; k < e.mean_.size(); ++k)
    for (size_t i = 0; i < e.mean_[k].size(); ++i)
      e.mean_[k][i] += se_[k][i] * (i == 0 && k < anchor_z.size() ? anchor_z[k] : n01(rng));
  return e;
}

std::vector<Prediction> Emulator::at(double u) const {
  std::vector<Prediction> p;
  for (size_t k = 0; k < mean_.size(); ++k) p.push_back(at(k, u));
  return p;
}

void add_knot(Response& r, double strength, std::vector<Prediction> pred) {
  const auto at = std::upper_bound(r.strengths.begin(), r.strengths.end(), strength) - r.strengths.begin();
  r.strengths.insert(r.strengths.begin() + at, strength);
  r.pred.insert(r.pred.begin() + at, std::move(pred));
}

void drop_knot(Response& r, double strength) {
  for (size_t i = 0; i < r.strengths.size(); ++i)
    if (r.strengths[i] == strength) {
      r.strengths.erase(r.strengths.begin() + long(i));
      r.pred.erase(r.pred.begin() + long(i));
      return;
    }
}

}  // namespace wetdem::diagnose
