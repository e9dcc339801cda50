#include "diagnose/next_experiment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "diagnose/baseline.h"
#include "diagnose/files.h"
#include "diagnose/shrink.h"

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

// For each assay the file names ([assays]): the calibrated model's seed spread over its runs' own window
// SE at the table's conditions (as the baseline measures it for the table's observables, baseline.cpp), so
// that an assay's model error is the seed-to-seed one. 1 where fewer than two seeds report it.
std::map<std::string, double> assays_inflation(const Procedure& p) {
  std::map<std::string, double> f;
  const Variant base = p.variant("", 0);
  for (const auto& [obs, sd] : p.d.assays) {
    std::vector<Cell> cells;
    std::vector<std::vector<Prediction>> per_seed(p.base_seeds.size());
    for (const Condition& c : p.tab.conditions) {
      Cell cell;
      cell.observable = obs;
      cells.push_back(cell);
      for (size_t s = 0; s < p.base_seeds.size(); ++s)
        per_seed[s].push_back(p.book.reports(c, base, {p.base_seeds[s]}, obs)
                                  ? p.book.predict(c, base, {p.base_seeds[s]}, obs, 1.0)
                                  : Prediction{std::nan(""), std::nan("")});
    }
    f[obs] = within_inflation(cells, per_seed)[obs];
  }
  return f;
}

}  // namespace

std::vector<Condition> propose_conditions(const std::vector<Condition>& table, const Condition& base,
                                          double model_rpm, double model_duration_s, size_t max) {
  std::vector<Condition> beyond, between;
  std::set<std::string> keys;
  for (const Condition& c : table)
    for (const auto& v : c.values) keys.insert(v.key);
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
    beyond.push_back(with_value(base, key, written(si.back() + (si.back() - si[si.size() - 2]))));
    for (size_t i = 0; i + 1 < si.size(); ++i)
      between.push_back(with_value(base, key, written(0.5 * (si[i] + si[i + 1]))));
  }
  std::vector<Condition> out = beyond;
  if (!keys.count("drum.rpm") && model_rpm > 0) {
    out.push_back(with_value(base, "drum.rpm", fmt::format("{:.4g}", 2.0 * model_rpm)));
    out.push_back(with_value(base, "drum.rpm", fmt::format("{:.4g}", 0.5 * model_rpm)));
  }
  // Four times as long, not twice: what tells a saturating sink (pore absorption) from a steady one
  // (evaporation) is the liquid left late in the run, and a window four times as long also has half the
  // noise.
  if (!keys.count("run.duration") && model_duration_s > 0)
    out.push_back(with_value(base, "run.duration", fmt::format("{:.4g} s", 4.0 * model_duration_s)));
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

std::map<std::string, double> median_sigma(const std::vector<Cell>& cells) {
  std::map<std::string, std::vector<double>> sig;
  for (const Cell& c : cells) sig[c.observable].push_back(c.sigma);
  std::map<std::string, double> sigma;
  for (auto& [o, v] : sig) {
    std::sort(v.begin(), v.end());
    sigma[o] = v[v.size() / 2];
  }
  return sigma;
}

void rank_proposals(std::vector<Proposal>& proposals, double new_condition_factor) {
  const auto rank = [&](const Proposal& q) {
    return q.in_table ? new_condition_factor * q.separation : q.separation;
  };
  std::stable_sort(proposals.begin(), proposals.end(),
                   [&](const Proposal& x, const Proposal& y) { return rank(x) > rank(y); });
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
  std::map<std::string, double> sigma = median_sigma(p.tab.cells);
  std::map<std::string, double> inflation;  // per observable: seed spread over the runs' own window SE
  for (const Cell& c : p.tab.cells) inflation[c.observable] = p.inflation(c.observable);
  const std::map<std::string, double> assay_inflation = assays_inflation(p);
  for (const auto& [obs, sd] : p.d.assays) sigma[obs] = sd, inflation[obs] = assay_inflation.at(obs);
  const auto separation = [&](const std::string& obs, const Prediction& x, const Prediction& y) {
    return std::fabs(x.mean - y.mean) / std::sqrt(sigma[obs] * sigma[obs] + x.se * x.se + y.se * y.se);
  };
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
               sigma[obs],
               separation(obs, a.after[k], b.after[k]),
               true,
               false,
               p.fresh_seeds.size()};
    if (q.separation > best) best = q.separation, base = p.tab.cell_condition[k];
    p.next.proposals.push_back(q);
  }
  const size_t camera_base = base;  // where the table's own observables separate the pair most
  const Variant va = p.variant(a.effect, a.strength, a.refit, a.shape);
  const Variant vb = p.variant(b.effect, b.strength, b.refit, b.shape);
  // Both models' runs at condition c on these seeds, for one observable: each run's own window error scaled
  // to the baseline's seed spread (two seeds may agree by chance).
  const auto pair_at = [&](const Condition& c, const std::vector<uint64_t>& seeds, const std::string& obs,
                           bool in_table) {
    const Prediction x = p.book.predict(c, va, seeds, obs, inflation[obs]),
                     y = p.book.predict(c, vb, seeds, obs, inflation[obs]);
    return Proposal{c.label,     obs,
                    x.mean,      y.mean,
                    x.se,        y.se,
                    sigma[obs],  separation(obs, x, y),
                    in_table,    p.d.assays.count(obs) > 0,
                    seeds.size()};
  };
  const auto both_report = [&](const Condition& c, const std::vector<uint64_t>& seeds,
                               const std::string& obs) {
    return p.book.reports(c, va, seeds, obs) && p.book.reports(c, vb, seeds, obs);
  };
  // The assays at the table's conditions, from the same fresh runs (no new run).
  for (size_t ci = 0; ci < p.tab.conditions.size(); ++ci)
    for (const auto& [obs, sd] : p.d.assays) {
      if (!both_report(p.tab.conditions[ci], p.fresh_seeds, obs)) continue;
      const Proposal q = pair_at(p.tab.conditions[ci], p.fresh_seeds, obs, true);
      if (q.separation > best) best = q.separation, base = ci;
      p.next.proposals.push_back(q);
    }
  // Beyond the table, in two rounds to halve the cost where nothing separates: both models at every proposed
  // condition on the first seed (common random numbers: the pair's difference is less noisy than either),
  // then the other seeds only where some observable already separates them by kPromising; a condition that
  // stays on one seed is reported with its one-seed numbers (seeds = 1) and cannot be the best proposal by
  // much.
  constexpr double kPromising = 2.0;
  std::vector<Condition> props = propose_conditions(p.tab.conditions, p.tab.conditions[base], p.models[0].rpm,
                                                    p.models[0].duration_s, p.d.next_conditions);
  // When an assay moved the base, the table's own observables are also tried around their own best
  // condition (half as many conditions): a laboratory that cannot make the assay still gets the best
  // measurement it can make beyond the table.
  if (camera_base != base)
    props = merge_conditions(props,
                             propose_conditions(p.tab.conditions, p.tab.conditions[camera_base],
                                                p.models[0].rpm, p.models[0].duration_s, p.d.next_conditions),
                             (p.d.next_conditions + 1) / 2);
  const std::vector<uint64_t> first{p.base_seeds.front()};
  std::vector<Condition> wanted;
  for (Condition& c : props) {
    try {
      p.book.want(c, va, first);
      p.book.want(c, vb, first);
      wanted.push_back(c);
    } catch (const study::StudyError& e) {
      p.notes.push_back(fmt::format("next experiment: {} cannot be run: {}", c.label, e.what()));
    }
  }
  p.run();
  std::set<std::string> observables;
  for (const Cell& c : p.tab.cells) observables.insert(c.observable);
  for (const auto& [obs, sd] : p.d.assays) observables.insert(obs);
  // The proposals at condition c on these seeds; empty when a run failed (noted).
  const auto measure = [&](const Condition& c, const std::vector<uint64_t>& seeds) {
    std::vector<Proposal> out;
    const std::string fa = p.book.failure({c}, va, seeds), fb = p.book.failure({c}, vb, seeds);
    if (!fa.empty() || !fb.empty()) {
      p.notes.push_back("next experiment: " + (fa.empty() ? fb : fa));
      return out;
    }
    for (const std::string& obs : observables)
      if (both_report(c, seeds, obs)) out.push_back(pair_at(c, seeds, obs, false));
    return out;
  };
  std::vector<std::vector<Proposal>> found;
  std::vector<bool> promising;
  for (Condition& c : wanted) {
    found.push_back(measure(c, first));
    bool any = false;
    for (const Proposal& q : found.back()) any = any || q.separation >= kPromising;
    promising.push_back(any && p.base_seeds.size() > 1);
    if (promising.back()) {
      p.book.want(c, va, p.base_seeds);
      p.book.want(c, vb, p.base_seeds);
    }
  }
  p.run();
  for (size_t i = 0; i < wanted.size(); ++i) {
    if (promising[i])
      if (std::vector<Proposal> all = measure(wanted[i], p.base_seeds); !all.empty()) found[i] = all;
    p.next.proposals.insert(p.next.proposals.end(), found[i].begin(), found[i].end());
  }
  // Each assay on every sample of the table: separations at independent conditions add in quadrature.
  for (const auto& [obs, sd] : p.d.assays) {
    AssaySeries as{obs, 0, 0.0};
    for (const Proposal& q : p.next.proposals)
      if (q.assay && q.in_table && q.observable == obs)
        ++as.conditions, as.separation += q.separation * q.separation;
    as.separation = std::sqrt(as.separation);
    if (as.conditions > 1) p.next.series.push_back(as);
  }
  std::sort(p.next.series.begin(), p.next.series.end(),
            [](const AssaySeries& x, const AssaySeries& y) { return x.separation > y.separation; });
  rank_proposals(p.next.proposals);
}

}  // namespace wetdem::diagnose
