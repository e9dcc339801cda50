#include "diagnose/power.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "diagnose/next_experiment.h"
#include "diagnose/procedure.h"

namespace wetdem::diagnose {

double visible_chi2_excess(size_t cells) {
  // Wilson-Hilferty: the p-quantile of a χ² with n degrees of freedom is n (1 - 2/(9n) + z_p √(2/(9n)))³,
  // within 1 % for n >= 3; z = 2.326 for the upper 1 %.
  const double n = double(std::max<size_t>(1, cells)), a = 2.0 / (9.0 * n);
  return n * std::pow(1.0 - a + 2.326 * std::sqrt(a), 3) - n;
}

Shift shift_of(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Prediction>& probe) {
  Shift s;
  for (size_t k = 0; k < cells.size() && k < baseline.size() && k < probe.size(); ++k) {
    const double v = cells[k].sigma * cells[k].sigma + probe[k].se * probe[k].se;
    const double z = std::fabs(probe[k].mean - baseline[k].mean) / std::sqrt(v);
    if (!std::isfinite(z)) continue;
    ++s.cells;
    s.chi2_excess += z * z - probe[k].se * probe[k].se / v;
    if (z > s.max_z) s.max_z = z, s.cell = k;
  }
  return s;
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
        if (!p.book.has_summaries(p.tab.conditions, v, p.probe_seed) || !p.failure(v, p.probe_seed).empty())
          continue;
        const Shift sh = shift_of(p.tab.cells, p.baselines[0], p.probe(v, 0));
        r.strongest = std::max(r.strongest, s);
        if (sh.max_z > r.max_z) r.max_z = sh.max_z, r.at = s, r.cell = sh.cell;
        if (sh.chi2_excess > r.chi2_excess) r.chi2_excess = sh.chi2_excess, r.chi2_at = s;
      }
    r.visible = r.max_z >= kVisibleZ || r.chi2_excess >= visible_chi2_excess(p.tab.cells.size());
    out.push_back(r);
  }
  return out;
}

namespace {

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
                                           p.models[0].rpm, p.models[0].duration_s, p.d.reach_conditions)) {
      try {
        p.book.want(c, none, p.probe_seed);
        p.book.want(c, v, p.probe_seed);
        conds[i].push_back(c);
      } catch (const study::StudyError& e) {
        p.notes.push_back(fmt::format("reach: {} at {} cannot be run: {}", r.effect, c.label, e.what()));
      }
    }
  }
  p.run();
  const std::map<std::string, double> sigma = median_sigma(p.tab.cells);
  for (size_t i = 0; i < p.reach.size(); ++i) {
    Reach& r = p.reach[i];
    const Variant v = p.variant(r.effect, r.strongest);
    for (const Condition& c : conds[i]) {
      const std::string why = p.book.failure({c}, none, p.probe_seed) + p.book.failure({c}, v, p.probe_seed);
      if (!why.empty()) {
        p.notes.push_back(fmt::format("reach: {} at {}: {}", r.effect, c.label, why));
        continue;
      }
      r.beyond_tried.push_back(c.label);
      for (const auto& [obs, sd] : sigma) {
        if (!p.book.reports(c, v, p.probe_seed, obs) || !p.book.reports(c, none, p.probe_seed, obs)) continue;
        const Prediction x = p.book.predict(c, v, p.probe_seed, obs),
                         y = p.book.predict(c, none, p.probe_seed, obs);
        const double z = std::fabs(x.mean - y.mean) / std::sqrt(sd * sd + x.se * x.se + y.se * y.se);
        if (std::isfinite(z) && z > r.beyond_z)
          r.beyond_z = z, r.beyond_condition = c.label, r.beyond_observable = obs;
      }
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
      if (!p.failure(v, p.probe_seed).empty()) continue;
      if (const std::string why = p.want(v, p.probe_seed); !why.empty()) {
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
      if (const std::string why = p.failure(v, p.probe_seed); !why.empty())
        p.notes.push_back(
            fmt::format("reach: {} failed ({}); the reach is that of a weaker probe", v.label(), why));
    p.reach = table_reach(p);
  }
  run_beyond(p);
}

}  // namespace wetdem::diagnose
