#include "diagnose/limits.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "diagnose/fit.h"
#include "diagnose/procedure.h"
#include "diagnose/shrink.h"

namespace wetdem::diagnose {

double limit_noise_share(size_t probe_seeds, size_t replicates) {
  const double np = double(std::max<size_t>(1, probe_seeds)), r = double(std::max<size_t>(1, replicates));
  return std::max(0.0, (2.0 / np - 2.0 / r) / (2.0 / np + 1.0 / r));
}

LimitRun limit_run(const std::vector<Cell>& cells, const std::vector<Prediction>& model,
                   const std::vector<Prediction>& run, size_t probe_seeds, size_t replicates) {
  const double np = double(std::max<size_t>(1, probe_seeds)), r = double(std::max<size_t>(1, replicates));
  const double share = limit_noise_share(probe_seeds, replicates);
  LimitRun out;
  double var = 0.0;
  for (size_t k = 0; k < cells.size() && k < model.size() && k < run.size(); ++k) {
    // A run bitwise equal to the model there moved nothing (a liquid-only effect at a dry condition, on
    // common seeds; or a cell the run does not report, Procedure::probe): no shift and no noise.
    if (run[k].mean == model[k].mean) continue;
    // One variance for both sides: a likelihood ratio of two Gaussians of different widths would rule a
    // run out for its wider se alone (~50 cells of ln(v/v0) ~ 1 on the flowing table), whatever its mean.
    const double s2 = cells[k].sigma * cells[k].sigma, se2 = run[k].se * run[k].se, v = s2 + se2;
    const double z0 = cells[k].y - model[k].mean, z = cells[k].y - run[k].mean;
    const double term = (z * z - z0 * z0 - share * se2) / v;
    if (!std::isfinite(term)) continue;
    out.delta += term;
    // Its scatter without a shift: A = y - run and B = y - model are Gaussian with variances
    // a = σ² + 2s²/P - s²/R and b = σ² + s²/R and covariance c = σ² (s² the runs' seed noise,
    // se_run² / (2/P + 1/R); the probe seeds among the model's), so var(A² - B²) = 2 (a² + b² - 2c²).
    const double n2 = se2 / (2.0 / np + 1.0 / r);
    const double va = s2 + 2.0 * n2 / np - n2 / r, vb = s2 + n2 / r;
    var += 2.0 * (va * va + vb * vb - 2.0 * s2 * s2) / (v * v);
  }
  out.noise_sd = std::sqrt(var);
  return out;
}

double limit_scale(const std::vector<Cell>& cells, const std::vector<Prediction>& model) {
  double c2 = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < cells.size() && k < model.size(); ++k) {
    const double z = z_score(cells[k], model[k]);
    if (std::isfinite(z)) c2 += z * z, ++n;
  }
  return n > 1 ? std::max(1.0, c2 / double(n - 1)) : 1.0;
}

double rule_out_at(const LimitRun& x, double threshold) {
  return std::max(threshold, kRuleOutNoiseZ * x.noise_sd);
}

bool ruled_out(const LimitRun& x, double threshold) {
  return x.delta >= rule_out_at(x, threshold);
}

Limit limit_of(const std::string& effect, std::vector<LimitRun> runs, double threshold) {
  std::sort(runs.begin(), runs.end(),
            [](const LimitRun& a, const LimitRun& b) { return a.strength < b.strength; });
  Limit l;
  l.effect = effect;
  l.threshold = threshold;
  l.runs = runs;
  // The ruled-out tail: from the strongest run down, while each is ruled out. A weaker run ruled out under
  // an allowed stronger one is not a limit (seed noise, or a response that turns back).
  size_t first = runs.size();
  while (first > 0 && ruled_out(runs[first - 1], threshold)) --first;
  if (first < runs.size()) l.ruled_out_from = runs[first].strength;
  if (first > 0) l.allowed_to = runs[first - 1].strength;
  if (l.ruled_out_from > 0 && l.allowed_to > 0) {
    // In √Δ, a shift in units of the noise (Δ ~ Σ z² grows as the square of a small effect's shift), linear
    // in log strength between the two runs: b's √Δ >= √threshold > a's.
    const LimitRun &a = runs[first - 1], &b = runs[first];
    const double za = std::sqrt(std::max(0.0, a.delta)), zb = std::sqrt(b.delta);
    // Where √Δ crosses the larger of the two runs' thresholds (each counts its own seed noise).
    const double zt = std::sqrt(std::max(rule_out_at(a, threshold), rule_out_at(b, threshold)));
    const double t = std::clamp((zt - za) / (zb - za), 0.0, 1.0);
    l.about = std::pow(10.0, std::log10(a.strength) + t * (std::log10(b.strength) - std::log10(a.strength)));
  }
  return l;
}

std::vector<Limit> table_limits(const Procedure& p) {
  std::vector<Limit> out;
  if (p.verdict.kind != "no_gap" || p.baselines.empty()) return out;
  const std::vector<Prediction>& model = p.baselines[0];
  const double threshold = kRuleOutDelta * limit_scale(p.tab.cells, model);
  for (const std::string& e : p.effects) {
    // The strengths run at every condition of the table: the catalogue's probes (the screen ran one), those
    // the reach stepped past them and those run_limits ran, at the default shape (the screen's and theirs).
    std::set<double> strengths;
    if (auto it = p.d.probes.find(e); it != p.d.probes.end())
      strengths.insert(it->second.begin(), it->second.end());
    if (auto it = p.reach_strengths.find(e); it != p.reach_strengths.end())
      strengths.insert(it->second.begin(), it->second.end());
    if (auto it = p.limit_strengths.find(e); it != p.limit_strengths.end())
      strengths.insert(it->second.begin(), it->second.end());
    std::vector<LimitRun> runs;
    for (const double s : strengths) {
      const Variant v = p.variant(e, s);
      if (!p.book.has_summaries(p.tab.conditions, v, p.probe_seeds) || !p.failure(v, p.probe_seeds).empty())
        continue;
      LimitRun x = limit_run(p.tab.cells, model, p.probe(v, 0), p.probe_seeds.size(), p.base_seeds.size());
      x.strength = s;
      runs.push_back(x);
    }
    if (!runs.empty()) out.push_back(limit_of(e, std::move(runs), threshold));
  }
  return out;
}

double next_limit_strength(const Limit& l, double step, double phys_lo) {
  if (!(l.ruled_out_from > 0)) return 0.0;
  double s = 0.0;
  if (!(l.allowed_to > 0))
    s = std::max(phys_lo, rounded_strength(l.ruled_out_from / std::max(step, 1.25)));
  else if (l.ruled_out_from / l.allowed_to > kLimitRatio)
    s = rounded_strength(std::sqrt(l.ruled_out_from * l.allowed_to));
  if (!(s > 0) || s >= l.ruled_out_from) return 0.0;
  for (const LimitRun& x : l.runs)
    if (std::fabs(s / x.strength - 1.0) < 0.1) return 0.0;
  return s;
}

void run_limits(Procedure& p) {
  p.limits = table_limits(p);
  for (int round = 0; round < p.d.limit_steps && !p.limits.empty(); ++round) {
    std::vector<Variant> asked;
    for (const Limit& l : p.limits) {
      const EffectSpec& spec = effect_spec(l.effect);
      const auto it = p.d.probes.find(l.effect);
      const double s =
          next_limit_strength(l, probe_step(it != p.d.probes.end() ? it->second : spec.probes), spec.phys_lo);
      if (!(s > 0)) continue;
      const Variant v = p.variant(l.effect, s);
      if (!p.failure(v, p.probe_seeds).empty()) continue;  // failed before: noted then
      if (const std::string why = p.want(v, p.probe_seeds); !why.empty()) {
        p.notes.push_back(fmt::format("limits: {} {}", v.label(), why));
        continue;
      }
      p.limit_strengths[l.effect].insert(s);
      asked.push_back(v);
    }
    if (asked.empty()) break;
    p.run();
    for (const Variant& v : asked)
      if (const std::string why = p.failure(v, p.probe_seeds); !why.empty())
        p.notes.push_back(
            fmt::format("limits: {} failed ({}); the limit is bracketed without it", v.label(), why));
    p.limits = table_limits(p);
  }
}

}  // namespace wetdem::diagnose
