#include "diagnose/candidates.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "diagnose/where.h"

namespace wetdem::diagnose {

double screen_score(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                    const std::vector<Prediction>& probe) {
  if (baseline.size() != cells.size() || probe.size() != cells.size())
    throw std::invalid_argument("screen_score: one prediction per cell");
  double zr = 0, rr = 0;
  for (size_t k = 0; k < cells.size(); ++k) {
    const double s = std::sqrt(cells[k].sigma * cells[k].sigma + baseline[k].se * baseline[k].se);
    const double r = (probe[k].mean - baseline[k].mean) / s;
    zr += z_score(cells[k], baseline[k]) * r;
    rr += r * r;
  }
  return rr > 0 ? zr / std::sqrt(rr) : 0.0;
}

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
  return {lerp(mean_[cell]), std::max(0.0, lerp(se_[cell]))};
}

std::vector<Prediction> Emulator::at(double u) const {
  std::vector<Prediction> p;
  for (size_t k = 0; k < mean_.size(); ++k) p.push_back(at(k, u));
  return p;
}

StrengthFit fit_strength(const std::vector<Cell>& cells, const Emulator& em,
                         const std::vector<size_t>& idx_in) {
  std::vector<size_t> idx = idx_in;
  if (idx.empty())
    for (size_t k = 0; k < cells.size(); ++k) idx.push_back(k);
  auto chi = [&](double u) {
    double s = 0;
    for (size_t k : idx) {
      const double z = z_score(cells[k], em.at(k, u));
      s += z * z;
    }
    return s;
  };
  constexpr int kGrid = 401;
  const double a = em.u_lo(), b = em.u_hi(), h = (b - a) / (kGrid - 1);
  std::vector<double> g(kGrid);
  int best = 0;
  for (int i = 0; i < kGrid; ++i) {
    g[size_t(i)] = chi(a + h * i);
    if (g[size_t(i)] < g[size_t(best)]) best = i;
  }
  // Golden-section refinement inside the grid cell pair around the minimum.
  double lo = a + h * std::max(0, best - 1), hi = a + h * std::min(kGrid - 1, best + 1);
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo), f1 = chi(x1), f2 = chi(x2);
  for (int it = 0; it < 40; ++it) {
    if (f1 < f2)
      hi = x2, x2 = x1, f2 = f1, x1 = hi - phi * (hi - lo), f1 = chi(x1);
    else
      lo = x1, x1 = x2, f1 = f2, x2 = lo + phi * (hi - lo), f2 = chi(x2);
  }
  double u_best = 0.5 * (lo + hi), c_best = chi(u_best);
  if (g[size_t(best)] < c_best) u_best = a + h * best, c_best = g[size_t(best)];
  StrengthFit f;
  f.strength = std::pow(10.0, u_best);
  f.chi2 = c_best;
  f.at_edge = best == 0 || best == kGrid - 1;
  // Δχ² = 1 interval on the grid (clipped to the probed range).
  int i_lo = best, i_hi = best;
  while (i_lo > 0 && g[size_t(i_lo - 1)] <= c_best + 1.0) --i_lo;
  while (i_hi < kGrid - 1 && g[size_t(i_hi + 1)] <= c_best + 1.0) ++i_hi;
  f.lo = std::pow(10.0, a + h * i_lo);
  f.hi = std::pow(10.0, a + h * i_hi);
  return f;
}

RefitFit fit_refit(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                   const std::vector<size_t>& idx) {
  if (ems.empty()) throw std::invalid_argument("fit_refit: one emulator per refit setting, at least one");
  RefitFit best;
  for (size_t j = 0; j < ems.size(); ++j) {
    const StrengthFit f = fit_strength(cells, ems[j], idx);
    if (j == 0 || f.chi2 < best.fit.chi2) best = {j, f};
  }
  return best;
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

}  // namespace

double loco_score(const std::vector<Cell>& cells, const std::vector<Emulator>& ems) {
  double total = 0;
  for (const auto& [train, test] : loco_folds(cells, "loco_score")) {
    const RefitFit f = fit_refit(cells, ems, train);
    const double u = std::log10(f.fit.strength);
    for (size_t k : test) {
      const double z = z_score(cells[k], ems[f.setting].at(k, u));
      total += z * z;
    }
  }
  return total;
}

double loco_score(const std::vector<Cell>& cells, const Emulator& em) {
  return loco_score(cells, std::vector<Emulator>{em});
}

double loco_null(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline) {
  return chi2(cells, baseline);
}

double loco_null(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines) {
  if (baselines.size() == 1) return loco_null(cells, baselines.front());
  double total = 0;
  for (const auto& [train, test] : loco_folds(cells, "loco_null"))
    total += chi2(cells, baselines[fit_null_refit(cells, baselines, train)], test);
  return total;
}

std::pair<size_t, double> next_refit_knot(const std::vector<Cell>& cells,
                                          const std::vector<std::vector<Prediction>>& baselines,
                                          const std::vector<Response>& responses) {
  if (baselines.size() != responses.size())
    throw std::invalid_argument("next_refit_knot: one baseline and one response per refit setting");
  std::vector<Emulator> ems;
  for (size_t j = 0; j < baselines.size(); ++j) ems.emplace_back(baselines[j], responses[j]);
  const size_t j = fit_refit(cells, ems).setting;
  return {j, next_knot(cells, baselines[j], responses[j])};
}

Verdict decide(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Response>& responses, const std::vector<double>& screens,
               const VerdictRule& rule) {
  std::vector<std::vector<Response>> per_setting;
  for (const Response& r : responses) per_setting.push_back({r});
  return decide(cells, std::vector<std::vector<Prediction>>{baseline}, per_setting, screens, rule);
}

Verdict decide(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
               const std::vector<std::vector<Response>>& responses, const std::vector<double>& screens,
               const VerdictRule& rule) {
  if (screens.size() != responses.size())
    throw std::invalid_argument("decide: one screen score per response");
  if (baselines.empty()) throw std::invalid_argument("decide: one baseline per refit setting, at least one");
  Verdict v;
  v.null_loco = loco_null(cells, baselines);
  v.null_refit = fit_null_refit(cells, baselines);
  for (size_t i = 0; i < responses.size(); ++i) {
    if (responses[i].size() != baselines.size())
      throw std::invalid_argument("decide: one response per refit setting for every candidate");
    std::vector<Emulator> ems;
    for (size_t j = 0; j < baselines.size(); ++j) ems.emplace_back(baselines[j], responses[i][j]);
    Candidate c;
    c.effect = responses[i].front().effect;
    c.screen = screens[i];
    c.loco = loco_score(cells, ems);
    const RefitFit f = fit_refit(cells, ems);
    c.fit = f.fit;
    c.refit = f.setting;
    v.ranking.push_back(c);
  }
  std::stable_sort(v.ranking.begin(), v.ranking.end(),
                   [](const Candidate& a, const Candidate& b) { return a.loco < b.loco; });
  const std::vector<CellGap> g = where(cells, baselines.front(), rule.q);
  const bool any = std::any_of(g.begin(), g.end(), [](const CellGap& x) { return x.significant; });
  if (!v.ranking.empty())
    v.held_out_shrink = v.null_loco > 0 ? 1.0 - v.ranking.front().loco / v.null_loco : 0.0;
  // With refit, a gap the null closes at its re-fitted setting (no cell significant there, by the same rule)
  // needs no effect: the analogue of no_gap for the re-fitted model.
  const auto closed = [&] {
    if (baselines.size() < 2 || v.null_refit == 0) return false;
    const std::vector<CellGap> r = where(cells, baselines[v.null_refit], rule.q);
    return std::none_of(r.begin(), r.end(), [](const CellGap& x) { return x.significant; });
  };
  if (!any) {
    v.kind = "no_gap";
  } else if (closed()) {
    v.kind = "refit";
  } else if (!v.ranking.empty() && v.ranking.front().loco <= rule.ratio * v.null_loco &&
             v.null_loco - v.ranking.front().loco >= rule.min_drop) {
    v.kind = "effect";
    v.effect = v.ranking.front().effect;
  } else {
    v.kind = "unexplained";
  }
  return v;
}

double next_knot(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline, const Response& r) {
  const double s = std::stod(fmt::format("{:.3g}", fit_strength(cells, Emulator(baseline, r)).strength));
  for (double k : r.strengths)
    if (std::fabs(std::log(s / k)) < 0.02) return 0.0;
  return s;
}

void add_knot(Response& r, double strength, std::vector<Prediction> pred) {
  const auto at = std::upper_bound(r.strengths.begin(), r.strengths.end(), strength) - r.strengths.begin();
  r.strengths.insert(r.strengths.begin() + at, strength);
  r.pred.insert(r.pred.begin() + at, std::move(pred));
}

}  // namespace wetdem::diagnose
