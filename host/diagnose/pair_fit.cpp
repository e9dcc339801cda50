#include "diagnose/pair_fit.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace wetdem::diagnose {

namespace {

// Points per axis of the coarse grid, and of the fine grid over the coarse minimum's neighbouring cells.
constexpr int kCoarse = 81, kFine = 41;

struct Point {
  double ua = 0.0, ub = 0.0, c = std::numeric_limits<double>::infinity();
};

// The additive emulator's prediction of cell k (fit_pair).
Prediction pair_at(const Emulator& first_alone, double ua_star, const Emulator& second_on_top, size_t k,
                   double ua, double ub) {
  Prediction p = second_on_top.at(k, ub);
  p.mean += first_alone.at(k, ua).mean - first_alone.at(k, ua_star).mean;
  return p;
}

}  // namespace

PairFit fit_pair(const std::vector<Cell>& cells, const Emulator& first_alone, double first_fitted,
                 const Emulator& second_on_top, const std::vector<size_t>& idx_in) {
  std::vector<size_t> idx = idx_in;
  if (idx.empty())
    for (size_t k = 0; k < cells.size(); ++k) idx.push_back(k);
  const double ua_star = std::log10(first_fitted);
  const auto chi = [&](double ua, double ub) {
    double s = 0;
    for (size_t k : idx) {
      const double z = z_score(cells[k], pair_at(first_alone, ua_star, second_on_top, k, ua, ub));
      if (std::isfinite(z)) s += z * z;  // NaN: a cell without a prediction
    }
    return s;
  };
  const double a0 = first_alone.u_lo(), a1 = first_alone.u_hi();
  const double b0 = second_on_top.u_lo(), b1 = second_on_top.u_hi();
  const double ha = (a1 - a0) / (kCoarse - 1), hb = (b1 - b0) / (kCoarse - 1);
  const auto search = [&](double alo, double ahi, double blo, double bhi, int n) {
    Point best;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double ua = alo + (ahi - alo) * i / (n - 1), ub = blo + (bhi - blo) * j / (n - 1);
        const double c = chi(ua, ub);
        if (c < best.c) best = {ua, ub, c};
      }
    return best;
  };
  Point m = search(a0, a1, b0, b1, kCoarse);
  m = search(std::max(a0, m.ua - ha), std::min(a1, m.ua + ha), std::max(b0, m.ub - hb),
             std::min(b1, m.ub + hb), kFine);
  // The stepwise fit for comparison: the first held at its fit, the second alone on top of it (the same
  // coarse-then-fine search along u_b).
  const auto along_b = [&](double blo, double bhi, int n, Point best) {
    for (int j = 0; j < n; ++j) {
      const double ub = blo + (bhi - blo) * j / (n - 1), c = chi(ua_star, ub);
      if (c < best.c) best = {ua_star, ub, c};
    }
    return best;
  };
  Point s = along_b(b0, b1, kCoarse, Point{});
  s = along_b(std::max(b0, s.ub - hb), std::min(b1, s.ub + hb), kFine, s);
  PairFit f;
  f.first = std::pow(10.0, m.ua);
  f.second = std::pow(10.0, m.ub);
  f.chi2 = m.c;
  f.chi2_stepwise = s.c;
  f.second_stepwise = std::pow(10.0, s.ub);
  if (f.chi2_stepwise < f.chi2) f.first = first_fitted, f.second = f.second_stepwise, f.chi2 = s.c;
  return f;
}

double loco_pair(const std::vector<Cell>& cells, const Emulator& first_alone, double first_fitted,
                 const Emulator& second_on_top) {
  std::vector<size_t> cond;
  const size_t n = conditions_of(cells, &cond).size();
  if (n < 2) throw std::invalid_argument("loco_pair: leave-one-condition-out needs two conditions");
  const double ua_star = std::log10(first_fitted);
  double s = 0;
  for (size_t c = 0; c < n; ++c) {
    std::vector<size_t> train;
    for (size_t k = 0; k < cells.size(); ++k)
      if (cond[k] != c) train.push_back(k);
    const PairFit f = fit_pair(cells, first_alone, first_fitted, second_on_top, train);
    const double ua = std::log10(f.first), ub = std::log10(f.second);
    for (size_t k = 0; k < cells.size(); ++k) {
      if (cond[k] != c) continue;
      const double z = z_score(cells[k], pair_at(first_alone, ua_star, second_on_top, k, ua, ub));
      if (std::isfinite(z)) s += z * z;
    }
  }
  return s;
}

}  // namespace wetdem::diagnose
