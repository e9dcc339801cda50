#include "diagnose/next_experiment.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "diagnose/baseline.h"
#include "diagnose/files.h"
#include "diagnose/fit.h"
#include "diagnose/shrink.h"
#include "diagnose/where.h"
#include "wetdem/params.h"

namespace wetdem::diagnose {

namespace {

// "5 %" -> (5, " %"); "0.3" -> (0.3, "").
std::pair<double, std::string> split_number(const std::string& w) {
  size_t used = 0;
  double x = 0;
  try {
    x = std::stod(w, &used);
  } catch (const std::exception&) {
    return {std::nan(""), w};
  }
  return {x, w.substr(used)};
}

Condition with_value(const Condition& base, const std::string& key, const std::string& written) {
  Condition c;
  bool found = false;
  for (study::AxisValue a : base.values) {
    if (a.key == key)
      a.written = written, a.toml = toml_text_of_written(written), a.si = std::nan(""), found = true;
    c.values.push_back(a);
  }
  if (!found) c.values.push_back({key, written, toml_text_of_written(written), std::nan("")});
  std::sort(c.values.begin(), c.values.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
  c.label = condition_label(c.values);
  return c;
}

// A tied model as a rival: the members of its fitted candidate (refit settings x shapes), the one its fresh
// check ran first. Each with its response over the table and its variants: the null first, then one per
// strength. A member re-fits to a new measurement only where its response there is known: at the table's
// conditions every member's probes ran; beyond the table the first runs, and the others only when they fit
// the table within the first's Δ (the profile's members, widen_by_profile): a member the table already
// rejects cannot take the re-fit.
struct Member {
  const Response* response = nullptr;
  size_t refit = 0;
  bool beyond = false;  // run beyond the table
  std::vector<Variant> variants;
};

std::vector<Member> side_of(const Procedure& p, const FreshCheck& f) {
  std::vector<Member> out;
  const CandidateRuns* cr = nullptr;
  for (const CandidateRuns& c : p.fitted)
    if (c.effect == f.effect) cr = &c;
  if (!cr) return out;
  const auto member = [&](size_t i) {
    Member m;
    m.response = &cr->members[i];
    m.refit = cr->refit_of[i];
    const double shape = cr->shapes.at(cr->shape_of[i]);
    m.variants.push_back(p.variant("", 0.0, m.refit));
    for (double x : m.response->strengths) m.variants.push_back(p.variant(f.effect, x, m.refit, shape));
    return m;
  };
  for (size_t i = 0; i < cr->members.size(); ++i) {
    const double sh = cr->shapes.at(cr->shape_of[i]);
    if (cr->refit_of[i] == f.refit && (sh == f.shape || (std::isnan(sh) && std::isnan(f.shape))) &&
        !cr->members[i].strengths.empty())
      out.insert(out.begin(), member(i)), out.front().beyond = true;
  }
  if (out.empty()) return out;
  const StrengthFit first =
      fit_strength(p.tab.cells, Emulator(p.baselines[out.front().refit], *out.front().response));
  for (size_t i = 0; i < cr->members.size(); ++i) {
    if (&cr->members[i] == out.front().response || cr->members[i].strengths.empty()) continue;
    Member m = member(i);
    m.beyond = fit_strength(p.tab.cells, Emulator(p.baselines[m.refit], *m.response)).chi2 <=
               first.chi2 + first.delta;
    out.push_back(m);
  }
  return out;
}

// The refit separation (refit_rise) of the proposals at the table's conditions, where both models' probes
// ran, and at the best `next_refit` conditions beyond it, where both now also run at every strength they were
// probed at (on the probe seeds, with the null there: common random numbers, as the table's probes); then of
// pairs of those proposals and of each assay on every sample.
void add_refit_separations(Procedure& p, const FreshCheck& a, const FreshCheck& b,
                           std::vector<Condition>& beyond, std::map<std::string, double>& inflation) {
  if (p.d.next_refit == 0) return;
  const std::vector<Member> sa = side_of(p, a), sb = side_of(p, b);
  if (sa.empty() || sb.empty()) {
    p.notes.push_back("next experiment: no refit separation (a tied model has no probed response)");
    return;
  }
  std::map<std::string, Condition*> at;  // the conditions the models' responses are known at, by label
  for (Condition& c : p.tab.conditions) at[c.label] = &c;
  std::map<std::string, double> best;  // beyond the table: each condition's best separation
  for (const Proposal& q : p.next.proposals)
    if (!q.in_table) best[q.condition] = std::max(best[q.condition], q.separation);
  std::vector<Condition*> chosen;
  for (Condition& c : beyond)
    if (best.count(c.label) && best[c.label] >= 1.0) chosen.push_back(&c);  // below 1 σ nothing separates
  std::stable_sort(chosen.begin(), chosen.end(),
                   [&](const Condition* x, const Condition* y) { return best[x->label] > best[y->label]; });
  if (chosen.size() > p.d.next_refit) chosen.resize(p.d.next_refit);
  for (Condition* c : chosen) {
    try {
      for (const std::vector<Member>* side : {&sa, &sb})
        for (const Member& m : *side)
          if (m.beyond)
            for (const Variant& v : m.variants) p.book.want(*c, v, p.probe_seeds);
      at[c->label] = c;
    } catch (const study::StudyError& e) {
      p.notes.push_back(
          fmt::format("next experiment: {} cannot be run at every probed strength: {}", c->label, e.what()));
    }
  }
  p.run();
  // Member x of a rival at condition c for observable obs, the other model's value y ± y_se the
  // measurement with noise s (the proposal's, sigma_at); none where a run is missing, failed or does not
  // report obs. At a table cell the member's own emulator knots are used.
  const auto extra = [&](const std::string& label, const std::string& obs, double y, double y_se, double s,
                         const Member& x) -> std::optional<ExtraMeasurement> {
    if (!at.count(label)) return std::nullopt;
    const Condition& c = *at.at(label);
    ExtraMeasurement e;
    e.cell.observable = obs;
    e.cell.y = y;
    e.cell.sigma = std::sqrt(s * s + y_se * y_se);
    for (size_t k = 0; k < p.tab.cells.size(); ++k)
      if (p.tab.cells[k].observable == obs && p.tab.conditions[p.tab.cell_condition[k]].label == label) {
        e.null = p.baselines[x.refit][k];
        for (const auto& pred : x.response->pred) e.knots.push_back(pred[k]);
        return e;
      }
    for (size_t i = 0; i < x.variants.size(); ++i) {
      const Variant& v = x.variants[i];
      const std::vector<uint64_t>* seeds = &p.probe_seeds;
      if (!p.book.has_summaries({c}, v, *seeds)) seeds = &p.fresh_seeds;  // a knot of the fresh runs
      if (!p.book.has_summaries({c}, v, *seeds) || !p.book.failure({c}, v, *seeds).empty() ||
          !p.book.reports(c, v, *seeds, obs))
        return std::nullopt;
      Prediction q = p.book.predict(c, v, *seeds, obs, inflation[obs]);
      if (i == 0) {
        e.null = q;
        continue;
      }
      q.se = knot_se(0.0, q.se, seeds->size(), p.base_seeds.size());
      e.knots.push_back(q);
    }
    return e;
  };
  // Each proposal's extra measurement per member: of b as the rival (a right), of a as the rival (b right).
  using PerMember = std::vector<std::optional<ExtraMeasurement>>;
  std::vector<std::pair<PerMember, PerMember>> ex(p.next.proposals.size());
  std::vector<bool> has(p.next.proposals.size(), false);
  const auto family = [&](const std::vector<Member>& side, bool side_b, const std::vector<size_t>& set) {
    std::vector<RivalMember> f;
    for (size_t m = 0; m < side.size(); ++m) {
      RivalMember r{&p.baselines[side[m].refit], side[m].response, {}, true};
      for (size_t i : set) {
        const std::optional<ExtraMeasurement>& e = side_b ? ex[i].first[m] : ex[i].second[m];
        if (!e) r.known = false;
        if (r.known) r.extra.push_back(*e);
      }
      f.push_back(r);
    }
    return f;
  };
  const auto rises = [&](const std::vector<size_t>& set) {
    return refit_separation(refit_rise(p.tab.cells, family(sb, true, set)),
                            refit_rise(p.tab.cells, family(sa, false, set)));
  };
  for (size_t i = 0; i < p.next.proposals.size(); ++i) {
    Proposal& q = p.next.proposals[i];
    for (const Member& m : sb)
      ex[i].first.push_back(extra(q.condition, q.observable, q.model_a, q.se_a, q.sigma, m));
    for (const Member& m : sa)
      ex[i].second.push_back(extra(q.condition, q.observable, q.model_b, q.se_b, q.sigma, m));
    if (!ex[i].first.front() || !ex[i].second.front()) continue;  // the fitted members must be known
    has[i] = true;
    q.refit_separation = rises({i});
  }
  // Pairs of the best eight at two conditions (two observables at one condition share its runs' noise).
  std::vector<size_t> top;
  for (size_t i = 0; i < has.size(); ++i)
    if (has[i]) top.push_back(i);
  std::stable_sort(top.begin(), top.end(), [&](size_t x, size_t y) {
    return p.next.proposals[x].refit_separation > p.next.proposals[y].refit_separation;
  });
  if (top.size() > 8) top.resize(8);
  for (size_t u = 0; u < top.size(); ++u)
    for (size_t w = u + 1; w < top.size(); ++w) {
      const Proposal &x = p.next.proposals[top[u]], &y = p.next.proposals[top[w]];
      if (x.condition == y.condition) continue;
      p.next.pairs.push_back({x, y, std::hypot(x.separation, y.separation), rises({top[u], top[w]})});
    }
  std::stable_sort(
      p.next.pairs.begin(), p.next.pairs.end(),
      [](const ProposalPair& x, const ProposalPair& y) { return x.refit_separation > y.refit_separation; });
  if (p.next.pairs.size() > 5) p.next.pairs.resize(5);
  // Each assay on every sample of the table, both models re-fitted to all of it.
  for (AssaySeries& as : p.next.series) {
    std::vector<size_t> set;
    for (size_t i = 0; i < p.next.proposals.size(); ++i) {
      const Proposal& q = p.next.proposals[i];
      if (q.assay && q.in_table && q.observable == as.observable) {
        if (!has[i]) {
          set.clear();
          break;
        }
        set.push_back(i);
      }
    }
    if (!set.empty()) as.refit_separation = rises(set);
  }
}

}  // namespace

double max_drum_omega(double drum_radius_m, double max_froude) {
  if (!(drum_radius_m > 0) || !(max_froude > 0)) return std::numeric_limits<double>::infinity();
  const double g = glm::length(SimParams{}.gravity);  // the engine's gravity (no case key sets it)
  return std::sqrt(max_froude * g / drum_radius_m);   // Fr = ω²R/g
}

std::vector<Condition> propose_conditions(const std::vector<Condition>& table, const Condition& base,
                                          double model_rpm, double model_duration_s, size_t max,
                                          double max_omega) {
  std::vector<Condition> beyond, further, between;
  std::set<std::string> keys;
  for (const Condition& c : table)
    for (const auto& v : c.values) keys.insert(v.key);
  // A drum speed key (drum.rpm, drum.rotation...: its SI value is ω in rad/s, study_file.cpp's si_of_key).
  const auto speed_key = [](const std::string& key) {
    const std::string leaf = key.substr(key.rfind('.') == std::string::npos ? 0 : key.rfind('.') + 1);
    return leaf == "rpm" || leaf.rfind("rotation", 0) == 0;
  };
  for (const std::string& key : keys) {
    // The measured values (SI) and the unit the table writes them in (from a value with SI != 0).
    std::map<double, std::string> vals;
    double per_si = std::nan("");
    std::string unit;
    for (const Condition& c : table)
      for (const auto& v : c.values)
        if (v.key == key && std::isfinite(v.si)) {
          vals[v.si] = v.written;
          const auto [x, rest] = split_number(v.written);
          if (std::isfinite(x) && v.si != 0.0 && std::isnan(per_si)) per_si = x / v.si, unit = rest;
        }
    if (vals.size() < 2 || !std::isfinite(per_si)) continue;
    std::vector<double> si;
    for (const auto& [x, w] : vals) si.push_back(x);
    const auto written = [&](double x) { return fmt::format("{:.4g}{}", x * per_si, unit); };
    // A speed past max_omega is not a measurement a laboratory makes (the 60 mm drum at 240 rpm centrifuges;
    // absorption-0.05-at-10's second round proposed it, docs/twin_matrix_flowing.md).
    const auto add = [&](std::vector<Condition>& to, double x) {
      if (!(speed_key(key) && x > max_omega)) to.push_back(with_value(base, key, written(x)));
    };
    const double step = si.back() - si[si.size() - 2];
    add(beyond, si.back() + step);
    // Two steps past: a fingerprint that grows with the key may part two models only there, and a pair of
    // measurements one and two steps past lets the re-fit see the trend (evaporation-strong: 15 % then 20 %).
    add(further, si.back() + 2.0 * step);
    for (size_t i = 0; i + 1 < si.size(); ++i) add(between, 0.5 * (si[i] + si[i + 1]));
  }
  std::vector<Condition> out = beyond;
  if (!keys.count("drum.rpm") && model_rpm > 0) {
    constexpr double kRpm = 2.0 * 3.14159265358979323846 / 60.0;  // rad/s per rpm
    if (2.0 * model_rpm * kRpm <= max_omega)
      out.push_back(with_value(base, "drum.rpm", fmt::format("{:.4g}", 2.0 * model_rpm)));
    out.push_back(with_value(base, "drum.rpm", fmt::format("{:.4g}", 0.5 * model_rpm)));
  }
  // Four times as long, not twice: what tells a saturating sink (pore absorption) from a steady one
  // (evaporation) is the liquid left late in the run, and a window four times as long also has half the
  // noise.
  if (!keys.count("run.duration") && model_duration_s > 0)
    out.push_back(with_value(base, "run.duration", fmt::format("{:.4g} s", 4.0 * model_duration_s)));
  out.insert(out.end(), further.begin(), further.end());
  out.insert(out.end(), between.begin(), between.end());
  std::vector<Condition> unique;
  for (const Condition& c : out) {
    bool seen = c.label == base.label;
    for (const Condition& t : table) seen = seen || t.label == c.label;
    for (const Condition& u : unique) seen = seen || u.label == c.label;
    if (!seen && unique.size() < max) unique.push_back(c);
  }
  return unique;
}

std::vector<Condition> merge_conditions(std::vector<Condition> first, const std::vector<Condition>& second,
                                        size_t max_second) {
  size_t added = 0;
  for (const Condition& c : second) {
    if (added == max_second) break;
    const bool seen =
        std::any_of(first.begin(), first.end(), [&](const Condition& f) { return f.label == c.label; });
    if (!seen) first.push_back(c), ++added;
  }
  return first;
}

void rank_proposals(std::vector<Proposal>& proposals, double new_condition_factor) {
  const auto rank = [&](const Proposal& q) {
    const double s = judged_separation(q.refit_separation, q.separation);
    return q.in_table ? new_condition_factor * s : s;
  };
  std::stable_sort(proposals.begin(), proposals.end(), [&](const Proposal& x, const Proposal& y) {
    const bool fx = std::isfinite(x.refit_separation), fy = std::isfinite(y.refit_separation);
    if (fx != fy) return fx;
    return rank(x) > rank(y);
  });
}

size_t tie_repeats(const Proposal& q, double needed, size_t seeds) {
  if (!q.in_table && q.seeds < seeds) return 0;
  const double se2 = q.se_a * q.se_a + q.se_b * q.se_b;
  const double s = judged_separation(q.refit_separation, q.separation);
  return repeats_for(s * std::sqrt(q.sigma * q.sigma + se2), q.sigma, se2, needed);
}

Proposal compare_at(const Procedure& p, const Variant& a, const Variant& b, const MeasurementNoise& n,
                    const Condition& c, const std::vector<uint64_t>& seeds, const std::string& obs,
                    bool in_table) {
  const double f = n.inflation.count(obs) ? n.inflation.at(obs) : 1.0;
  const Prediction x = p.book.predict(c, a, seeds, obs, f), y = p.book.predict(c, b, seeds, obs, f);
  return Proposal{c.label,
                  obs,
                  x.mean,
                  y.mean,
                  x.se,
                  y.se,
                  sigma_at(n, obs, x.se, y.se),
                  separation_of(n, obs, x, y),
                  in_table,
                  p.d.assays.count(obs) > 0,
                  seeds.size()};
}

std::vector<Proposal> measure_at(Procedure& p, const Variant& a, const Variant& b, const MeasurementNoise& n,
                                 const Condition& c, const std::vector<uint64_t>& seeds,
                                 const std::string& stage) {
  std::vector<Proposal> out;
  const std::string fa = p.book.failure({c}, a, seeds), fb = p.book.failure({c}, b, seeds);
  if (!fa.empty() || !fb.empty()) {
    p.notes.push_back(stage + ": " + (fa.empty() ? fb : fa));
    return out;
  }
  std::set<std::string> observables;
  for (const Cell& cell : p.tab.cells) observables.insert(cell.observable);
  for (const auto& [obs, sd] : p.d.assays) observables.insert(obs);
  for (const std::string& obs : observables)
    if (p.book.reports(c, a, seeds, obs) && p.book.reports(c, b, seeds, obs))
      out.push_back(compare_at(p, a, b, n, c, seeds, obs, false));
  return out;
}

std::vector<Proposal> measure_beyond(Procedure& p, const Variant& a, const Variant& b,
                                     const MeasurementNoise& n, std::vector<Condition>& props,
                                     std::vector<Condition>& wanted, const std::string& stage) {
  // In two rounds to halve the cost where nothing separates: both models at every proposed condition on the
  // first seed (common random numbers: the pair's difference is less noisy than either), then the other seeds
  // only where some observable already separates them by kPromising; a condition that stays on one seed is
  // reported with its one-seed numbers (seeds = 1) and cannot be the best proposal by much.
  constexpr double kPromising = 2.0;
  const std::vector<uint64_t> first{p.base_seeds.front()};
  wanted.clear();
  for (Condition& c : props) {
    try {
      p.book.want(c, a, first);
      p.book.want(c, b, first);
      wanted.push_back(c);
    } catch (const study::StudyError& e) {
      p.notes.push_back(fmt::format("{}: {} cannot be run: {}", stage, c.label, e.what()));
    }
  }
  p.run();
  const auto measure = [&](const Condition& c, const std::vector<uint64_t>& seeds) {
    return measure_at(p, a, b, n, c, seeds, stage);
  };
  std::vector<std::vector<Proposal>> found;
  std::vector<bool> promising;
  for (Condition& c : wanted) {
    found.push_back(measure(c, first));
    bool any = false;
    for (const Proposal& q : found.back()) any = any || q.separation >= kPromising;
    promising.push_back(any && p.base_seeds.size() > 1);
    if (promising.back()) {
      p.book.want(c, a, p.base_seeds);
      p.book.want(c, b, p.base_seeds);
    }
  }
  p.run();
  std::vector<Proposal> out;
  for (size_t i = 0; i < wanted.size(); ++i) {
    if (promising[i])
      if (std::vector<Proposal> all = measure(wanted[i], p.base_seeds); !all.empty()) found[i] = all;
    out.insert(out.end(), found[i].begin(), found[i].end());
  }
  return out;
}

void run_next_experiment(Procedure& p) {
  p.next = {};
  if (p.verdict.tied.empty()) return;
  if (p.fresh.size() < 2 || p.fresh[0].after.empty() || p.fresh[1].after.empty()) {
    p.next.note = "the fresh runs of the tied models could not be made";
    return;
  }
  const FreshCheck &a = p.fresh[0], &b = p.fresh[1];
  p.next.effect_a = a.effect;
  p.next.effect_b = b.effect;
  const MeasurementNoise noise = measurement_noise(p);
  std::map<std::string, double> inflation = noise.inflation;
  // The table's own conditions, from the fresh runs (no new run).
  double best = -1;
  size_t base = 0;
  for (size_t k = 0; k < p.tab.cells.size(); ++k) {
    const std::string& obs = p.tab.cells[k].observable;
    Proposal q{p.tab.conditions[p.tab.cell_condition[k]].label,
               obs,
               a.after[k].mean,
               b.after[k].mean,
               a.after[k].se,
               b.after[k].se,
               sigma_at(noise, obs, a.after[k].se, b.after[k].se),
               separation_of(noise, obs, a.after[k], b.after[k]),
               true,
               false,
               p.fresh_seeds.size()};
    if (q.separation > best) best = q.separation, base = p.tab.cell_condition[k];
    p.next.proposals.push_back(q);
  }
  const size_t camera_base = base;  // where the table's own observables separate the pair most
  const Variant va = p.variant(a.effect, a.strength, a.refit, a.shape);
  const Variant vb = p.variant(b.effect, b.strength, b.refit, b.shape);
  // The assays at the table's conditions, from the same fresh runs (no new run).
  for (size_t ci = 0; ci < p.tab.conditions.size(); ++ci)
    for (const auto& [obs, sd] : p.d.assays) {
      const Condition& c = p.tab.conditions[ci];
      if (!p.book.reports(c, va, p.fresh_seeds, obs) || !p.book.reports(c, vb, p.fresh_seeds, obs)) continue;
      const Proposal q = compare_at(p, va, vb, noise, c, p.fresh_seeds, obs, true);
      if (q.separation > best) best = q.separation, base = ci;
      p.next.proposals.push_back(q);
    }
  // Beyond the table (measure_beyond).
  const double max_omega = max_drum_omega(p.models[0].drum_radius_m, p.d.max_froude);
  std::vector<Condition> props = propose_conditions(p.tab.conditions, p.tab.conditions[base], p.models[0].rpm,
                                                    p.models[0].duration_s, p.d.next_conditions, max_omega);
  // When an assay moved the base, the table's own observables are also tried around their own best
  // condition (half as many conditions): a laboratory that cannot make the assay still gets the best
  // measurement it can make beyond the table.
  if (camera_base != base)
    props =
        merge_conditions(props,
                         propose_conditions(p.tab.conditions, p.tab.conditions[camera_base], p.models[0].rpm,
                                            p.models[0].duration_s, p.d.next_conditions, max_omega),
                         (p.d.next_conditions + 1) / 2);
  std::vector<Condition> wanted;
  const std::vector<Proposal> beyond = measure_beyond(p, va, vb, noise, props, wanted, "next experiment");
  p.next.proposals.insert(p.next.proposals.end(), beyond.begin(), beyond.end());
  // Each assay on every sample of the table: separations at independent conditions add in quadrature.
  for (const auto& [obs, sd] : p.d.assays) {
    AssaySeries as{obs, 0, 0.0};
    for (const Proposal& q : p.next.proposals)
      if (q.assay && q.in_table && q.observable == obs)
        ++as.conditions, as.separation += q.separation * q.separation;
    as.separation = std::sqrt(as.separation);
    if (as.conditions > 1) p.next.series.push_back(as);
  }
  add_refit_separations(p, a, b, wanted, inflation);
  p.next.needed = needed_separation(chi2_of(a.gaps_after), p.tab.cells.size(), p.d.rule, p.verdict.seed_luck);
  std::sort(p.next.series.begin(), p.next.series.end(), [](const AssaySeries& x, const AssaySeries& y) {
    return judged_separation(x.refit_separation, x.separation) >
           judged_separation(y.refit_separation, y.separation);
  });
  rank_proposals(p.next.proposals);
  if (!p.next.proposals.empty())
    p.next.repeats =
        tie_repeats(p.next.proposals.front(), std::max(kDecisive, p.next.needed), p.base_seeds.size());
}

}  // namespace wetdem::diagnose
