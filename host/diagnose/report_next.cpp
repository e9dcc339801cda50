// The report's section and diagnosis.json's "next_experiment": the measurement that would separate two tied
// effects (next_experiment.h), with the assays the file names ([assays]).
#include <fmt/format.h>

#include <cmath>
#include <set>
#include <string>

#include "app/output/summary.h"
#include "diagnose/report.h"

namespace wetdem::diagnose {

namespace {

std::string refit_text(double x) {
  return std::isfinite(x) ? fmt::format("{:.2f}", x) : "";
}

}  // namespace

std::string next_markdown(const Report& r) {
  if (r.next.proposals.empty()) return "";
  std::string md = fmt::format("## Next experiment: `{}` or `{}`?\n\n", r.next.effect_a, r.next.effect_b);
  md += fmt::format(
      "| condition | observable | `{}` | `{}` | noise σ | separation (σ) | after re-fit (σ) | in the table | "
      "seeds |\n",
      r.next.effect_a, r.next.effect_b);
  md += "|---|---|---|---|---|---|---|---|---|\n";
  // The best eight, and each assay's best where it is not among them: the file asked about it, so the
  // report says how it did, weak or not (diagnosis.json lists every proposal).
  std::set<std::string> shown;
  for (size_t i = 0; i < r.next.proposals.size(); ++i) {
    const Proposal& q = r.next.proposals[i];
    if (i >= 8 && (!q.assay || shown.count(q.observable))) continue;
    shown.insert(q.observable);
    md += fmt::format("| {} | {}{} | {:.4g} ± {:.2g} | {:.4g} ± {:.2g} | {:.3g} | {:.2f} | {} | {} | {} |\n",
                      q.condition, q.observable, q.assay ? " (assay, not in the table)" : "", q.model_a,
                      q.se_a, q.model_b, q.se_b, q.sigma, q.separation, refit_text(q.refit_separation),
                      q.in_table ? "yes" : "no", q.seeds);
  }
  md += "\n";
  md += "*After re-fit*: the separation once each model may re-fit its strength to the other's value ";
  md += "there (the rise of its least χ² over the table with that measurement added, in σ): what the ";
  md += "measurement would still tell apart. Blank where the models were not run at their probed strengths.";
  if (r.next.needed > 0)
    md += fmt::format(
        " To decide the tie on fresh runs the verdict needs a rise of about {:.1f} in χ² ({:.1f} σ after "
        "re-fit): its tie rule, max(tie_delta × max(1, χ²/n), the model's own seed luck).",
        r.next.needed * r.next.needed, r.next.needed);
  md += "\n\n";
  if (!r.next.pairs.empty()) {
    md += "Two measurements made together (the best pairs by their separation after re-fit):\n\n";
    md += "| first | second | separation (σ) | after re-fit (σ) |\n|---|---|---|---|\n";
    for (const ProposalPair& q : r.next.pairs)
      md += fmt::format("| `{}` at {} | `{}` at {} | {:.2f} | {:.2f} |\n", q.first.observable,
                        q.first.condition, q.second.observable, q.second.condition, q.separation,
                        q.refit_separation);
    md += "\n";
  }
  for (const AssaySeries& a : r.next.series)
    md += fmt::format(
        "The assay `{}` on every sample of the table ({} conditions) separates them by {:.1f} σ together "
        "(each condition's separation added in quadrature){}.\n\n",
        a.observable, a.conditions, a.separation,
        std::isfinite(a.refit_separation)
            ? fmt::format(", {:.1f} σ once each model re-fits to all of them", a.refit_separation)
            : "");
  return md;
}

nlohmann::json next_json(const Report& r) {
  using nlohmann::json;
  json props = json::array();
  for (const Proposal& q : r.next.proposals)
    props.push_back({{"condition", q.condition},
                     {"observable", q.observable},
                     {"model_a", q.model_a},
                     {"model_b", q.model_b},
                     {"se_a", q.se_a},
                     {"se_b", q.se_b},
                     {"sigma", q.sigma},
                     {"separation", q.separation},
                     {"refit_separation", app::number_or_null(q.refit_separation)},
                     {"in_table", q.in_table},
                     {"assay", q.assay},
                     {"seeds", q.seeds}});
  json series = json::array();
  for (const AssaySeries& a : r.next.series)
    series.push_back({{"observable", a.observable},
                      {"conditions", a.conditions},
                      {"separation", a.separation},
                      {"refit_separation", app::number_or_null(a.refit_separation)}});
  json pairs = json::array();
  for (const ProposalPair& q : r.next.pairs)
    pairs.push_back({{"first", {{"condition", q.first.condition}, {"observable", q.first.observable}}},
                     {"second", {{"condition", q.second.condition}, {"observable", q.second.observable}}},
                     {"separation", q.separation},
                     {"refit_separation", q.refit_separation}});
  return {{"effects", {r.next.effect_a, r.next.effect_b}},
          {"proposals", props},
          {"pairs", pairs},
          {"needed_separation", r.next.needed},
          {"repeats", r.next.repeats},
          {"assay_series", series},
          {"note", r.next.note}};
}

}  // namespace wetdem::diagnose
