#include "diagnose/next_bound.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "diagnose/next_experiment.h"

namespace wetdem::diagnose {

std::optional<OpenInterval> open_interval(const StrengthFit& f) {
  if (!f.open_lo && !f.open_hi) return std::nullopt;
  if (!(f.lo > 0) || !(f.hi >= kMinOpenRatio * f.lo)) return std::nullopt;
  OpenInterval o;
  o.both = f.open_lo && f.open_hi;
  o.above = f.open_hi;  // both open: from the weakest to the strongest, as open above
  o.closed = o.above ? f.lo : f.hi;
  o.open = o.above ? f.hi : f.lo;
  return o;
}

namespace {

const Candidate* chosen_candidate(const Verdict& v) {
  for (const Candidate& c : v.ranking)
    if (c.effect == v.effect) return &c;
  return nullptr;
}

// The two ends through the chosen member's emulator at every cell of the table: what the probes already say
// there (the ends' SEs come from the same knots, so the separation is conservative).
std::vector<Proposal> through_emulator(const Procedure& p, const Candidate& c, const OpenInterval& o,
                                       const MeasurementNoise& n) {
  std::vector<Proposal> out;
  MeasurementNoise plain = n;
  plain.typical_se2.clear();
  for (const Family& f : p.families()) {
    if (f.effect != c.effect || c.member >= f.ems.size()) continue;
    const Emulator& em = f.ems[c.member];
    for (size_t k = 0; k < p.tab.cells.size(); ++k) {
      const std::string& obs = p.tab.cells[k].observable;
      const Prediction x = em.at(k, std::log10(o.closed)), y = em.at(k, std::log10(o.open));
      if (!std::isfinite(x.mean) || !std::isfinite(y.mean)) continue;
      // The emulator's SEs are its knots' errors, not a run spread at the cell: the table's σ, as measured.
      out.push_back({p.tab.conditions[p.tab.cell_condition[k]].label, obs, x.mean, y.mean, x.se, y.se,
                     n.sigma.at(obs), separation_of(plain, obs, x, y), true, false, p.probe_seeds.size()});
    }
  }
  return out;
}

}  // namespace

void run_bound_experiment(Procedure& p) {
  p.bound = {};
  if ((p.verdict.kind != "effect" && p.verdict.kind != "partial") || p.d.next_conditions == 0) return;
  const Candidate* c = chosen_candidate(p.verdict);
  if (!c || p.fresh.empty() || p.fresh.front().effect != c->effect) return;
  const std::optional<OpenInterval> o = open_interval(c->fit);
  if (!o) return;
  BoundExperiment& b = p.bound;
  const FreshCheck& f = p.fresh.front();
  b.effect = c->effect;
  b.closed = o->closed;
  b.open = o->open;
  b.above = o->above;
  b.both = o->both;
  b.shape = f.shape;
  b.refit = f.refit;
  b.seeds = p.base_seeds.size();
  const MeasurementNoise noise = measurement_noise(p);
  b.proposals = through_emulator(p, *c, *o, noise);
  // Beyond the table, around the table's condition where the two ends lie furthest apart: a pore capacity
  // shows at the most liquid, a cohesion where bridges are fewest.
  size_t base = 0;
  double best = -1;
  for (size_t k = 0; k < b.proposals.size(); ++k)
    if (b.proposals[k].separation > best) {
      best = b.proposals[k].separation;
      for (size_t ci = 0; ci < p.tab.conditions.size(); ++ci)
        if (p.tab.conditions[ci].label == b.proposals[k].condition) base = ci;
    }
  std::vector<Condition> props =
      propose_conditions(p.tab.conditions, p.tab.conditions[base], p.models[0].rpm, p.models[0].duration_s,
                         p.d.next_conditions, max_drum_omega(p.models[0].drum_radius_m, p.d.max_froude));
  const Variant va = p.variant(b.effect, b.closed, b.refit, b.shape);
  const Variant vb = p.variant(b.effect, b.open, b.refit, b.shape);
  std::vector<Condition> wanted;
  const std::vector<Proposal> beyond = measure_beyond(p, va, vb, noise, props, wanted, "bound experiment");
  if (wanted.empty()) b.note = "no condition beyond the table could be run at both ends";
  b.proposals.insert(b.proposals.end(), beyond.begin(), beyond.end());
  const auto rank = [&] {
    rank_proposals(b.proposals);
    // A best measurement just short of kDecisive (cohesion-weak's 1.8 σ) may still bound the strength when it
    // is repeated: how often, for each.
    for (Proposal& q : b.proposals)
      q.repeats = repeats_for(q.model_a - q.model_b, q.sigma, q.se_a * q.se_a + q.se_b * q.se_b, kDecisive);
  };
  rank();
  // A repeated measurement is asked for only on the baseline's seeds: a condition beyond the table that ran
  // on one seed (measure_beyond's first round) and would need the fewest repeats runs the others first, and
  // is judged again over all of them, their spread included (a few rounds: the next fewest may be one-seed
  // too).
  for (int round = 0; round < 3 && !repeated_bound(b); ++round) {
    const Proposal* k = repeated_bound(b, /*unconfirmed=*/true);
    if (!k) break;
    const auto at = std::find_if(wanted.begin(), wanted.end(),
                                 [&](const Condition& w) { return w.label == k->condition; });
    if (at == wanted.end()) break;
    try {
      p.book.want(*at, va, p.base_seeds);
      p.book.want(*at, vb, p.base_seeds);
    } catch (const study::StudyError& e) {
      p.notes.push_back(
          fmt::format("bound experiment: {} cannot be run on every seed: {}", at->label, e.what()));
      break;
    }
    p.run();
    const std::string label = at->label;
    b.proposals.erase(std::remove_if(b.proposals.begin(), b.proposals.end(),
                                     [&](const Proposal& q) { return !q.in_table && q.condition == label; }),
                      b.proposals.end());
    const std::vector<Proposal> all = measure_at(p, va, vb, noise, *at, p.base_seeds, "bound experiment");
    b.proposals.insert(b.proposals.end(), all.begin(), all.end());
    rank();
  }
}

const Proposal* repeated_bound(const BoundExperiment& b, bool unconfirmed) {
  if (b.proposals.empty() || b.proposals.front().separation >= kDecisive) return nullptr;
  const Proposal* best = nullptr;
  for (const Proposal& q : b.proposals)
    if (q.repeats > 1 && (unconfirmed || q.in_table || q.seeds >= b.seeds) &&
        (!best || q.repeats < best->repeats))
      best = &q;  // ranked: the first of the fewest
  return best;
}

}  // namespace wetdem::diagnose
