// The report's section and diagnosis.json's "reach": what the table can see of each candidate (power.h).
#include <fmt/format.h>

#include <map>
#include <string>

#include "diagnose/report.h"

namespace wetdem::diagnose {

namespace {

// "×2.0 on surface_agglomerate_size, ×1.3 on aor_deg_std": the factors that scale a run's own error up.
std::string inflation_text(const std::map<std::string, double>& f) {
  std::string out;
  for (const auto& [obs, x] : f)
    if (x > 1.05) out += fmt::format("{}×{:.1f} on {}", out.empty() ? "" : ", ", x, obs);
  return out.empty() ? "none needed" : out;
}

// The weaker strengths run where the strongest showed beyond the table, and the bracket they give
// (weaker_bracket: shows_from, the weakest that reached 3 σ; short_at, the strongest under it that did not).
nlohmann::json weaker_json(const Reach& x) {
  nlohmann::json runs = nlohmann::json::array();
  for (const WeakerRun& w : x.beyond_weaker) runs.push_back({{"strength", w.strength}, {"max_abs_z", w.z}});
  const WeakerBracket b = weaker_bracket(x.strongest, x.beyond_z, x.beyond_weaker);
  return {{"runs", runs}, {"shows_from", b.from}, {"short_at", b.below}};
}

}  // namespace

std::string reach_stop_words(const std::string& stop) {
  if (stop == "physical limit") return "the end of its physical range";
  if (stop == "max_cost") return "the strongest max_cost lets run";
  if (stop == "failed") return "stronger runs failed";
  if (stop == "cannot run") return "stronger runs cannot be set up (see the notes)";
  if (stop == "reach_steps") return "reach_steps taken";
  return stop;
}

std::string reach_markdown(const Report& r) {
  if (r.reach.empty()) return "";
  std::string md = fmt::format(
      "## What this table can see\n\nEach candidate's probe runs against the baseline, in units of each "
      "cell's noise (z = (probe − baseline) / √(σ² + se²)): the largest |z| in any cell, and the χ² over the "
      "cells in excess of what the probe runs' own noise gives. A candidate is visible when some cell "
      "reaches {:g} σ or the excess reaches {:.1f} (the 1 % excess of a χ² over {} cells); one that is not, "
      "even at the strongest strength probed, is one this table cannot show, and the verdict says nothing "
      "about it. One that does not show at the file's strongest probe is first stepped past it (one run per "
      "condition a step, the probes' ratio, up to {} steps, the end of its physical range or the strongest "
      "max_cost lets run). Such a candidate was also run beside the baseline at conditions beyond the table "
      "({} each, and the baseline's other seeds too where they differ by {:.2f} σ, {:g} σ √(P/R); noise the "
      "table's median σ of the observable, each run's own error scaled to the seed spread of the baseline's "
      "replicates: {}): where it would show; where one measurement would not, but the runs differ by {:g} σ "
      "of their own error over all the baseline's seeds, how often a laboratory would repeat it (their mean, "
      "σ/√k) to see it. The fresh runs of a fitted candidate (R seeds at its fitted strength) are also set "
      "against the model without it on the same seeds, z = (fresh − control) / √(σ² + se_f² + se_c²): a "
      "candidate they show is seen, whatever its single probe runs showed.\n\n"
      "| effect | strongest probed | largest shift (σ) | at strength | cell | χ² excess | fresh runs | "
      "visible | beyond the table |\n|---|---|---|---|---|---|---|---|---|\n",
      kVisibleZ, visible_chi2_excess(r.cells.size()), r.cells.size(), r.spec->reach_steps,
      r.spec->probe_seeds == 1 ? std::string("one run") : fmt::format("{} runs", r.spec->probe_seeds),
      reach_screen_z(size_t(r.spec->replicates), size_t(r.spec->probe_seeds)), kVisibleZ,
      inflation_text(r.within_inflation), kVisibleZ);
  for (const Reach& x : r.reach) {
    if (x.strongest <= 0) {
      md += fmt::format("| {} | (no probe could run) | | | | | | no | |\n", x.effect);
      continue;
    }
    std::string beyond;
    if (!x.beyond_condition.empty())
      beyond = fmt::format("{:.1f} σ: {} at {} (of {} tried{})", x.beyond_z, x.beyond_observable,
                           x.beyond_condition, x.beyond_tried.size(),
                           x.beyond_seeds > 1 ? fmt::format("; {} runs each there", x.beyond_seeds) : "");
    if (x.beyond_repeats > 1)
      beyond += fmt::format("; {} σ when measured {} times", kVisibleZ, x.beyond_repeats);
    for (const WeakerRun& w : x.beyond_weaker)
      beyond += fmt::format("; at {:.3g}: {:.1f} σ", w.strength, w.z);
    const std::string fresh =
        x.fresh ? fmt::format("{:.1f} σ ({} at {}), χ² excess {:.1f}, at {:.3g}", x.fresh_max_z,
                              r.cells[x.fresh_cell].observable, r.cell_condition[x.fresh_cell],
                              x.fresh_chi2_excess, x.fresh_at)
                : std::string();
    // Visible on the fresh runs alone: say so, the probes' columns show no shift.
    const char* visible = !x.visible ? "**no**" : x.by_probes ? "yes" : "yes (fresh runs)";
    // Past the file's probes (extend_reach): from where, and why it stopped where it still does not show.
    std::string strongest = fmt::format("{:.3g}", x.strongest);
    if (x.extended_from > 0) strongest += fmt::format(" (stepped past {:.3g})", x.extended_from);
    if (!x.visible && !x.extension_stop.empty())
      strongest += fmt::format("; {}", reach_stop_words(x.extension_stop));
    md += fmt::format("| {} | {} | {:.1f} | {:.3g} | {} at {} | {:.1f} | {} | {} | {} |\n", x.effect,
                      strongest, x.max_z, x.at, r.cells[x.cell].observable, r.cell_condition[x.cell],
                      x.chi2_excess, fresh, visible, beyond);
  }
  return md + "\n";
}

nlohmann::json reach_json(const Report& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const Reach& x : r.reach)
    out.push_back({{"effect", x.effect},
                   {"strongest_probed", x.strongest},
                   {"max_abs_z", x.max_z},
                   {"at_strength", x.at},
                   {"cell", x.strongest > 0 ? r.cells[x.cell].observable + " at " + r.cell_condition[x.cell]
                                            : std::string()},
                   {"chi2_excess", x.chi2_excess},
                   {"chi2_excess_at_strength", x.chi2_at},
                   {"chi2_excess_visible_from", visible_chi2_excess(r.cells.size())},
                   {"visible", x.visible},
                   {"extended_from", x.extended_from},
                   {"visible_from", x.visible_from},
                   {"extension_stop", x.extension_stop},
                   {"beyond_tried", x.beyond_tried},
                   {"beyond_condition", x.beyond_condition},
                   {"beyond_observable", x.beyond_observable},
                   {"beyond_max_abs_z", x.beyond_z},
                   {"beyond_seeds", x.beyond_seeds},
                   {"beyond_repeats", x.beyond_repeats},
                   {"beyond_sigma", x.beyond_sigma},
                   {"beyond_weaker", weaker_json(x)},
                   {"fresh", x.fresh ? nlohmann::json{{"strength", x.fresh_at},
                                                      {"max_abs_z", x.fresh_max_z},
                                                      {"cell", r.cells[x.fresh_cell].observable + " at " +
                                                                   r.cell_condition[x.fresh_cell]},
                                                      {"chi2_excess", x.fresh_chi2_excess},
                                                      {"visible", x.seen_on_fresh}}
                                     : nlohmann::json()}});
  return out;
}

}  // namespace wetdem::diagnose
