#include "diagnose/limits.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "diagnose/effects.h"
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
  if (first < runs.size()) l.ruled_out_from = runs[first].strength, l.ruled_delta = runs[first].delta;
  if (first > 0) l.allowed_to = runs[first - 1].strength, l.allowed_delta = runs[first - 1].delta;
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

std::vector<FreeShapeLimit> free_shape_limits(const std::vector<Limit>& limits) {
  std::vector<FreeShapeLimit> out;
  for (const Limit& l : limits) {
    if (!(l.shape > 0) || l.runs.empty()) continue;
    auto it =
        std::find_if(out.begin(), out.end(), [&](const FreeShapeLimit& f) { return f.effect == l.effect; });
    if (it == out.end()) it = out.insert(out.end(), FreeShapeLimit{l.effect, {}, 0.0, 0.0, {}});
    it->shapes.push_back(l.shape);
  }
  out.erase(
      std::remove_if(out.begin(), out.end(), [](const FreeShapeLimit& f) { return f.shapes.size() < 2; }),
      out.end());
  for (FreeShapeLimit& f : out) {
    std::sort(f.shapes.begin(), f.shapes.end());
    for (const double sh : f.shapes) {
      const Limit& l = *std::find_if(limits.begin(), limits.end(),
                                     [&](const Limit& x) { return x.effect == f.effect && x.shape == sh; });
      if (!(l.ruled_out_from > 0))
        f.open.emplace_back(sh, l.runs.back().strength);
      else if (l.ruled_out_from > f.ruled_out_from)
        f.ruled_out_from = l.ruled_out_from, f.binding = sh;
    }
    if (!f.open.empty()) f.ruled_out_from = f.binding = 0.0;
  }
  return out;
}

const Limit* default_limit(const std::vector<Limit>& limits, const std::string& effect) {
  const EffectSpec& e = effect_spec(effect);
  const double d = e.shapes.empty() ? 0.0 : e.default_shape();
  for (const Limit& l : limits)
    if (l.effect == effect && l.shape == d) return &l;
  return nullptr;
}

namespace {

// The shapes whose limits table_limits takes: none (0) for an effect without a second parameter; else the
// default first, then the listed ones (the diagnosis file's [shapes], else the catalogue's).
std::vector<double> limit_shapes(const Procedure& p, const std::string& effect) {
  const EffectSpec& spec = effect_spec(effect);
  if (spec.shapes.empty()) return {0.0};
  std::vector<double> out = {spec.default_shape()};
  const auto it = p.d.shapes.find(effect);
  for (const double sh : it != p.d.shapes.end() ? it->second : spec.shapes)
    if (std::find(out.begin(), out.end(), sh) == out.end()) out.push_back(sh);
  return out;
}

}  // namespace

std::vector<Limit> table_limits(const Procedure& p) {
  std::vector<Limit> out;
  if (p.verdict.kind != "no_gap" || p.baselines.empty()) return out;
  const std::vector<Prediction>& model = p.baselines[0];
  const double threshold = kRuleOutDelta * limit_scale(p.tab.cells, model);
  for (const std::string& e : p.effects) {
    const std::vector<double> shapes = limit_shapes(p, e);
    for (const double sh : shapes) {
      // The strengths run at every condition of the table: at the default shape the catalogue's probes (the
      // screen ran one), those the reach stepped past them and those run_limits ran; at another shape only
      // run_limits'.
      std::set<double> strengths;
      if (sh == shapes.front()) {
        if (auto it = p.d.probes.find(e); it != p.d.probes.end())
          strengths.insert(it->second.begin(), it->second.end());
        if (auto it = p.reach_strengths.find(e); it != p.reach_strengths.end())
          strengths.insert(it->second.begin(), it->second.end());
      }
      if (auto it = p.limit_strengths.find({e, sh}); it != p.limit_strengths.end())
        strengths.insert(it->second.begin(), it->second.end());
      std::vector<LimitRun> runs;
      for (const double s : strengths) {
        const Variant v = sh > 0 ? p.variant(e, s, 0, sh) : p.variant(e, s);
        if (!p.book.has_summaries(p.tab.conditions, v, p.probe_seeds) || !p.failure(v, p.probe_seeds).empty())
          continue;
        LimitRun x = limit_run(p.tab.cells, model, p.probe(v, 0), p.probe_seeds.size(), p.base_seeds.size());
        x.strength = s;
        runs.push_back(x);
      }
      if (runs.empty()) continue;
      out.push_back(limit_of(e, std::move(runs), threshold));
      out.back().shape = sh;
    }
  }
  return out;
}

double next_limit_strength(const Limit& l, double step, double phys_lo, double phys_hi, bool climb) {
  step = std::max(step, 1.25);
  double s = 0.0;
  if (!(l.ruled_out_from > 0)) {
    // Straight to the end of the physical range: one run there says whether this shape rules anything out
    // at all (a sink is monotonic in its capacity), and if it does, the next rounds bisect the bracket it
    // makes; climbing a probe step per round could spend every round short of an answer.
    if (!climb || l.runs.empty() || !(l.runs.back().strength < phys_hi)) return 0.0;
    s = phys_hi;
  } else if (!(l.allowed_to > 0)) {
    s = std::max(phys_lo, rounded_strength(l.ruled_out_from / step));
  } else if (l.ruled_out_from / l.allowed_to > kLimitRatio) {
    s = rounded_strength(std::sqrt(l.ruled_out_from * l.allowed_to));
  }
  if (!(s > 0) || (l.ruled_out_from > 0 && s >= l.ruled_out_from)) return 0.0;
  for (const LimitRun& x : l.runs)
    if (std::fabs(s / x.strength - 1.0) < 0.1) return 0.0;
  return s;
}

void run_limits(Procedure& p) {
  p.limits = table_limits(p);
  for (int round = 0; round < p.d.limit_steps && !p.limits.empty(); ++round) {
    std::vector<Variant> asked;
    const std::vector<FreeShapeLimit> free = free_shape_limits(p.limits);  // this round's, as p.limits
    const auto ask = [&](const std::string& effect, double shape, double s) {
      const Variant v = shape > 0 ? p.variant(effect, s, 0, shape) : p.variant(effect, s);
      if (!p.failure(v, p.probe_seeds).empty()) return;  // failed before: noted then
      if (const std::string why = p.want(v, p.probe_seeds); !why.empty()) {
        p.notes.push_back(fmt::format("limits: {} {}", v.label(), why));
        return;
      }
      p.limit_strengths[{effect, shape}].insert(s);
      asked.push_back(v);
    };
    for (const std::string& e : p.effects) {
      const Limit* d = default_limit(p.limits, e);
      if (!d) continue;
      const EffectSpec& spec = effect_spec(e);
      const auto it = p.d.probes.find(e);
      const double step = probe_step(it != p.d.probes.end() ? it->second : spec.probes);
      for (const double sh : limit_shapes(p, e)) {
        const auto l = std::find_if(p.limits.begin(), p.limits.end(),
                                    [&](const Limit& x) { return x.effect == e && x.shape == sh; });
        if (l == p.limits.end()) {
          // Another shape, not run yet: from where the default shape is ruled out (nothing to profile
          // before).
          if (d->ruled_out_from > 0) ask(e, sh, d->ruled_out_from);
          continue;
        }
        // Another shape matters only where it sets the limit with the shape free: it climbs while it rules
        // nothing out, and brackets only when it binds (the others' brackets would not move that limit).
        const bool other = &*l != d;
        if (other && l->ruled_out_from > 0) {
          const auto f =
              std::find_if(free.begin(), free.end(), [&](const FreeShapeLimit& x) { return x.effect == e; });
          // Open at some shape (nothing there ruled out), or ruled out below the binding shape (ties bind).
          if (f == free.end() || !(f->ruled_out_from > 0) || l->ruled_out_from < f->ruled_out_from) continue;
        }
        if (const double s = next_limit_strength(*l, step, spec.phys_lo, spec.phys_hi, other); s > 0)
          ask(e, sh, s);
      }
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
