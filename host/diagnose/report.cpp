#include "diagnose/report.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "app/output/summary.h"
#include "diagnose/effects.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

namespace {

double chi2_of(const std::vector<CellGap>& g) {
  double s = 0;
  for (const CellGap& x : g) s += x.z * x.z;
  return s;
}

size_t significant(const std::vector<CellGap>& g) {
  size_t n = 0;
  for (const CellGap& x : g) n += x.significant;
  return n;
}

bool has_refit(const Report& r) {
  return !r.spec->refit.empty() && r.settings.size() > 1;
}

// What the null model with refit leaves (only with refit and a fitted null): a sentence for the paragraph.
std::string null_refit_sentence(const Report& r) {
  if (!has_refit(r) || r.null_refit_gaps.empty()) return "";
  return fmt::format(
      " Without any added effect, the model with {} scores a held-out χ² of {:.1f} and leaves {} of {} cells "
      "significant.",
      refit_phrase(r, r.verdict.null_refit), r.verdict.null_loco, significant(r.null_refit_gaps),
      r.cells.size());
}

}  // namespace

std::string refit_phrase(const Report& r, size_t j) {
  if (!has_refit(r)) return "";
  std::string keys;
  for (const RefitKey& k : r.spec->refit) keys += (keys.empty() ? "" : ", ") + k.key;
  if (j == 0) return keys + " kept as calibrated";
  std::string to;
  for (const std::string& o : r.settings.at(j).overrides) {
    const size_t eq = o.find('=');
    std::string v = o.substr(eq + 1);
    if (v.size() >= 2 && v.front() == '"') v = v.substr(1, v.size() - 2);
    to += (to.empty() ? "" : " and ") + o.substr(0, eq) + " re-fitted to " + v;
  }
  return to;
}

std::string verdict_paragraph(const Report& r) {
  const size_t n = r.cells.size(), ns = significant(r.gaps);
  if (r.verdict.kind == "no_gap")
    return fmt::format(
        "**No gap.** The calibrated model agrees with the observations within their uncertainties: none of "
        "the "
        "{} measured cells differs significantly (false-discovery rate {:.0f} %). No effect needs to be "
        "added; "
        "a new measurement (another liquid content or speed) is what would test the model further.",
        n, 100 * r.spec->rule.q);
  std::string where;
  for (const std::string& w : r.where) where += (where.empty() ? "" : "; ") + w;
  if (r.verdict.kind == "effect") {
    const Candidate& c = r.verdict.ranking.front();
    const EffectSpec& e = effect_spec(c.effect);
    const double before = chi2_of(r.gaps), after = chi2_of(r.gaps_after);
    return fmt::format(
        "**Gap explained by `{}`.** The model departs from the observations at {} of {} cells ({}). Of the "
        "candidates, `{}` ({}) explains it best: with {} = {:.3g} (interval {:.3g}-{:.3g}){} it predicts the "
        "conditions it was not fitted to {:.0f} % better than the model without it (held-out shrink), and "
        "fresh runs at that strength bring χ² from {:.1f} to {:.1f} over the {} cells, {} still "
        "significant.{} "
        "Add `{}` to the model (or measure it directly) before trusting predictions at new conditions.",
        c.effect, ns, n, where, c.effect, e.fingerprint, e.strength, r.chosen_strength, c.fit.lo, c.fit.hi,
        has_refit(r) ? " and " + refit_phrase(r, c.refit) : "", 100 * r.verdict.held_out_shrink, before,
        after, n, significant(r.gaps_after), null_refit_sentence(r), c.effect);
  }
  // Unexplained: either the best candidate helps but not by the rule's margin (a lead worth more data), or
  // none helps (the cause lies outside the candidates).
  const double ratio = r.spec->rule.ratio;
  // With refit, the model without any effect may close the gap at a re-fitted setting (decide: "refit").
  if (r.verdict.kind == "refit") {
    const std::string best =
        r.verdict.ranking.empty()
            ? ""
            : fmt::format(
                  " The best candidate, `{}`, scores {:.1f} held out, but no cell is left for it to explain.",
                  r.verdict.ranking.front().effect, r.verdict.ranking.front().loco);
    return fmt::format(
        "**Gap closed by re-fitting, no effect needed.** The model as calibrated departs from the "
        "observations at "
        "{} of {} cells ({}).{}{} Re-calibrate the model with these values rather than add an effect.",
        ns, n, where, null_refit_sentence(r), best);
  }
  if (!r.verdict.ranking.empty() && r.verdict.held_out_shrink >= 0.5 * (1.0 - ratio)) {
    const Candidate& c = r.verdict.ranking.front();
    return fmt::format(
        "**Gap not explained (a lead: `{}`).** The model departs from the observations at {} of {} cells "
        "({}). "
        "The best candidate, `{}` ({}), improves the held-out predictions by {:.0f} % (at {} = {:.3g}), "
        "short "
        "of the {:.0f} % the rule asks: the data point to it but do not single it out. To decide, measure "
        "more "
        "conditions where its fingerprint is strongest, or repeat the measurements to shrink their error "
        "bars.{}",
        c.effect, ns, n, where, c.effect, effect_spec(c.effect).fingerprint, 100 * r.verdict.held_out_shrink,
        effect_spec(c.effect).strength, c.fit.strength, 100 * (1.0 - ratio), null_refit_sentence(r));
  }
  std::string best = r.verdict.ranking.empty()
                         ? "none was fitted"
                         : fmt::format("the best, `{}`, improves the held-out predictions by only {:.0f} %",
                                       r.verdict.ranking.front().effect, 100 * r.verdict.held_out_shrink);
  return fmt::format(
      "**Gap not explained.** The model departs from the observations at {} of {} cells ({}), but none of "
      "the candidate effects explains it by the rule's margin ({}). The cause is likely outside the "
      "candidates "
      "(another mechanism, a measurement bias, or a model parameter to re-calibrate).{}",
      ns, n, where, best, null_refit_sentence(r));
}

nlohmann::json write_report(const std::string& dir, const Report& r, bool figures) {
  fs::create_directories(dir);
  using nlohmann::json;
  json j;
  j["name"] = r.spec->name;
  j["case"] = r.spec->case_path;
  j["observations"] = r.spec->observations;
  j["verdict"] = r.verdict.kind;
  j["effect"] = r.verdict.kind == "effect" ? json(r.verdict.effect) : json(nullptr);
  j["rule"] = {{"fdr", r.spec->rule.q}, {"ratio", r.spec->rule.ratio}, {"min_drop", r.spec->rule.min_drop}};
  j["where_summary"] = r.where;
  for (size_t k = 0; k < r.cells.size(); ++k) {
    json c = {{"condition", r.cell_condition[k]},
              {"observable", r.cells[k].observable},
              {"y", r.cells[k].y},
              {"sigma", r.cells[k].sigma},
              {"model", r.baseline[k].mean},
              {"model_se", r.baseline[k].se},
              {"gap", r.gaps[k].gap},
              {"z", r.gaps[k].z},
              {"p", r.gaps[k].p},
              {"significant", bool(r.gaps[k].significant)}};
    for (const auto& [key, v] : r.cells[k].condition) c["condition_si"][key] = v;
    if (!r.null_refit_gaps.empty())
      c["null_refit"] = {{"model", r.null_refit_pred[k].mean},
                         {"model_se", r.null_refit_pred[k].se},
                         {"z", r.null_refit_gaps[k].z},
                         {"significant", bool(r.null_refit_gaps[k].significant)}};
    if (!r.after.empty())
      c["after"] = {{"model", r.after[k].mean},
                    {"model_se", r.after[k].se},
                    {"z", r.gaps_after[k].z},
                    {"significant", bool(r.gaps_after[k].significant)}};
    j["cells"].push_back(c);
  }
  for (const auto& [s, e] : r.screened) j["screen"].push_back({{"effect", e}, {"score", s}});
  const bool refit = has_refit(r);
  auto setting_json = [&](size_t s) {
    return json{{"setting", s}, {"label", r.settings.at(s).label}, {"values", r.settings.at(s).si}};
  };
  if (refit) {
    json keys = json::array();
    for (const RefitKey& k : r.spec->refit) {
      json vals = json::array();
      for (const RefitValue& v : k.values) vals.push_back({{"written", v.written}, {"si", v.si}});
      keys.push_back({{"key", k.key}, {"calibrated_si", k.calibrated_si}, {"values", vals}});
    }
    json settings = json::array();
    for (size_t s = 0; s < r.settings.size(); ++s) settings.push_back(setting_json(s));
    j["refit"] = {{"keys", keys}, {"settings", settings}};
  }
  for (const Candidate& c : r.verdict.ranking) {
    j["ranking"].push_back({{"effect", c.effect},
                            {"screen", c.screen},
                            {"loco_chi2", c.loco},
                            {"weight", r.verdict.null_loco > 0 ? 1.0 - c.loco / r.verdict.null_loco : 0.0},
                            {"strength", c.fit.strength},
                            {"strength_interval", {c.fit.lo, c.fit.hi}},
                            {"strength_at_edge", c.fit.at_edge},
                            {"strength_meaning", effect_spec(c.effect).strength}});
    if (refit) j["ranking"].back()["refit"] = setting_json(c.refit);
  }
  if (refit && !r.null_refit_gaps.empty()) {
    j["null_refit"] = setting_json(r.verdict.null_refit);
    j["null_refit"]["chi2"] = chi2_of(r.null_refit_gaps);
    j["null_refit"]["significant_cells"] = significant(r.null_refit_gaps);
  }
  for (size_t i = 0; i < r.responses.size(); ++i) {
    const Response& resp = r.responses[i];
    json x = {{"effect", resp.effect}, {"strengths", resp.strengths}};
    if (refit)
      for (const Candidate& c : r.verdict.ranking)
        if (c.effect == resp.effect) x["refit"] = setting_json(c.refit);
    for (const auto& p : resp.pred) {
      json row;
      for (const Prediction& q : p) row.push_back({q.mean, q.se});
      x["pred"].push_back(row);
    }
    j["responses"].push_back(x);
  }
  j["null_loco_chi2"] = r.verdict.null_loco;
  j["held_out_shrink"] = r.verdict.ranking.empty() ? json(nullptr) : json(r.verdict.held_out_shrink);
  j["chi2_before"] = chi2_of(r.gaps);
  j["dof"] = r.cells.size();
  if (!r.after.empty()) {
    j["chosen_strength"] = r.chosen_strength;
    if (refit) j["chosen_refit"] = setting_json(r.verdict.ranking.front().refit);
    j["chi2_after"] = chi2_of(r.gaps_after);
    j["shrink"] = 1.0 - chi2_of(r.gaps_after) / std::max(1e-300, chi2_of(r.gaps));
    json rem = json::array();
    for (size_t k = 0; k < r.cells.size(); ++k)
      if (r.gaps_after[k].significant) rem.push_back(r.cell_condition[k] + " / " + r.cells[k].observable);
    j["remaining_gap"] = rem;
  }
  j["runs"] = r.runs;
  j["runs_computed"] = r.computed;
  j["store"] = r.store;
  j["device"] = r.device;
  j["wall_s"] = r.wall_s;
  j["paragraph"] = verdict_paragraph(r);
  app::write_file_atomic((fs::path(dir) / "diagnosis.json").string(), j.dump(2) + "\n");

  std::string figs;
  if (figures) {
    const char* env = std::getenv("WETDEM_PLOT_DIAGNOSIS");
    const std::string script = env ? env : std::string(WETDEM_SOURCE_ROOT) + "/scripts/plot_diagnosis.py";
    fs::create_directories(fs::path(dir) / "figures");
    const std::string cmd = fmt::format("/usr/bin/python3 '{}' '{}' > '{}' 2>&1", script, dir,
                                        (fs::path(dir) / "figures" / "plot.log").string());
    if (fs::exists(script) && std::system(cmd.c_str()) == 0)
      for (const char* f : {"gap_map", "observables", "ranking"})
        if (fs::exists(fs::path(dir) / "figures" / (std::string(f) + ".png")))
          figs += fmt::format("![{}](figures/{}.png)\n\n", f, f);
  }
  std::string md = "# Sim-to-real diagnosis: " + r.spec->name + "\n\n" + verdict_paragraph(r) + "\n\n";
  md += "## Where\n\n";
  for (const std::string& w : r.where) md += "- " + w + "\n";
  md += "\n| condition | observable | observed | model (baseline) | z | significant |";
  md += r.after.empty() ? "\n|---|---|---|---|---|---|\n"
                        : " with effect | z after |\n|---|---|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < r.cells.size(); ++k) {
    md += fmt::format("| {} | {} | {:.4g} ± {:.2g} | {:.4g} ± {:.2g} | {:+.2f} | {} |", r.cell_condition[k],
                      r.cells[k].observable, r.cells[k].y, r.cells[k].sigma, r.baseline[k].mean,
                      r.baseline[k].se, r.gaps[k].z, r.gaps[k].significant ? "yes" : "no");
    if (!r.after.empty())
      md += fmt::format(" {:.4g} ± {:.2g} | {:+.2f} |", r.after[k].mean, r.after[k].se, r.gaps_after[k].z);
    md += "\n";
  }
  md += "\n## Candidates\n\n| effect | screen score | held-out χ² (LOCO) | fitted strength | interval |";
  md += refit ? " re-fitted (all cells) |\n|---|---|---|---|---|---|\n" : "\n|---|---|---|---|---|\n";
  if (refit)
    md += fmt::format("| (none: the model without an added effect) | | {:.2f} | | | {} |\n",
                      r.verdict.null_loco, r.settings.at(r.verdict.null_refit).label);
  else
    md += fmt::format("| (none: the model as calibrated) | | {:.2f} | | |\n", r.verdict.null_loco);
  for (const Candidate& c : r.verdict.ranking) {
    md += fmt::format("| {} | {:.2f} | {:.2f} | {:.3g} {} | {:.3g}-{:.3g}{} |", c.effect, c.screen, c.loco,
                      c.fit.strength, effect_spec(c.effect).strength, c.fit.lo, c.fit.hi,
                      c.fit.at_edge ? " (at the probed range's edge)" : "");
    md += refit ? fmt::format(" {} |\n", r.settings.at(c.refit).label) : "\n";
  }
  if (refit) {
    std::string keys;
    for (const RefitKey& k : r.spec->refit) keys += (keys.empty() ? "" : ", ") + k.key;
    md += fmt::format(
        "\nRe-fitted with every candidate and with the null ({} settings of {}); the held-out χ² re-fits "
        "them in every fold.\n",
        r.settings.size(), keys);
  }
  md += "\nScreen scores of every candidate: ";
  for (const auto& [s, e] : r.screened) md += fmt::format("{} {:.2f}; ", e, s);
  md += fmt::format(
      "\n\nRule: `effect` when the best held-out χ² ≤ {} × the null's and lower by ≥ {}; cells "
      "significant by Benjamini-Hochberg at {}.\n\n",
      r.spec->rule.ratio, r.spec->rule.min_drop, r.spec->rule.q);
  md += figs;
  md += fmt::format("Runs: {} in the store ({} computed now), device {}, wall time {:.0f} s.\n", r.runs,
                    r.computed, r.device.empty() ? "-" : r.device, r.wall_s);
  app::write_file_atomic((fs::path(dir) / "report.md").string(), md);
  return j;
}

}  // namespace wetdem::diagnose
