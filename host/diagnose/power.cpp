#include "diagnose/power.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "diagnose/fit.h"
#include "diagnose/next_experiment.h"
#include "diagnose/procedure.h"
#include "diagnose/shrink.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

double visible_chi2_excess(size_t cells) {
  const size_t n = std::max<size_t>(1, cells);
  return chi2_upper_point(n, 0.01) - double(n);
}

namespace {

// z_k = (to - from) / sqrt(σ² + se_to² [+ se_from²]) and the χ² excess over the same own noise.
Shift shift_between(const std::vector<Cell>& cells, const std::vector<Prediction>& from,
                    const std::vector<Prediction>& to, bool from_noise) {
  Shift s;
  for (size_t k = 0; k < cells.size() && k < from.size() && k < to.size(); ++k) {
    const double own = to[k].se * to[k].se + (from_noise ? from[k].se * from[k].se : 0.0);
    const double v = cells[k].sigma * cells[k].sigma + own;
    const double z = std::fabs(to[k].mean - from[k].mean) / std::sqrt(v);
    if (!std::isfinite(z)) continue;
    ++s.cells;
    s.chi2_excess += z * z - own / v;
    if (z > s.max_z) s.max_z = z, s.cell = k;
  }
  return s;
}

}  // namespace

Shift shift_of(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Prediction>& probe) {
  return shift_between(cells, baseline, probe, false);
}

bool shows(const Shift& s, size_t cells) {
  return s.max_z >= kVisibleZ || s.chi2_excess >= visible_chi2_excess(cells);
}

Shift fresh_shift(const std::vector<Cell>& cells, const std::vector<Prediction>& control,
                  const std::vector<Prediction>& fresh) {
  return shift_between(cells, control, fresh, true);
}

bool names_unseen_lead(const Shift& sh, size_t n, double chi2_control, double chi2_fresh,
                       const VerdictRule& rule, double luck) {
  return shows(sh, n) && fresh_confirms(chi2_control, chi2_fresh, rule, luck);
}

bool fresh_shift_of(const Procedure& p, const std::string& effect, Shift* out, double* strength) {
  if (p.null_fresh.after.empty()) return false;
  for (const FreshCheck& f : p.fresh) {
    if (f.effect != effect) continue;
    if (f.after.empty() || f.refit != p.null_fresh.refit) return false;
    *out = fresh_shift(p.tab.cells, p.null_fresh.after, f.after);
    *strength = f.strength;
    return true;
  }
  return false;
}

std::vector<Reach> table_reach(const Procedure& p) {
  std::vector<Reach> out;
  for (const std::string& e : p.effects) {
    Reach r;
    r.effect = e;
    // The strengths with runs: the catalogue's probes (the screen ran one, the fit more) and whatever the fit
    // and the second round added (an extended range, refinement knots), at every shape value they ran.
    std::set<double> strengths;
    std::vector<double> shapes = {std::nan("")};  // NaN: the effect's default shape (not in a std::set)
    if (auto it = p.d.probes.find(e); it != p.d.probes.end())
      strengths.insert(it->second.begin(), it->second.end());
    if (auto it = p.reach_strengths.find(e); it != p.reach_strengths.end())
      strengths.insert(it->second.begin(), it->second.end());
    for (const std::vector<CandidateRuns>* list : {&p.fitted, &p.second.fitted})
      for (const CandidateRuns& c : *list) {
        if (c.effect != e) continue;
        for (size_t m = 0; m < c.members.size(); ++m) {
          if (c.refit_of[m] != 0) continue;
          strengths.insert(c.members[m].strengths.begin(), c.members[m].strengths.end());
          const double sh = c.shape_of[m] < c.shapes.size() ? c.shapes[c.shape_of[m]] : std::nan("");
          if (!std::isnan(sh) && std::find(shapes.begin(), shapes.end(), sh) == shapes.end())
            shapes.push_back(sh);
        }
      }
    for (const double s : strengths)
      for (const double shape : shapes) {
        const Variant v = p.variant(e, s, 0, shape);
        if (!p.book.has_summaries(p.tab.conditions, v, p.probe_seeds) || !p.failure(v, p.probe_seeds).empty())
          continue;
        const Shift sh = shift_of(p.tab.cells, p.baselines[0], p.probe(v, 0));
        r.strongest = std::max(r.strongest, s);
        if (sh.max_z > r.max_z) r.max_z = sh.max_z, r.at = s, r.cell = sh.cell;
        if (sh.chi2_excess > r.chi2_excess) r.chi2_excess = sh.chi2_excess, r.chi2_at = s;
      }
    r.by_probes = r.max_z >= kVisibleZ || r.chi2_excess >= visible_chi2_excess(p.tab.cells.size());
    r.visible = r.by_probes;
    Shift f;
    if (r.strongest > 0 && fresh_shift_of(p, e, &f, &r.fresh_at)) {
      r.fresh = true;
      r.fresh_max_z = f.max_z, r.fresh_cell = f.cell, r.fresh_chi2_excess = f.chi2_excess;
      r.seen_on_fresh = shows(f, p.tab.cells.size());
      r.visible = r.visible || r.seen_on_fresh;
    }
    out.push_back(r);
  }
  return out;
}

void mark_unseen(Procedure& p) {
  p.unseen.clear();
  // Called again after a widened fit (driver.cpp), whose rounds may have run another candidate's range
  // differently: the notes of the last call go, so the report states the reach the verdict was taken on.
  p.notes.erase(std::remove_if(p.notes.begin(), p.notes.end(),
                               [](const std::string& n) {
                                 return n.rfind("verdict: `", 0) == 0 &&
                                        n.find("` cannot be seen by the table: ") != std::string::npos;
                               }),
                p.notes.end());
  for (const Reach& r : table_reach(p)) {
    const bool fitted = std::any_of(p.fitted.begin(), p.fitted.end(),
                                    [&](const CandidateRuns& c) { return c.effect == r.effect; });
    if (!fitted || r.visible || r.strongest <= 0) continue;
    p.unseen.push_back(r.effect);
    const std::string note = fmt::format(
        "verdict: `{}` cannot be seen by the table: its runs up to {:.3g} move no cell by more than {:.1f} σ "
        "and the table's χ² by {:.1f} (visible from {} σ or {:.1f}), so its held-out score may follow the "
        "runs' own noise; it is never named first on that score alone",
        r.effect, r.strongest, r.max_z, r.chi2_excess, kVisibleZ, visible_chi2_excess(p.tab.cells.size()));
    if (std::find(p.notes.begin(), p.notes.end(), note) == p.notes.end())
      p.notes.push_back(note);  // widened fit
  }
}

Verdict decide_seen(Procedure& p) {
  Verdict v = decide(p.tab.cells, p.baselines, p.families(), p.d.rule);
  for (const std::string& n : name_only_seen(v, p.unseen, p.unseen_rejected, p.d.rule))
    if (std::find(p.notes.begin(), p.notes.end(), n) == p.notes.end()) p.notes.push_back(n);
  return v;
}

bool confirms_beyond(double z, size_t repeats, size_t seeds, size_t base_seeds, double screen) {
  // Confirmed, unconfirmable, or under the screen with nothing a repeated measurement would show.
  if (seeds == 0 || seeds >= base_seeds) return false;
  return z >= screen || repeats > 0;
}

double reach_screen_z(size_t replicates, size_t probe_seeds) {
  const size_t np = std::max<size_t>(1, probe_seeds);
  return kVisibleZ * std::sqrt(double(np) / double(std::max(np, replicates)));
}

WeakerBracket weaker_bracket(double strongest, double z, const std::vector<WeakerRun>& runs) {
  WeakerBracket b;
  if (!(z >= kVisibleZ) || !(strongest > 0)) return b;
  b.from = strongest, b.from_z = z;
  for (const WeakerRun& w : runs)
    if (w.z >= kVisibleZ && w.strength < b.from) b.from = w.strength, b.from_z = w.z;
  for (const WeakerRun& w : runs)
    if (!(w.z >= kVisibleZ) && w.strength < b.from && w.strength > b.below)
      b.below = w.strength, b.below_z = w.z;
  return b;
}

double next_weaker_strength(double strongest, double z, const std::vector<WeakerRun>& runs) {
  const WeakerBracket b = weaker_bracket(strongest, z, runs);
  if (!(b.from > 0)) return 0.0;
  const double s =
      rounded_strength(b.below > 0 ? std::sqrt(b.below * b.from) : b.from * kVisibleZ / b.from_z);
  // Within 10 % of a strength already run (the bracket's ends among them): not worth a run.
  if (!(s > 0) || std::fabs(s - strongest) < 0.1 * strongest) return 0.0;
  for (const WeakerRun& w : runs)
    if (std::fabs(s - w.strength) < 0.1 * w.strength) return 0.0;
  return s;
}

double next_reach_strength(double strongest, const std::vector<double>& probes, double hi) {
  if (!(strongest > 0) || !(hi > 0)) return 0.0;
  const double s = std::min(hi, rounded_strength(strongest * probe_step(probes)));
  return s >= 1.25 * strongest ? s : 0.0;
}

namespace {

// Past the file's strongest probe (run_reach, between its two parts; power.h). Each step runs, for every
// candidate still not shown, one strength more (one run per condition, the probe seeds), then re-reads the
// reach. A step the cost guard refuses is tried once at the geometric middle (the damper's time step limits
// viscous somewhere inside the range); a failed run ends the candidate's steps there, as in the fit stage.
void extend_reach(Procedure& p) {
  if (p.d.reach_steps <= 0) return;
  std::map<std::string, double> from;
  std::map<std::string, std::string> stop;
  for (int step = 0; step < p.d.reach_steps; ++step) {
    std::vector<Variant> asked;
    std::vector<std::string> who;
    for (const Reach& r : p.reach) {
      if (r.visible || r.strongest <= 0 || stop.count(r.effect)) continue;
      const EffectSpec& spec = effect_spec(r.effect);
      const auto it = p.d.probes.find(r.effect);
      const std::vector<double>& probes = it != p.d.probes.end() ? it->second : spec.probes;
      double s = next_reach_strength(r.strongest, probes, spec.realisable_hi(p.models[0]));
      if (s <= 0) {
        stop[r.effect] = "physical limit";
        continue;
      }
      std::string why;
      for (int attempt = 0; attempt < 2 && s > 0; ++attempt) {
        const Variant v = p.variant(r.effect, s);
        if (const std::string f = p.failure(v, p.probe_seeds); !f.empty()) {
          why = "failed";
          p.notes.push_back(fmt::format("reach: {} failed before ({}); it is not stepped past {:.3g}",
                                        v.label(), f, r.strongest));
          break;
        }
        const bool costly = p.cost(v) > p.d.max_cost;
        why = p.want(v, p.probe_seeds);
        if (why.empty()) {
          from.emplace(r.effect, r.strongest);
          p.reach_strengths[r.effect].insert(s);
          asked.push_back(v);
          who.push_back(r.effect);
          break;
        }
        p.notes.push_back(fmt::format("reach: {} {}", v.label(), why));
        why = costly ? "max_cost" : "cannot run";
        const double mid = rounded_strength(std::sqrt(s * r.strongest));
        s = mid >= 1.25 * r.strongest ? mid : 0.0;
      }
      if (!why.empty()) stop[r.effect] = why;
    }
    if (asked.empty()) break;
    p.run();
    for (size_t i = 0; i < asked.size(); ++i)
      if (const std::string why = p.failure(asked[i], p.probe_seeds); !why.empty()) {
        p.notes.push_back(
            fmt::format("reach: {} failed ({}); the reach is that of a weaker probe", asked[i].label(), why));
        stop[who[i]] = "failed";
      }
    p.reach = table_reach(p);
  }
  for (Reach& r : p.reach) {
    const auto f = from.find(r.effect);
    if (f != from.end()) r.extended_from = f->second;
    if (f != from.end() && r.by_probes)  // unseen up to `from`: the strongest step that ran is the one
      r.visible_from = r.strongest;
    else if (!r.visible && r.strongest > 0)
      r.extension_stop = stop.count(r.effect) ? stop[r.effect] : "reach_steps";
  }
}

// Where a candidate the table cannot see would show (run_reach, second part).
void run_beyond(Procedure& p) {
  if (p.d.reach_conditions == 0) return;
  const Variant none = p.variant("", 0.0);
  std::vector<std::vector<Condition>> conds(p.reach.size());
  for (size_t i = 0; i < p.reach.size(); ++i) {
    const Reach& r = p.reach[i];
    if (r.visible || r.strongest <= 0) continue;
    const Variant v = p.variant(r.effect, r.strongest);
    for (Condition& c : propose_conditions(p.tab.conditions, p.tab.conditions[p.tab.cell_condition[r.cell]],
                                           p.models[0].rpm, p.models[0].duration_s, p.d.reach_conditions,
                                           max_drum_omega(p.models[0].drum_radius_m, p.d.max_froude))) {
      try {
        p.book.want(c, none, p.probe_seeds);
        p.book.want(c, v, p.probe_seeds);
        conds[i].push_back(c);
      } catch (const study::StudyError& e) {
        p.notes.push_back(fmt::format("reach: {} at {} cannot be run: {}", r.effect, c.label, e.what()));
      }
    }
  }
  p.run();
  const std::map<std::string, double> sigma = median_sigma(p.tab.cells);
  const MeasurementNoise noise = measurement_noise(p);  // sigma_at: the spread of the runs at c in the noise
  // The largest shift of r's probe over the baseline at c, over the observables both report with these seeds:
  // z = |Δ| / √(σ_c² + se_probe² + se_base²), each se the larger of the seeds' spread and their own window
  // errors scaled to the baseline's seed spread (Procedure::within_inflation), σ_c the measurement's noise
  // there (sigma_at: the table's σ, with the excess of the runs' spread at c over the table's typical).
  struct Tried {
    Condition* c;
    double z;
    std::string observable;
    size_t seeds;
    size_t repeats;  // of the measurement, for kVisibleZ there (repeats_for); 0: none will do
    double sigma;    // the measurement's noise there (sigma_at)
  };
  // `only`: that observable alone (the weaker strength's check, measured where the strongest showed).
  const auto shift_at = [&](const Reach& r, Tried& t, const std::vector<uint64_t>& seeds,
                            double strength = 0.0, const std::string& only = "") {
    const Variant v = p.variant(r.effect, strength > 0 ? strength : r.strongest);
    t.z = 0.0;
    t.repeats = 0;
    t.sigma = 0.0;
    for (const auto& [obs, sd] : sigma) {
      if (!only.empty() && obs != only) continue;
      if (!p.book.reports(*t.c, v, seeds, obs) || !p.book.reports(*t.c, none, seeds, obs)) continue;
      const Prediction x = p.book.predict(*t.c, v, seeds, obs, p.inflation(obs)),
                       y = p.book.predict(*t.c, none, seeds, obs, p.inflation(obs));
      const double s = sigma_at(noise, obs, x.se, y.se);  // sd, widened where the runs at c spread more
      const double z = std::fabs(x.mean - y.mean) / std::sqrt(s * s + x.se * x.se + y.se * y.se);
      if (!std::isfinite(z) || z <= t.z) continue;
      t.z = z;
      t.observable = obs;
      t.sigma = s;
      t.repeats = repeats_for(x.mean - y.mean, s, x.se * x.se + y.se * y.se, kVisibleZ);
    }
  };
  std::vector<std::vector<Tried>> tried(p.reach.size());
  for (size_t i = 0; i < p.reach.size(); ++i) {
    Reach& r = p.reach[i];
    const Variant v = p.variant(r.effect, r.strongest);
    for (Condition& c : conds[i]) {
      const std::string why =
          p.book.failure({c}, none, p.probe_seeds) + p.book.failure({c}, v, p.probe_seeds);
      if (!why.empty()) {
        p.notes.push_back(fmt::format("reach: {} at {}: {}", r.effect, c.label, why));
        continue;
      }
      r.beyond_tried.push_back(c.label);
      Tried t{&c, 0.0, "", p.probe_seeds.size(), 0, 0.0};
      shift_at(r, t, p.probe_seeds);
      tried[i].push_back(t);
    }
  }
  const auto largest = [](std::vector<Tried>& ts) {
    return std::max_element(ts.begin(), ts.end(), [](const Tried& a, const Tried& b) { return a.z < b.z; });
  };
  // The probe seeds each side are a screen, not a claim: where the largest shift reaches the screen threshold
  // (reach_screen_z: 3 σ √(P/R)), the baseline's other seeds run there too (both sides) and the shift is
  // taken over all of them, their spread included; then the next largest, until the largest is confirmed or
  // under the threshold. The claim needs 3 σ over all the seeds: the wet bed's avalanches decorrelate runs
  // more than one window's error shows, so a single pair can differ by "4 σ" by chance, and as easily hide a
  // real shift.
  const double screen = reach_screen_z(p.base_seeds.size(), p.probe_seeds.size());
  while (p.base_seeds.size() > p.probe_seeds.size()) {
    std::vector<std::pair<size_t, Tried*>> confirm;
    for (size_t i = 0; i < p.reach.size(); ++i) {
      if (tried[i].empty()) continue;
      Tried& t = *largest(tried[i]);
      if (!confirms_beyond(t.z, t.repeats, t.seeds, p.base_seeds.size(), screen)) continue;
      const Variant v = p.variant(p.reach[i].effect, p.reach[i].strongest);
      try {
        p.book.want(*t.c, none, p.base_seeds);
        p.book.want(*t.c, v, p.base_seeds);
        confirm.emplace_back(i, &t);
      } catch (const study::StudyError& e) {
        p.notes.push_back(fmt::format("reach: {} at {}: the confirming seeds cannot be run: {}",
                                      p.reach[i].effect, t.c->label, e.what()));
        t.seeds = 0;  // unconfirmable: a screen's value, not run again
      }
    }
    if (confirm.empty()) break;
    p.run();
    for (auto& [i, t] : confirm) {
      const Variant v = p.variant(p.reach[i].effect, p.reach[i].strongest);
      const std::string why =
          p.book.failure({*t->c}, none, p.base_seeds) + p.book.failure({*t->c}, v, p.base_seeds);
      if (!why.empty()) {
        p.notes.push_back(fmt::format("reach: {} at {}: {}", p.reach[i].effect, t->c->label, why));
        t->seeds = 0;
        continue;
      }
      shift_at(p.reach[i], *t, p.base_seeds);
      t->seeds = p.base_seeds.size();
    }
  }
  for (size_t i = 0; i < p.reach.size(); ++i) {
    if (tried[i].empty()) continue;
    const Tried& t = *largest(tried[i]);
    Reach& r = p.reach[i];
    r.beyond_z = t.z, r.beyond_condition = t.c->label, r.beyond_observable = t.observable;
    r.beyond_sigma = t.sigma;
    r.beyond_seeds = t.seeds == 0 ? p.probe_seeds.size() : t.seeds;
    // Repeats are advised only on a shift the baseline's seeds all confirm (or that had no others).
    r.beyond_repeats = r.beyond_seeds >= p.base_seeds.size() ? t.repeats : 0;
  }
  // The promise is for the strongest strength; a weaker truth shifts less (the flowing viscous-weak twin,
  // 0.03 Pa s: promised 4.0 σ at 0.1 Pa s, measured 1.1 σ; docs/validation.md). Where the strongest shows by
  // kVisibleZ on the baseline's seeds, weaker strengths run there too, on those seeds (next_weaker_strength:
  // the proportional one, then the bracket's middle), so the report says from about which strength it shows
  // there as measured, not as a straight line gives.
  struct Weaker {
    size_t i;
    Tried t;
    bool done;
  };
  std::vector<Weaker> weaker;
  for (size_t i = 0; i < p.reach.size(); ++i) {
    const Reach& r = p.reach[i];
    if (!tried[i].empty() && r.beyond_z >= kVisibleZ && r.beyond_seeds >= p.base_seeds.size())
      weaker.push_back({i, *largest(tried[i]), false});
  }
  for (int step = 0; step < kWeakerSteps; ++step) {
    std::vector<std::pair<Weaker*, double>> asked;
    for (Weaker& w : weaker) {
      const Reach& r = p.reach[w.i];
      const double s = w.done ? 0.0 : next_weaker_strength(r.strongest, r.beyond_z, r.beyond_weaker);
      if (s <= 0) {
        w.done = true;
        continue;
      }
      const Variant v = p.variant(r.effect, s);
      if (const std::string f = p.failure(v, p.probe_seeds); !f.empty()) {
        p.notes.push_back(
            fmt::format("reach: {} failed before ({}); not run at {}", v.label(), f, w.t.c->label));
        w.done = true;
        continue;
      }
      try {
        p.book.want(*w.t.c, v, p.base_seeds);
        asked.emplace_back(&w, s);
      } catch (const study::StudyError& e) {
        p.notes.push_back(
            fmt::format("reach: {} at {}: cannot be run: {}", v.label(), w.t.c->label, e.what()));
        w.done = true;
      }
    }
    if (asked.empty()) break;
    p.run();
    for (auto& [w, s] : asked) {
      Reach& r = p.reach[w->i];
      const Variant v = p.variant(r.effect, s);
      if (const std::string why = p.book.failure({*w->t.c}, v, p.base_seeds); !why.empty()) {
        p.notes.push_back(fmt::format("reach: {} at {}: {}", v.label(), w->t.c->label, why));
        w->done = true;
        continue;
      }
      Tried t = w->t;
      shift_at(r, t, p.base_seeds, s, r.beyond_observable);
      r.beyond_weaker.push_back({s, t.z});
    }
  }
}

}  // namespace

void run_reach(Procedure& p) {
  p.reach = table_reach(p);
  std::vector<Variant> asked;
  for (const Reach& r : p.reach) {
    if (r.visible) continue;
    const auto it = p.d.probes.find(r.effect);
    if (it == p.d.probes.end()) continue;
    // The strongest probe that has not failed and may run; none when the strongest run so far is it.
    std::vector<double> probes = it->second;
    std::sort(probes.rbegin(), probes.rend());
    for (const double s : probes) {
      if (s <= r.strongest) break;
      const Variant v = p.variant(r.effect, s);
      if (!p.failure(v, p.probe_seeds).empty()) continue;
      if (const std::string why = p.want(v, p.probe_seeds); !why.empty()) {
        p.notes.push_back(fmt::format("reach: {} {}", v.label(), why));
        continue;
      }
      asked.push_back(v);
      break;
    }
  }
  if (!asked.empty()) {
    p.run();
    for (const Variant& v : asked)
      if (const std::string why = p.failure(v, p.probe_seeds); !why.empty())
        p.notes.push_back(
            fmt::format("reach: {} failed ({}); the reach is that of a weaker probe", v.label(), why));
    p.reach = table_reach(p);
  }
  extend_reach(p);
  run_beyond(p);
}

}  // namespace wetdem::diagnose
