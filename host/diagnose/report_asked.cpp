// The measurements a report asks for (report.h, AskedMeasurement): one list, from the rules the paragraph
// states, so that report.md's checklist, diagnosis.json and the twin loop (scripts/twin_measure.py) name the
// same measurements.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "diagnose/effects.h"
#include "diagnose/next_bound.h"
#include "diagnose/next_experiment.h"
#include "diagnose/power.h"
#include "diagnose/report.h"

namespace wetdem::diagnose {

std::vector<AskedMeasurement> asked_measurements(const Report& r) {
  std::vector<AskedMeasurement> out;
  const auto add = [&](AskedMeasurement m) {
    for (const AskedMeasurement& x : out)
      if (x.condition == m.condition && x.observable == m.observable) return;  // the first asks for it
    out.push_back(std::move(m));
  };
  const auto from = [](const std::string& reason, const std::string& effect, const Proposal& q, size_t k,
                       double separation) {
    return AskedMeasurement{reason,       effect,     q.condition,
                            q.observable, q.sigma,    std::max<size_t>(1, k),
                            separation,   q.in_table, q.assay};
  };
  // The tie (paragraph_next.cpp next_sentence): its pair when the pair beats the single one made twice
  // (pair_beats_single), else the single one, made as often as it must be to decide (tie_repeats; 0: once).
  if (!r.next.proposals.empty()) {
    const std::string tie = r.next.effect_a + " or " + r.next.effect_b;
    const Proposal& q = r.next.proposals.front();
    if (!r.next.pairs.empty() && pair_beats_single(r.next.pairs.front(), q)) {
      const ProposalPair& w = r.next.pairs.front();
      add(from("tie", tie, w.first, 1, w.refit_separation));
      add(from("tie", tie, w.second, 1, w.refit_separation));
    } else {
      add(from("tie", tie, q, r.next.repeats, judged_separation(q.refit_separation, q.separation)));
    }
  }
  // The open interval (bound_sentence): the best measurement when it bounds by kDecisive, else the one that
  // does when repeated (repeated_bound), else none.
  const BoundExperiment& b = r.bound;
  if (!b.effect.empty() && !b.proposals.empty()) {
    const Proposal& q = b.proposals.front();
    if (q.separation >= kDecisive)
      add(from("bound", b.effect, q, 1, q.separation));
    else if (const Proposal* k = repeated_bound(b))
      add(from("bound", b.effect, *k, k->repeats, k->separation));
  }
  // Where a candidate the table cannot see would show (beyond_clause): once at kVisibleZ, or repeated. Its
  // noise is the one the reach assumed there (sigma_at), else the table's median σ of the observable, or an
  // assay's stated one.
  const std::map<std::string, double> sigma = median_sigma(r.cells);
  for (const Reach& x : r.reach) {
    if (x.visible || x.beyond_tried.empty() || x.beyond_observable.empty()) continue;
    const size_t k = x.beyond_z >= kVisibleZ ? 1 : x.beyond_repeats > 1 ? x.beyond_repeats : 0;
    if (k == 0) continue;
    const bool assay = r.spec->assays.count(x.beyond_observable) > 0 && !sigma.count(x.beyond_observable);
    const double s = x.beyond_sigma > 0                 ? x.beyond_sigma
                     : sigma.count(x.beyond_observable) ? sigma.at(x.beyond_observable)
                     : assay                            ? r.spec->assays.at(x.beyond_observable)
                                                        : std::nan("");
    if (!std::isfinite(s)) continue;
    add({"reach", x.effect, x.beyond_condition, x.beyond_observable, s, k, x.beyond_z, false, assay,
         x.strongest});
  }
  return out;
}

std::string asked_markdown(const Report& r) {
  const std::vector<AskedMeasurement> asked = asked_measurements(r);
  if (asked.empty()) return "";
  std::string md =
      "## Measurements to make next\n\n"
      "What the paragraph above asks a laboratory to measure, in its order; a measurement made k times is "
      "entered in the table as the mean of the k (σ/√k), its `n` the repeats behind it. The noise is the one "
      "the report assumed there: the table's, and more where the runs spread more. Sections below give the "
      "alternatives.\n\n"
      "| for | measure | at | times | noise of one (σ) | what one shows (σ) |\n|---|---|---|---|---|---|\n";
  for (const AskedMeasurement& m : asked) {
    const std::string why =
        m.reason == "tie" ? fmt::format("separate `{}`", m.effect)
        : m.reason == "bound"
            ? fmt::format("bound `{}`'s {}", m.effect, effect_spec(m.effect).strength)
            : fmt::format("see `{}` (at {} = {:.3g})", m.effect, effect_spec(m.effect).strength, m.strength);
    md += fmt::format("| {} | `{}`{} | {}{} | {} | {:.3g} | {:.1f} |\n", why, m.observable,
                      m.assay ? " (an assay)" : "", m.condition,
                      m.in_table ? " (a condition of the table)" : "", m.repeats, m.sigma, m.separation);
  }
  return md + "\n";
}

nlohmann::json asked_json(const Report& r) {
  nlohmann::json a = nlohmann::json::array();
  for (const AskedMeasurement& m : asked_measurements(r))
    a.push_back({{"reason", m.reason},
                 {"effect", m.effect},
                 {"condition", m.condition},
                 {"observable", m.observable},
                 {"sigma", m.sigma},
                 {"repeats", m.repeats},
                 {"separation", m.separation},
                 {"in_table", m.in_table},
                 {"assay", m.assay},
                 {"strength", m.reason == "reach" ? nlohmann::json(m.strength) : nlohmann::json()}});
  return a;
}

}  // namespace wetdem::diagnose
