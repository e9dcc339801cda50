// The report's section and diagnosis.json's "bound_experiment": the measurement that would close the chosen
// effect's open interval (next_bound.h).
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "app/output/summary.h"
#include "diagnose/effects.h"
#include "diagnose/next_bound.h"
#include "diagnose/next_experiment.h"
#include "diagnose/report.h"

namespace wetdem::diagnose {

namespace {

std::string repeats_words(size_t k) {
  if (k == 0) return "none will do";
  return k == 1 ? std::string("1 (one measurement)") : fmt::format("{}", k);
}

std::string side_words(const BoundExperiment& b) {
  if (b.both) return "the strength undetermined: the table cannot place it anywhere in the probed range";
  return b.above ? "the interval open above: the table cannot tell its lower end from any stronger strength "
                   "probed"
                 : "the interval open below: the table cannot tell its upper end from any weaker strength";
}

}  // namespace

std::string bound_markdown(const Report& r) {
  const BoundExperiment& b = r.bound;
  if (b.effect.empty()) return "";
  const std::string key = effect_spec(b.effect).strength;
  std::string md =
      fmt::format("## Bounding `{}`: {} = {:.3g} or {:.3g}?\n\n", b.effect, key, b.closed, b.open);
  md += fmt::format(
      "The fit leaves {} ({:.3g}–{:.3g}{}). Both ends were compared at the table's conditions through the "
      "fit's emulator and run at conditions beyond it (on one seed, and on every seed where they differ by "
      "2 σ): where they differ most relative to the noise, one measurement would bound the strength.\n\n",
      side_words(b), std::min(b.closed, b.open), std::max(b.closed, b.open),
      std::isnan(b.shape) ? "" : fmt::format(", at {} = {:.3g}", effect_spec(b.effect).shape, b.shape));
  if (b.proposals.empty()) return md + (b.note.empty() ? "" : "No proposal: " + b.note + ".\n\n");
  md += fmt::format(
      "| condition | observable | {} = {:.3g} | {} = {:.3g} | noise σ | separation (σ) | repeats for {:g} σ "
      "| in the table | seeds |\n|---|---|---|---|---|---|---|---|---|\n",
      key, b.closed, key, b.open, kDecisive);
  for (size_t i = 0; i < b.proposals.size() && i < 8; ++i) {
    const Proposal& q = b.proposals[i];
    md += fmt::format("| {} | {}{} | {:.4g} ± {:.2g} | {:.4g} ± {:.2g} | {:.3g} | {:.2f} | {} | {} | {} |\n",
                      q.condition, q.observable, q.assay ? " (assay, not in the table)" : "", q.model_a,
                      q.se_a, q.model_b, q.se_b, q.sigma, q.separation, repeats_words(q.repeats),
                      q.in_table ? "yes (emulated)" : "no", q.seeds);
  }
  md += "\n*Separation*: at the fitted shape and refit setting, without re-fitting them to the new value; ";
  md += "the table's own conditions through the fit's emulator (the seeds of its probes). ";
  md += fmt::format(
      "*Repeats*: how often the measurement must be made (their mean entered, σ/√k) for the ends to lie {:g} "
      "σ apart; repeats shrink the measurement's noise, not the runs' own error, so where that error alone "
      "holds them closer none will do (more than {}: none).\n\n",
      kDecisive, kMaxRepeats);
  return md;
}

nlohmann::json bound_json(const Report& r) {
  using nlohmann::json;
  const BoundExperiment& b = r.bound;
  json props = json::array();
  for (const Proposal& q : b.proposals)
    props.push_back({{"condition", q.condition},
                     {"observable", q.observable},
                     {"closed_end", q.model_a},
                     {"open_end", q.model_b},
                     {"se_closed", q.se_a},
                     {"se_open", q.se_b},
                     {"sigma", q.sigma},
                     {"separation", q.separation},
                     {"in_table", q.in_table},
                     {"assay", q.assay},
                     {"seeds", q.seeds},
                     {"repeats", q.repeats}});
  // The measurement the report asks to repeat (no single one bounds it): paragraph.cpp bound_sentence.
  const Proposal* k = repeated_bound(b);
  return {{"effect", b.effect},
          {"closed", b.closed},
          {"open", b.open},
          {"open_above", b.above},
          {"open_both", b.both},
          {"shape", app::number_or_null(b.shape)},
          {"proposals", props},
          {"note", b.note},
          {"repeated", k ? json{{"condition", k->condition},
                                {"observable", k->observable},
                                {"sigma", k->sigma},
                                {"repeats", k->repeats}}
                         : json()}};
}

}  // namespace wetdem::diagnose
