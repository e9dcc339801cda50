#include "diagnose/more_seeds.h"

#include <algorithm>
#include <cmath>

#include "diagnose/where.h"

namespace wetdem::diagnose {

double predicted_separation(const std::vector<Cell>& cells, const std::vector<Prediction>& a,
                            const std::vector<Prediction>& b, const std::vector<double>& diff_var,
                            double ratio) {
  double sum = 0.0;
  for (size_t i = 0; i < cells.size() && i < a.size() && i < b.size() && i < diff_var.size(); ++i) {
    const double d = a[i].mean - b[i].mean, w = diff_var[i];
    const double s2 = cells[i].sigma * cells[i].sigma + (a[i].se * a[i].se + b[i].se * b[i].se) * ratio;
    if (!std::isfinite(d) || !std::isfinite(w) || !std::isfinite(s2) || !(s2 > 0.0)) continue;
    sum += (d * d - w) / s2;
  }
  return std::max(0.0, sum);
}

std::vector<double> paired_difference_variance(const std::vector<std::vector<Prediction>>& a_by_seed,
                                               const std::vector<std::vector<Prediction>>& b_by_seed) {
  const size_t r = std::min(a_by_seed.size(), b_by_seed.size());
  const size_t n = r == 0 ? 0 : std::min(a_by_seed.front().size(), b_by_seed.front().size());
  std::vector<double> out(n, std::nan(""));
  if (r < 2) return out;
  for (size_t i = 0; i < n; ++i) {
    std::vector<double> d;
    for (size_t s = 0; s < r; ++s)
      if (i < a_by_seed[s].size() && i < b_by_seed[s].size())
        d.push_back(a_by_seed[s][i].mean - b_by_seed[s][i].mean);
    if (d.size() < r) continue;
    double mean = 0.0, ss = 0.0;
    for (double x : d) mean += x / double(r);
    for (double x : d) ss += (x - mean) * (x - mean);
    out[i] = ss / double(r - 1) / double(r);  // the sample variance of one difference, over R: of their mean
  }
  return out;
}

bool MoreSeeds::worth() const {
  if (!other.empty()) return true;
  return std::any_of(ties.begin(), ties.end(), [](const TieOutlook& t) { return t.could_decide(); });
}

namespace {

const FreshCheck* fresh_of(const Procedure& p, const std::string& effect) {
  for (const FreshCheck& f : p.fresh)
    if (f.effect == effect && f.failure.empty() && !f.after.empty()) return &f;
  return nullptr;
}

// A fresh check's predictions with each SE at least the model's run-to-run spread over √R: two seeds give an
// SE that is itself noisy, and an SE drawn small would read the models' noise as their difference
// (add_fresh_knot, shrink.cpp, does the same).
std::vector<Prediction> floored(const Procedure& p, const FreshCheck& f) {
  std::vector<Prediction> k = f.after;
  const double root_r = std::sqrt(double(std::max<size_t>(1, p.fresh_seeds.size())));
  for (size_t i = 0; i < k.size() && i < p.spread.size(); ++i)
    if (std::isfinite(p.spread[i])) k[i].se = std::max(k[i].se, p.spread[i] / root_r);
  return k;
}

// Var(Δ̂) per cell: from the two checks' per-seed differences (their runs share the fresh seeds), or where
// that cannot be had (one seed, a value missing) the independent sum se_a² + se_b².
std::vector<double> diff_variance(const Procedure& p, const FreshCheck& fa, const FreshCheck& fb,
                                  const std::vector<Prediction>& a, const std::vector<Prediction>& b) {
  std::vector<std::vector<Prediction>> by_a, by_b;
  if (p.fresh_seeds.size() >= 2) {
    const Variant va = p.variant(fa.effect, fa.strength, fa.refit, fa.shape);
    const Variant vb = p.variant(fb.effect, fb.strength, fb.refit, fb.shape);
    for (uint64_t s : p.fresh_seeds) {
      by_a.push_back(p.predict(va, {s}));
      by_b.push_back(p.predict(vb, {s}));
    }
  }
  std::vector<double> w = paired_difference_variance(by_a, by_b);
  w.resize(a.size(), std::nan(""));
  for (size_t i = 0; i < w.size() && i < b.size(); ++i)
    if (!std::isfinite(w[i])) w[i] = a[i].se * a[i].se + b[i].se * b[i].se;
  return w;
}

bool listed(const std::vector<std::string>& list, const std::string& e) {
  return std::find(list.begin(), list.end(), e) != list.end();
}

}  // namespace

MoreSeeds more_seeds_outlook(const Procedure& p, int to) {
  MoreSeeds m;
  m.from = int(p.d.replicates);
  m.to = to;
  const Verdict& v = p.verdict;
  const double ratio = double(m.from) / double(std::max(to, 1));
  const FreshCheck* chosen = fresh_of(p, v.effect);
  for (const std::string& e : v.tied) {
    TieOutlook t;
    t.effect = e;
    const FreshCheck* other = fresh_of(p, e);
    if (chosen && other) {
      const std::vector<Prediction> a = floored(p, *chosen), b = floored(p, *other);
      const std::vector<double> w = diff_variance(p, *chosen, *other, a, b);
      t.known = true;
      t.at_more = predicted_separation(p.tab.cells, a, b, w, ratio);
      t.exact = predicted_separation(p.tab.cells, a, b, w, 0.0);
      // The luck's leading term is the models' seed variance over the table, which falls as 1/R (measured
      // faster: 49.1 -> 18.0 from R = 2 to 4 on cohesion-weak, docs/validation.md).
      const double chi2_a = chi2_of(chosen->gaps_after);
      const auto margin_at = [&](int r) {
        return fresh_tie_margin(chi2_a, p.tab.cells.size(), p.d.rule, v.seed_luck * m.from / double(r));
      };
      t.margin = margin_at(to);
      for (int r = m.from + 1; r <= kMostSeeds && t.seeds_needed == 0; ++r)
        if (predicted_separation(p.tab.cells, a, b, w, double(m.from) / r) >= margin_at(r))
          t.seeds_needed = r;
    }
    m.ties.push_back(t);
  }
  for (const std::string& e : v.held_by_luck)
    if (!listed(v.tied, e))
      m.other.push_back(e == v.effect ? "`" + e + "` unconfirmed" : "`" + e + "` on top");
  if (gap_on_baseline_seeds_only(v.fresh_rejected, p.null_fresh, p.d.rule.table_level))
    m.other.push_back("a gap on the baseline's seeds only");
  return m;
}

bool undecided(const Procedure& p) {
  return !p.verdict.tied.empty() || !p.verdict.held_by_luck.empty() ||
         gap_on_baseline_seeds_only(p.verdict.fresh_rejected, p.null_fresh, p.d.rule.table_level);
}

}  // namespace wetdem::diagnose
