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

// The additive emulator's prediction of cell k (fit_pair): the first at member m, strength ua.
struct Additive {
  const std::vector<Emulator>& first;
  size_t m_star;
  double ua_star;
  const Emulator& second;
  Prediction at(size_t k, size_t m, double ua, double ub) const {
    Prediction p = second.at(k, ub);
    p.mean += first[m].at(k, ua).mean - first[m_star].at(k, ua_star).mean;
    return p;
  }
};

}  // namespace

PairFit fit_pair(const std::vector<Cell>& cells, const std::vector<Emulator>& first_members,
                 size_t fitted_member, double first_fitted, const Emulator& second_on_top,
                 const std::vector<size_t>& idx_in) {
  if (fitted_member >= first_members.size())
    throw std::invalid_argument("fit_pair: the fitted member is not among the first's members");
  std::vector<size_t> idx = idx_in;
  if (idx.empty())
    for (size_t k = 0; k < cells.size(); ++k) idx.push_back(k);
  const Additive e{first_members, fitted_member, std::log10(first_fitted), second_on_top};
  const auto chi = [&](size_t m, double ua, double ub) {
    double s = 0;
    for (size_t k : idx) {
      const double z = z_score(cells[k], e.at(k, m, ua, ub));
      if (std::isfinite(z)) s += z * z;  // NaN: a cell without a prediction
    }
    return s;
  };
  const double b0 = second_on_top.u_lo(), b1 = second_on_top.u_hi();
  const double hb = (b1 - b0) / (kCoarse - 1);
  PairFit f;
  f.chi2 = std::numeric_limits<double>::infinity();
  for (size_t m = 0; m < first_members.size(); ++m) {
    const double a0 = first_members[m].u_lo(), a1 = first_members[m].u_hi();
    const double ha = (a1 - a0) / (kCoarse - 1);
    const auto search = [&](double alo, double ahi, double blo, double bhi, int n) {
      Point best;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double ua = alo + (ahi - alo) * i / (n - 1), ub = blo + (bhi - blo) * j / (n - 1);
          const double c = chi(m, ua, ub);
          if (c < best.c) best = {ua, ub, c};
        }
      return best;
    };
    Point p = search(a0, a1, b0, b1, kCoarse);
    p = search(std::max(a0, p.ua - ha), std::min(a1, p.ua + ha), std::max(b0, p.ub - hb),
               std::min(b1, p.ub + hb), kFine);
    if (p.c < f.chi2)
      f.member = m, f.first = std::pow(10.0, p.ua), f.second = std::pow(10.0, p.ub), f.chi2 = p.c;
  }
  // The stepwise fit for comparison: the first held at its fit, the second alone on top of it (the same
  // coarse-then-fine search along u_b).
  const auto along_b = [&](double blo, double bhi, int n, Point best) {
    for (int j = 0; j < n; ++j) {
      const double ub = blo + (bhi - blo) * j / (n - 1), c = chi(fitted_member, e.ua_star, ub);
      if (c < best.c) best = {e.ua_star, ub, c};
    }
    return best;
  };
  Point s = along_b(b0, b1, kCoarse, Point{});
  s = along_b(std::max(b0, s.ub - hb), std::min(b1, s.ub + hb), kFine, s);
  f.chi2_stepwise = s.c;
  f.second_stepwise = std::pow(10.0, s.ub);
  if (f.chi2_stepwise <= f.chi2)
    f.member = fitted_member, f.first = first_fitted, f.second = f.second_stepwise, f.chi2 = s.c;
  return f;
}

double loco_pair(const std::vector<Cell>& cells, const std::vector<Emulator>& first_members,
                 size_t fitted_member, double first_fitted, const Emulator& second_on_top) {
  std::vector<size_t> cond;
  const size_t n = conditions_of(cells, &cond).size();
  if (n < 2) throw std::invalid_argument("loco_pair: leave-one-condition-out needs two conditions");
  const Additive e{first_members, fitted_member, std::log10(first_fitted), second_on_top};
  double s = 0;
  for (size_t c = 0; c < n; ++c) {
    std::vector<size_t> train;
    for (size_t k = 0; k < cells.size(); ++k)
      if (cond[k] != c) train.push_back(k);
    const PairFit f = fit_pair(cells, first_members, fitted_member, first_fitted, second_on_top, train);
    for (size_t k = 0; k < cells.size(); ++k) {
      if (cond[k] != c) continue;
      const double z = z_score(cells[k], e.at(k, f.member, std::log10(f.first), std::log10(f.second)));
      if (std::isfinite(z)) s += z * z;
    }
  }
  return s;
}

}  // namespace wetdem::diagnose
