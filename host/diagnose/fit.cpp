#include "diagnose/fit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <set>
#include <stdexcept>

namespace wetdem::diagnose {

namespace {

// argmin of f over [a, b]: a dense grid, then golden-section search in the grid cells around its minimum.
// Returns the minimiser and fills the grid values (for the interval).
struct GridMin {
  double u = 0.0, c = 0.0;
  int best = 0;
  std::vector<double> g;
};
template <class F>
GridMin grid_min(F&& f, double a, double b, int n) {
  GridMin m;
  const double h = (b - a) / (n - 1);
  m.g.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    m.g[size_t(i)] = f(a + h * i);
    if (m.g[size_t(i)] < m.g[size_t(m.best)]) m.best = i;
  }
  double lo = a + h * std::max(0, m.best - 1), hi = a + h * std::min(n - 1, m.best + 1);
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 40; ++it) {
    if (f1 < f2)
      hi = x2, x2 = x1, f2 = f1, x1 = hi - phi * (hi - lo), f1 = f(x1);
    else
      lo = x1, x1 = x2, f1 = f2, x2 = lo + phi * (hi - lo), f2 = f(x2);
  }
  m.u = 0.5 * (lo + hi);
  m.c = f(m.u);
  if (m.g[size_t(m.best)] < m.c) m.u = a + h * m.best, m.c = m.g[size_t(m.best)];
  return m;
}

// The cells fitted: idx, or every cell when it is empty.
std::vector<size_t> fitted_cells(const std::vector<Cell>& cells, const std::vector<size_t>& idx) {
  if (!idx.empty()) return idx;
  std::vector<size_t> all(cells.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = k;
  return all;
}

// χ² over the cells idx at u = log10(strength), with the emulator's SE in every cell's variance.
double chi2_at(const std::vector<Cell>& cells, const Emulator& em, const std::vector<size_t>& idx, double u) {
  double s = 0;
  for (size_t k : idx) {
    const double z = z_score(cells[k], em.at(k, u));
    s += z * z;
  }
  return s;
}

constexpr int kStrengthGrid =
    401;  // points of the dense grid over [u_lo, u_hi] (fit_strength, widen_by_profile)

}  // namespace

StrengthFit fit_strength(const std::vector<Cell>& cells, const Emulator& em,
                         const std::vector<size_t>& idx_in) {
  const std::vector<size_t> idx = fitted_cells(cells, idx_in);
  // χ² with the emulator's SE in every cell's variance (the effective-variance method for a model that is
  // itself noisy). Its u-dependence pulls weak fits onto the knots, where that SE is largest; freezing the
  // weights (iteratively reweighted) or adding the Gaussian log-determinant removes the pull, but both fit
  // the interpolated slope between two noisy knots as if exact and are biased towards the middle of the
  // segment (errors in variables: +0.06 to +0.12 decades on DiagnoseStats.IntervalsStay...'s responses,
  // against < 0.01 here). This one is kept, and the interval is widened by the emulator's own noise instead
  // (widen_by_emulator_noise), which makes a fit on a knot honest about what it knows.
  auto chi = [&](double u) { return chi2_at(cells, em, idx, u); };
  constexpr int kGrid = kStrengthGrid;
  const double a = em.u_lo(), b = em.u_hi(), h = (b - a) / (kGrid - 1);
  const GridMin m = grid_min(chi, a, b, kGrid);
  const std::vector<double>& g = m.g;
  const int best = m.best;
  StrengthFit f;
  f.strength = std::pow(10.0, m.u);
  f.chi2 = m.c;
  f.at_hi = best == kGrid - 1;
  f.at_lo = m.u < em.u_first() - 1e-9 && em.u_first() > em.u_lo();
  f.at_edge = best == 0 || f.at_hi;
  f.delta = idx.size() > 1 ? std::max(1.0, m.c / double(idx.size() - 1)) : 1.0;
  int i_lo = best, i_hi = best;
  while (i_lo > 0 && g[size_t(i_lo - 1)] <= m.c + f.delta) --i_lo;
  while (i_hi < kGrid - 1 && g[size_t(i_hi + 1)] <= m.c + f.delta) ++i_hi;
  // The grid's points within delta, and the refined minimum itself: a fit so tight that χ² leaves the band
  // within one grid step (0.004 decades) would otherwise be the grid point beside its own strength.
  f.lo = std::min(std::pow(10.0, a + h * i_lo), f.strength);
  f.hi = std::max(std::pow(10.0, a + h * i_hi), f.strength);
  f.open_lo = i_lo == 0;
  f.open_hi = i_hi == kGrid - 1;
  f.chi2_lo = f.lo;
  f.chi2_hi = f.hi;
  return f;
}

namespace {

// The interval becomes its union with log10(strength) ± se, bounded by the probed range [u_lo, u_hi]; a side
// that reaches an end of that range (a hair of tolerance) is open there.
void widen_to(StrengthFit& f, double se, double u_lo, double u_hi) {
  const double u = std::log10(f.strength);
  constexpr double kTol = 1e-9;
  if (u - se < std::log10(f.lo)) {
    f.lo = std::pow(10.0, std::max(u_lo, u - se));
    if (u - se <= u_lo + kTol) f.open_lo = true;
  }
  if (u + se > std::log10(f.hi)) {
    f.hi = std::pow(10.0, std::min(u_hi, u + se));
    if (u + se >= u_hi - kTol) f.open_hi = true;
  }
}

}  // namespace

void widen_by_condition_jackknife(StrengthFit& f, const std::vector<double>& loco_strengths, double u_lo,
                                  double u_hi) {
  const size_t m = loco_strengths.size();
  if (m < 2) return;
  double mean = 0;
  for (double s : loco_strengths) mean += std::log10(s) / double(m);
  double ss = 0;
  for (double s : loco_strengths) ss += (std::log10(s) - mean) * (std::log10(s) - mean);
  const double se = std::sqrt(double(m - 1) / double(m) * ss);
  f.jackknife_se_log10 = se;
  widen_to(f, se, u_lo, u_hi);
}

void widen_by_emulator_noise(StrengthFit& f, const std::vector<Cell>& cells, const Emulator& em, int draws,
                             uint64_t seed) {
  if (draws < 2) return;
  std::mt19937_64 rng(seed);
  double m = 0, ss = 0;
  for (int d = 0; d < draws; ++d) {
    // Welford's running mean and sum of squares of the redrawn fits' log10 strengths.
    const double u = std::log10(fit_strength(cells, em.redrawn(rng)).strength), dm = u - m;
    m += dm / (d + 1);
    ss += dm * (u - m);
  }
  const double se = std::sqrt(ss / (draws - 1));
  f.emulator_se_log10 = se;
  widen_to(f, se, em.u_lo(), em.u_hi());
}

void set_two_se_interval(StrengthFit& f, double u_lo, double u_hi) {
  constexpr double kTol = 1e-9;
  const double u = std::log10(f.strength);
  const double a = u - 2.0 * (u - std::log10(f.lo)), b = u + 2.0 * (std::log10(f.hi) - u);
  // It always holds the reported interval (the profile's members may reach past this member's range).
  f.lo2 = std::min(f.lo, std::pow(10.0, std::max(u_lo, a)));
  f.hi2 = std::max(f.hi, std::pow(10.0, std::min(u_hi, b)));
  f.open_lo2 = f.open_lo || a <= u_lo + kTol;
  f.open_hi2 = f.open_hi || b >= u_hi - kTol;
}

ProfileFit fit_profile(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                       const std::vector<size_t>& idx) {
  if (ems.empty()) throw std::invalid_argument("fit_profile: one emulator per member, at least one");
  ProfileFit best;
  for (size_t j = 0; j < ems.size(); ++j) {
    const StrengthFit f = fit_strength(cells, ems[j], idx);
    if (j == 0 || f.chi2 < best.fit.chi2) best = {j, f};
  }
  return best;
}

size_t widen_by_profile(StrengthFit& f, const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                        size_t best, const std::vector<size_t>& idx_in) {
  const std::vector<size_t> idx = fitted_cells(cells, idx_in);
  const double threshold = f.chi2 + f.delta;
  constexpr int kGrid = kStrengthGrid;
  size_t reached = 0;
  for (size_t j = 0; j < ems.size(); ++j) {
    if (j == best) continue;
    const Emulator& em = ems[j];
    const double a = em.u_lo(), b = em.u_hi(), h = (b - a) / (kGrid - 1);
    int first = -1, last = -1;
    for (int i = 0; i < kGrid; ++i)
      if (chi2_at(cells, em, idx, a + h * i) <= threshold) last = i, first = first < 0 ? i : first;
    if (first < 0) continue;
    ++reached;
    // An open side stays open (the best member's included): it says the data allow any strength past it.
    f.lo = std::min(f.lo, std::pow(10.0, a + h * first));
    f.hi = std::max(f.hi, std::pow(10.0, a + h * last));
    f.open_lo = f.open_lo || first == 0;
    f.open_hi = f.open_hi || last == kGrid - 1;
  }
  f.chi2_lo = f.lo;
  f.chi2_hi = f.hi;
  f.profile_members = reached;
  return reached;
}

size_t fit_null_refit(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
                      const std::vector<size_t>& idx) {
  if (baselines.empty()) throw std::invalid_argument("fit_null_refit: one baseline per refit setting");
  if (idx.empty() && cells.empty()) return 0;
  size_t best = 0;
  double c_best = 0;
  for (size_t j = 0; j < baselines.size(); ++j) {
    const double c = idx.empty() ? chi2(cells, baselines[j]) : chi2(cells, baselines[j], idx);
    if (j == 0 || c < c_best) best = j, c_best = c;
  }
  return best;
}

namespace {

// The conditions' cells for leave-one-condition-out: per condition c, (train, test) index lists.
std::vector<std::pair<std::vector<size_t>, std::vector<size_t>>> loco_folds(const std::vector<Cell>& cells,
                                                                            const char* who) {
  std::vector<size_t> cond;
  const size_t nc = conditions_of(cells, &cond).size();
  if (nc < 2)
    throw std::invalid_argument(std::string(who) +
                                ": fewer than two conditions (no held-out check possible)");
  std::vector<std::pair<std::vector<size_t>, std::vector<size_t>>> folds(nc);
  for (size_t c = 0; c < nc; ++c)
    for (size_t k = 0; k < cells.size(); ++k) (cond[k] == c ? folds[c].second : folds[c].first).push_back(k);
  return folds;
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

// The held-out score of a condition predicted by a family's mixture (fit.h, loco_cells): member m has χ²
// `train_chi2[m]` on the fold's cells and held-out cell scores `test[m][i]` (-2 log density, up to a constant
// shared by the members). Its weight after the fold is w_m ∝ exp(-χ²_m/2) (a uniform prior over members);
// the mixture's score is -2 ln Σ_m w_m exp(-S_m/2), S_m = Σ_i test[m][i]. Writes one score per held-out
// cell into out[cells[i]]: each member's cell score weighted by its share of the mixture's density at the
// held-out observation, plus an equal part of the remainder, so the cells sum to the mixture's score.
void mixture_fold(const std::vector<double>& train_chi2, const std::vector<std::vector<double>>& test,
                  const std::vector<size_t>& cells, std::vector<double>& out) {
  const size_t n = train_chi2.size();
  auto lse = [](const std::vector<double>& v) {
    const double mx = *std::max_element(v.begin(), v.end());
    double acc = 0;
    for (double x : v) acc += std::exp(x - mx);
    return mx + std::log(acc);
  };
  std::vector<double> lw(n), la(n), tot(n, 0.0);
  for (size_t m = 0; m < n; ++m) {
    for (double x : test[m])
      if (std::isfinite(x)) tot[m] += x;
    lw[m] = -0.5 * train_chi2[m];
    la[m] = lw[m] - 0.5 * tot[m];
  }
  const double la_all = lse(la), score = -2.0 * (la_all - lse(lw));
  std::vector<double> r(n);
  double shared = 0;
  for (size_t m = 0; m < n; ++m) r[m] = std::exp(la[m] - la_all), shared += r[m] * tot[m];
  for (size_t i = 0; i < cells.size(); ++i) {
    double x = 0;
    for (size_t m = 0; m < n; ++m)
      if (std::isfinite(test[m][i])) x += r[m] * test[m][i];
    out[cells[i]] = x + (score - shared) / double(cells.size());
  }
}

}  // namespace

std::vector<double> loco_strengths(const std::vector<Cell>& cells, const std::vector<Emulator>& ems) {
  std::vector<double> s;
  loco_cells(cells, ems, &s);
  return s;
}

std::vector<double> loco_cells(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                               std::vector<double>* fold_strengths, const std::vector<double>* null_se) {
  std::vector<double> out(cells.size(), 0.0);
  if (fold_strengths) fold_strengths->clear();
  // One held-out cell's score under member m at log strength u: z² (+ the log-variance ratio with null_se).
  auto cell_score = [&](size_t m, size_t k, double u) {
    const Prediction p = ems[m].at(k, u);
    const double z = z_score(cells[k], p);
    const double z2 = z * z;
    if (!null_se || !std::isfinite(z) || k >= null_se->size() || !std::isfinite((*null_se)[k])) return z2;
    const double s2 = cells[k].sigma * cells[k].sigma;
    return z2 + std::log((s2 + p.se * p.se) / (s2 + (*null_se)[k] * (*null_se)[k]));
  };
  for (const auto& [train, test] : loco_folds(cells, "loco_score")) {
    std::vector<double> train_chi2;
    std::vector<std::vector<double>> scores(ems.size());
    size_t best = 0;
    double best_strength = 0;
    for (size_t m = 0; m < ems.size(); ++m) {
      const StrengthFit g = fit_strength(cells, ems[m], train);
      if (m == 0 || g.chi2 < train_chi2[best]) best = m, best_strength = g.strength;  // fit_profile's choice
      train_chi2.push_back(g.chi2);
      for (size_t k : test) scores[m].push_back(cell_score(m, k, std::log10(g.strength)));
    }
    if (fold_strengths) fold_strengths->push_back(best_strength);
    if (ems.size() == 1) {
      for (size_t i = 0; i < test.size(); ++i) out[test[i]] = scores[0][i];
      continue;
    }
    mixture_fold(train_chi2, scores, test, out);
  }
  return out;
}

std::vector<double> loco_draws(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                               const std::vector<size_t>& refit_of,
                               const std::vector<std::vector<std::vector<double>>>& anchors, uint64_t seed,
                               const std::vector<double>* null_se) {
  if (refit_of.size() != ems.size()) throw std::invalid_argument("loco_draws: one refit setting per member");
  std::mt19937_64 rng(seed);
  std::vector<double> out;
  for (const auto& anchor : anchors) {
    std::vector<Emulator> drawn;
    for (size_t j = 0; j < ems.size(); ++j) {
      if (refit_of[j] >= anchor.size())
        throw std::invalid_argument("loco_draws: no anchor for a refit setting");
      drawn.push_back(ems[j].redrawn(rng, anchor[refit_of[j]]));
    }
    out.push_back(sum(loco_cells(cells, drawn, nullptr, null_se)));
  }
  return out;
}

std::vector<std::vector<std::vector<double>>> anchor_draws(size_t draws, size_t settings, size_t cells,
                                                           uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<std::vector<std::vector<double>>> a(draws, std::vector<std::vector<double>>(settings));
  for (auto& d : a)
    for (auto& r : d)
      for (size_t k = 0; k < cells; ++k) r.push_back(n01(rng));
  return a;
}

double loco_score(const std::vector<Cell>& cells, const std::vector<Emulator>& ems) {
  return sum(loco_cells(cells, ems));
}

double loco_score(const std::vector<Cell>& cells, const Emulator& em) {
  return loco_score(cells, std::vector<Emulator>{em});
}

std::vector<double> loco_null_cells(const std::vector<Cell>& cells,
                                    const std::vector<std::vector<Prediction>>& baselines) {
  if (baselines.empty()) throw std::invalid_argument("loco_null: one baseline per refit setting");
  std::vector<double> out(cells.size(), 0.0);
  if (baselines.size() == 1) {
    for (size_t k = 0; k < cells.size(); ++k) {
      const double z = z_score(cells[k], baselines[0][k]);
      out[k] = z * z;
    }
    return out;
  }
  // The refit settings are the null's members: mixed as a candidate's are (loco_cells), so the two scores
  // treat their nuisance parameters alike.
  for (const auto& [train, test] : loco_folds(cells, "loco_null")) {
    std::vector<double> train_chi2;
    std::vector<std::vector<double>> scores(baselines.size());
    for (size_t j = 0; j < baselines.size(); ++j) {
      train_chi2.push_back(chi2(cells, baselines[j], train));
      for (size_t k : test) {
        const double z = z_score(cells[k], baselines[j][k]);
        scores[j].push_back(z * z);
      }
    }
    mixture_fold(train_chi2, scores, test, out);
  }
  return out;
}

double loco_null(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines) {
  return sum(loco_null_cells(cells, baselines));
}

double loco_null(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline) {
  return chi2(cells, baseline);
}

namespace {

// Strengths the stage asks for are kept to 3 significant digits (the store's run names and the report's
// text).
double round3(double x) {
  return std::stod(fmt::format("{:.3g}", x));
}

}  // namespace

double next_knot(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline, const Response& r) {
  const double s = round3(fit_strength(cells, Emulator(baseline, r)).strength);
  for (double k : r.strengths)
    if (std::fabs(std::log(s / k)) < 0.02) return 0.0;
  return s;
}

double probe_step(const std::vector<double>& strengths) {
  double step = 3.0;
  for (size_t i = 1; i < strengths.size(); ++i)
    if (strengths[i - 1] > 0) step = std::max(step, strengths[i] / strengths[i - 1]);
  return step;
}

std::vector<double> one_knot_bracket(const Response& r, double step, double phys_lo, double phys_hi) {
  if (r.strengths.size() != 1 || !(step > 1.0)) return {};
  const double s = r.strengths.front();
  std::vector<double> out;
  if (const double lo = std::max(phys_lo, round3(s / step)); lo * 1.25 <= s) out.push_back(lo);
  if (const double hi = std::min(phys_hi, round3(s * step)); hi >= 1.25 * s) out.push_back(hi);
  return out;
}

double next_edge_knot(const StrengthFit& f, const Response& r, double phys_lo, double phys_hi,
                      int* at_limit) {
  if (at_limit) *at_limit = 0;
  if (r.strengths.empty()) return 0.0;
  const double step = probe_step(r.strengths);
  if (f.at_hi || f.open_hi) {
    const double top = r.strengths.back();
    if (top >= phys_hi * (1.0 - 1e-9)) {
      if (at_limit) *at_limit = 1;
      return 0.0;
    }
    return std::min(phys_hi, round3(top * step));
  }
  if (f.at_lo) {
    const double bottom = r.strengths.front();
    if (bottom <= phys_lo * (1.0 + 1e-9)) {
      if (at_limit) *at_limit = -1;
      return 0.0;
    }
    return std::max(phys_lo, round3(bottom / step));
  }
  return 0.0;
}

MemberEdge next_member_edge(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                            const std::vector<const Response*>& responses, size_t best, double phys_lo,
                            double phys_hi) {
  if (responses.size() != ems.size())
    throw std::invalid_argument("next_member_edge: one response per emulator");
  MemberEdge e;
  for (size_t i = 0; i < ems.size(); ++i) {
    if (i == best || !responses[i]) continue;
    const StrengthFit f = fit_strength(cells, ems[i]);
    const double s = next_edge_knot(f, *responses[i], phys_lo, phys_hi);
    if (s > 0 && (e.member == MemberEdge::npos || f.chi2 < e.chi2)) e = {i, s, f.chi2};
  }
  return e;
}

std::vector<double> next_shapes_between(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                                        const std::vector<double>& shape_of, size_t best,
                                        double unexplained_above, double min_ratio) {
  if (shape_of.size() != ems.size()) throw std::invalid_argument("next_shapes_between: one shape per member");
  std::vector<double> out;
  if (best >= ems.size() || !(shape_of[best] > 0)) return out;
  const double v = shape_of[best];
  const auto unexplained = [&] {
    if (fit_strength(cells, ems[best]).chi2 > unexplained_above) return true;
    try {
      return loco_score(cells, ems[best]) > unexplained_above;
    } catch (const std::invalid_argument&) {
      return false;  // one condition: nothing to hold out
    }
  };
  if (!unexplained()) return out;
  std::set<double> listed;
  for (double s : shape_of)
    if (s > 0) listed.insert(s);
  const auto at = listed.find(v);
  std::vector<double> sides;
  if (at != listed.begin()) sides.push_back(*std::prev(at));
  if (std::next(at) != listed.end()) sides.push_back(*std::next(at));
  for (double other : sides) {
    if (std::max(v, other) / std::min(v, other) <= min_ratio) continue;
    const double mid = round3(std::sqrt(v * other));
    if (!listed.count(mid)) out.push_back(mid);
  }
  return out;
}

}  // namespace wetdem::diagnose
