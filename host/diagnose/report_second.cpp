// The report's section and diagnosis.json's "second": a second effect fitted on top of the first when that
// one explained the gap only in part (second_effect.h), stepwise and jointly, with its fresh runs and the
// cells it still leaves.
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <string>

#include "app/output/summary.h"
#include "diagnose/effects.h"
#include "diagnose/report.h"

namespace wetdem::diagnose {

nlohmann::json second_json(const Report& r) {
  using nlohmann::json;
  const SecondRound& s = r.second;
  if (s.outcome.empty()) return nullptr;
  json j = {{"outcome", s.outcome},
            {"first",
             {{"effect", s.base_effect},
              {"strength", s.base_strength},
              {"shape", app::number_or_null(s.base_shape)}}},
            {"first_chi2", chi2_of(s.base_gaps)},
            {"first_significant_cells", significant(s.base_gaps)},
            {"null_loco_chi2", s.verdict.null_loco},
            {"screen", json::array()},
            {"ranking", json::array()}};
  for (const Screened& x : s.screened) j["screen"].push_back({{"effect", x.effect}, {"score", x.score}});
  // The joint re-fit of the pair (pair_fit.h); `named`: the pair's fresh runs at the joint optimum (the
  // first at first_in_pair); `rescued`: the second failed the rule stepwise and was taken on through it.
  j["joint"] = nullptr;
  if (s.joint_first > 0)
    j["joint"] = {{"second", s.joint_effect},
                  {"first_strength", s.joint_first},
                  {"second_strength", s.joint_second},
                  {"chi2", s.joint_chi2},
                  {"stepwise_chi2", s.stepwise_chi2},
                  {"loco_chi2", s.joint_loco},
                  {"named", s.joint},
                  {"rescued", s.joint_rescued},
                  {"first_in_pair", s.pair_first},
                  {"first_shape", app::number_or_null(s.joint_first_shape)},
                  {"first_shape_in_pair", app::number_or_null(s.pair_first_shape)}};
  for (const Candidate& c : s.verdict.ranking) {
    const CandidateRuns* cr = r.second_runs_of(c.effect);
    j["ranking"].push_back({{"effect", c.effect},
                            {"screen", c.screen},
                            {"loco_chi2", c.loco},
                            {"strength", c.fit.strength},
                            {"strength_interval", {c.fit.lo, c.fit.hi}},
                            {"strength_interval_open", {c.fit.open_lo, c.fit.open_hi}},
                            {"strength_interval_2se", {c.fit.lo2, c.fit.hi2}},
                            {"strength_interval_2se_open", {c.fit.open_lo2, c.fit.open_hi2}},
                            {"strength_meaning", effect_spec(c.effect).strength},
                            {"probed", cr ? cr->members.front().strengths : std::vector<double>{}},
                            {"notes", cr ? cr->notes : std::vector<std::string>{}},
                            {"text", strength_text(c, cr)}});
  }
  // The confirmation (confirm_second): the pair's fresh runs against the first effect alone on the same
  // seeds.
  if (!s.fresh.gaps_after.empty() && r.chosen()) {
    j["fresh_candidate"] = s.fresh.effect;
    j["pair_fresh_chi2"] = chi2_of(s.fresh.gaps_after);
    j["first_fresh_chi2"] = chi2_of(r.chosen()->gaps_after);
  }
  const Candidate* b = r.second_named();
  j["effect"] = b ? json(b->effect) : json(nullptr);
  if (b) {
    // Held out, against the first effect alone, and against the model as calibrated (the first effect's
    // strength fitted on every condition, so this one is a little optimistic).
    // Taken on through the joint fit: the pair's own held-out χ² (both strengths re-fitted in every fold).
    const double held = s.joint ? s.joint_loco : b->loco;
    j["held_out_shrink"] = s.verdict.null_loco > 0 ? 1.0 - held / s.verdict.null_loco : 0.0;
    j["held_out_shrink_total"] = r.verdict.null_loco > 0 ? 1.0 - held / r.verdict.null_loco : 0.0;
  }
  if (const FreshCheck* f = r.second_fresh()) {
    j["strength"] = f->strength;
    j["shape"] = app::number_or_null(f->shape);
    j["chi2_after"] = chi2_of(f->gaps_after);
    j["shrink"] = 1.0 - chi2_of(f->gaps_after) / std::max(1e-300, chi2_of(r.gaps));
    j["significant_cells"] = significant(f->gaps_after);
    json rem = json::array();
    for (size_t k = 0; k < r.cells.size(); ++k)
      if (f->gaps_after[k].significant) rem.push_back(r.cell_condition[k] + " / " + r.cells[k].observable);
    j["remaining_gap"] = rem;
  }
  return j;
}

std::string second_markdown(const Report& r) {
  const SecondRound& s = r.second;
  if (s.outcome.empty()) return "";
  std::string md = fmt::format(
      "## A second effect on top of `{}`\n\n`{}` at {:.3g} explains the gap only in part, so the other "
      "candidates were screened against what it leaves ({} significant cells, χ² {:.1f} with seeds 1..R) and "
      "the best fitted on top of it, with the model with `{}` as the null (held-out χ² {:.1f}).\n\n",
      s.base_effect, s.base_effect, s.base_strength, significant(s.base_gaps), chi2_of(s.base_gaps),
      s.base_effect, s.verdict.null_loco);
  if (!s.verdict.ranking.empty()) {
    md +=
        "| second effect | screen score | held-out χ² (LOCO) | fitted strength (interval) "
        "|\n|---|---|---|---|\n";
    for (const Candidate& c : s.verdict.ranking)
      md += fmt::format("| {} | {:.2f} | {:.2f} | {} {} |\n", c.effect, c.screen, c.loco,
                        effect_spec(c.effect).strength, strength_text(c, r.second_runs_of(c.effect)));
    md += "\n";
  }
  const std::map<std::string, std::string> says = {
      {"closes", "the pair leaves no cell significant in its fresh-seed runs: both effects are named"},
      {"part",
       "the second effect passes the rule against the first alone, but cells stay significant with "
       "both"},
      {"noise",
       "with the first effect and seeds 1..R no cell is significant: nothing is left for a second "
       "effect (only the fresh seeds left cells)"},
      {"none", "no second candidate explains what the first leaves by the rule's margin"},
      {"unconfirmed",
       "the best second candidate passes the rule against the first alone on seeds 1..R, but its fresh-seed "
       "runs with the first are not better than the first alone on the same seeds by the model's seed luck, "
       "so it is not named"}};
  md += "Outcome: **" + s.outcome + "**: " + says.at(s.outcome) + ".";
  // The pair's fresh runs, named or not, beside the first effect alone on the same seeds (confirm_second).
  if (!s.fresh.gaps_after.empty() && r.chosen())
    md += fmt::format(
        " Fresh runs of `{}`{} + `{}` at {:.3g}: χ² {:.1f} over the {} cells, {} significant; "
        "`{}` alone on the same seeds: {:.1f} (seed luck {:.1f}).",
        s.base_effect, s.joint ? fmt::format(" at {:.3g}", s.pair_first) : "", s.fresh.effect,
        s.fresh.strength, chi2_of(s.fresh.gaps_after), r.cells.size(), significant(s.fresh.gaps_after),
        s.base_effect, chi2_of(r.chosen()->gaps_after), r.verdict.seed_luck);
  // The joint re-fit (pair_fit.h): what the pair does when the first may move too.
  if (s.joint_first > 0)
    md += fmt::format(
        "\n\nFitted jointly (the additive emulator of `{}` alone and `{}` on top of it): `{}` at {:.3g}{} "
        "and `{}` at {:.3g}, χ² {:.1f} against {:.1f} with `{}` held at its own fit; held out with both "
        "strengths re-fitted in every fold, χ² {:.1f} against {:.1f} for `{}` alone.{}",
        s.base_effect, s.joint_effect, s.base_effect, s.joint_first,
        std::isnan(s.joint_first_shape)
            ? ""
            : fmt::format(" at {} = {:.3g}", effect_spec(s.base_effect).shape, s.joint_first_shape),
        s.joint_effect, s.joint_second, s.joint_chi2, s.stepwise_chi2, s.base_effect, s.joint_loco,
        s.verdict.null_loco, s.base_effect,
        !s.joint ? ""
        : s.joint_rescued
            ? fmt::format(
                  " `{}` failed the rule held at its own fit and passes it jointly: the pair's fresh runs "
                  "are at the joint optimum.",
                  s.joint_effect)
            : fmt::format(" `{}` passes the rule held at its own fit too, but jointly the pair predicts the "
                          "left-out conditions better: its fresh runs are at the joint optimum.",
                          s.joint_effect));
  return md + "\n\n";
}

}  // namespace wetdem::diagnose
