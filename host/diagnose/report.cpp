#include "diagnose/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <utility>

#include "app/output/summary.h"
#include "diagnose/effects.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

bool has_refit(const Report& r) {
  return !r.spec->refit.empty() && r.settings.size() > 1;
}

namespace {

// The whole table's χ² test (where.h); critical is null when the test is off.
nlohmann::json table_json(const TableFit& t) {
  return {{"chi2", t.chi2},
          {"cells", t.n},
          {"p", t.p},
          {"critical", app::number_or_null(t.critical)},
          {"beyond", t.beyond}};
}

// The outlook of more seeds (more_seeds.h): the ties' predicted separations against their margins.
nlohmann::json more_seeds_json(const MoreSeeds& m) {
  if (m.to == 0) return nullptr;
  nlohmann::json ties = nlohmann::json::array();
  for (const TieOutlook& t : m.ties)
    ties.push_back({{"effect", t.effect},
                    {"estimated", t.known},
                    {"separation_chi2", t.known ? nlohmann::json(t.at_more) : nlohmann::json(nullptr)},
                    {"separation_exact_chi2", t.known ? nlohmann::json(t.exact) : nlohmann::json(nullptr)},
                    {"margin_chi2", t.known ? nlohmann::json(t.margin) : nlohmann::json(nullptr)},
                    {"seeds_needed", t.known && t.seeds_needed > 0 ? nlohmann::json(t.seeds_needed)
                                                                   : nlohmann::json(nullptr)},
                    {"could_decide", t.could_decide()}});
  return {{"from_replicates", m.from},
          {"to_replicates", m.to},
          {"ties", ties},
          {"other", m.other},
          {"worth", m.worth()}};
}

}  // namespace

const CandidateRuns* Report::runs_of(const std::string& effect) const {
  for (const CandidateRuns& c : fitted)
    if (c.effect == effect) return &c;
  return nullptr;
}

const CandidateRuns* Report::second_runs_of(const std::string& effect) const {
  for (const CandidateRuns& c : second.fitted)
    if (c.effect == effect) return &c;
  return nullptr;
}

const FreshCheck* Report::fresh_of(const std::string& effect) const {
  for (const FreshCheck& f : fresh)
    if (f.effect == effect) return &f;
  return nullptr;
}

Report make_report(const Procedure& p, double wall_s, std::vector<StageCost> stages) {
  Report r;
  r.spec = &p.d;
  r.cells = p.tab.cells;
  for (size_t k = 0; k < p.tab.cells.size(); ++k)
    r.cell_condition.push_back(p.tab.conditions[p.tab.cell_condition[k]].label);
  r.baseline = p.baselines.front();
  r.gaps = p.gaps;
  r.where = describe_where(p.tab.cells, p.gaps);
  r.screened = p.screened;
  r.fitted = p.fitted;
  r.settings = p.settings;
  r.verdict = p.verdict;
  if (p.settings.size() > 1 && p.baselines.size() > r.verdict.null_refit && r.verdict.kind != "no_gap") {
    r.null_refit_pred = p.baselines[r.verdict.null_refit];
    r.null_refit_gaps = where(p.tab.cells, r.null_refit_pred, p.d.rule.q);
  }
  r.fresh = p.fresh;
  r.null_fresh = p.null_fresh;
  r.confirmations = p.confirmations;
  r.next = p.next;
  r.bound = p.bound;
  r.second = p.second;
  r.reach = p.reach;
  r.limits = p.limits;
  r.within_inflation = p.within_inflation;
  r.unseen = p.unseen;
  r.seen_on_fresh = p.seen_on_fresh;
  r.confirmed_on_fresh = p.confirmed_on_fresh;
  r.notes = p.notes;
  r.escalation = p.escalation;
  r.more_seeds = p.more_seeds;
  r.escalation_held_back = p.d.escalate_replicates > p.d.replicates && p.d.escalate_only_decidable &&
                           p.more_seeds.to != 0 && !p.more_seeds.worth();
  r.notes.insert(r.notes.end(), p.second.notes.begin(), p.second.notes.end());
  r.not_measured = p.tab.not_measured;
  r.assays_in_table = p.assays_in_table;
  r.runs = p.book.runs();
  r.computed = p.book.computed();
  r.device = p.book.device();
  r.store = p.store;
  r.wall_s = wall_s;
  r.stages = std::move(stages);
  return r;
}

std::string refit_phrase(const Report& r, size_t j) {
  if (!has_refit(r)) return "";
  std::string keys;
  for (const RefitKey& k : r.spec->refit) keys += (keys.empty() ? "" : ", ") + k.key;
  if (j == 0) return keys + " kept as calibrated";
  std::string to;
  for (const std::string& o : r.settings.at(j).overrides) {
    const size_t eq = o.find('=');
    const std::string key = o.substr(0, eq);
    std::string v = o.substr(eq + 1);
    // As the user wrote it in [refit_values] ("5.4", not the override's round-trip "5.4000000000000004").
    for (const RefitKey& k : r.spec->refit)
      if (k.key == key)
        for (const RefitValue& x : k.values)
          if (x.toml == v) v = x.written;
    if (v.size() >= 2 && v.front() == '"') v = v.substr(1, v.size() - 2);
    to += (to.empty() ? "" : " and ") + key + " re-fitted to " + v;
  }
  return to;
}

namespace {

// The interval at two standard errors (fit.h, set_two_se_interval), after the reported one.
std::string two_se_text(const StrengthFit& f) {
  // Not set (a fit outside decide), or nothing determined at one standard error already.
  if (f.lo2 <= 0 || (f.open_lo && f.open_hi)) return "";
  if (f.open_lo2 && f.open_hi2) return "; at 2 SE any strength probed";
  if (f.open_hi2) return fmt::format("; at 2 SE {:.3g} and above", f.lo2);
  if (f.open_lo2) return fmt::format("; at 2 SE {:.3g} and below", f.hi2);
  return fmt::format("; at 2 SE {:.3g}-{:.3g}", f.lo2, f.hi2);
}

}  // namespace

std::string strength_text(const Candidate& c, const CandidateRuns* runs) {
  const StrengthFit& f = c.fit;
  std::string shape;
  if (runs && c.shape < runs->shapes.size() && !std::isnan(runs->shapes[c.shape]))
    shape = fmt::format(" at {} = {:.3g}", effect_spec(c.effect).shape, runs->shapes[c.shape]);
  std::string interval;
  if (f.open_lo && f.open_hi)
    interval = "any strength probed fits as well: not determined";
  else if (f.open_hi)
    interval = fmt::format(
        "{:.3g} and above: the interval runs to the strongest strength that could be probed", f.lo);
  else if (f.open_lo)
    interval = fmt::format("{:.3g} and below: the interval runs to the weakest strength probed", f.hi);
  else
    interval = fmt::format("{:.3g}-{:.3g}", f.lo, f.hi);
  // The interval spans the other shapes where they fit as well (widen_by_profile): say so beside the shape.
  if (!shape.empty() && f.profile_members > 0)
    interval += fmt::format(", over every {} that fits as well", effect_spec(c.effect).shape);
  interval += two_se_text(f);
  return fmt::format("{:.3g}{} ({})", f.strength, shape, interval);
}

std::string verdict_line(const Verdict& v, const std::string& second) {
  const bool named = v.kind == "effect" || v.kind == "partial";
  if (!named) return v.kind;
  std::string s = v.kind + " (" + v.effect + (second.empty() ? "" : " + " + second);
  for (size_t i = 0; i < v.tied.size(); ++i) s += (i == 0 ? "; tied: " : ", ") + v.tied[i];
  return s + ")";
}

nlohmann::json write_report(const std::string& dir, const Report& r, bool figures) {
  fs::create_directories(dir);
  using nlohmann::json;
  const FreshCheck* chosen = r.chosen();
  const bool after = chosen && !chosen->after.empty();
  const bool named = r.verdict.kind == "effect" || r.verdict.kind == "partial";
  json j;
  j["name"] = r.spec->name;
  j["case"] = r.spec->case_path;
  j["observations"] = r.spec->observations;
  // Seeds per condition (the file's `replicates`, or --replicates): baseline 1..R, fresh R+1..2R.
  j["replicates"] = r.spec->replicates;
  j["probe_seeds"] = r.spec->probe_seeds;  // seeds per probe knot: 1..P of the baseline's
  j["verdict"] = r.verdict.kind;
  j["fresh_rejected"] = r.verdict.fresh_rejected;  // the chosen fit did not reproduce on fresh seeds
  j["seed_luck_chi2"] = r.verdict.seed_luck;       // mean |Δχ²| between seed sets of the model (verdict.h)
  // The control of the fresh check: the model without an effect at the fresh seeds (null when not run).
  j["chi2_null_fresh"] = r.null_fresh.after.empty() ? json(nullptr) : json(chi2_of(r.null_fresh.gaps_after));
  j["effect"] = named ? json(r.verdict.effect) : json(nullptr);
  j["effects"] = json::array();  // every effect the verdict names: the first, then a second on top of it
  if (named) j["effects"].push_back(r.verdict.effect);
  if (named && r.second_named()) j["effects"].push_back(r.second_named()->effect);
  j["tied"] = r.verdict.tied;
  j["tied_on_fresh"] = r.verdict.tied_on_fresh;  // near ties held out that tie on fresh runs
  if (const auto& po = r.verdict.passed_over; !po.effect.empty())  // first held out, unconfirmed fresh
    j["passed_over"] = {{"effect", po.effect},
                        {"strength", po.strength},
                        {"held_out_chi2", po.loco},
                        {"fresh_chi2", po.fresh_chi2},
                        {"control_chi2", po.control_chi2}};
  j["held_by_luck"] = r.verdict.held_by_luck;  // fresh comparisons the seed luck decided (verdict.h)
  // A tie named in the order the held-out score and the fresh runs favour together (tie_order_evidence).
  j["tie_order"] = r.verdict.reordered.effect.empty() ? json(nullptr)
                                                      : json{{"first_held_out", r.verdict.reordered.effect},
                                                             {"held_out_z", r.verdict.reordered.held_out_z},
                                                             {"fresh_z", r.verdict.reordered.fresh_z}};
  // The first pass at fewer seeds, when its verdict was not decided and the diagnosis ran again.
  j["escalation"] = r.escalation.from == 0 ? json(nullptr)
                                           : json{{"from_replicates", r.escalation.from},
                                                  {"to_replicates", r.escalation.to},
                                                  {"tied", r.escalation.tied},
                                                  {"held_by_luck", r.escalation.held_by_luck},
                                                  {"baseline_only", r.escalation.baseline_only},
                                                  {"seed_luck_chi2", r.escalation.seed_luck},
                                                  {"verdict", r.escalation.verdict},
                                                  {"runs_computed", r.escalation.runs_computed},
                                                  {"outlook", more_seeds_json(r.escalation.outlook)}};
  // Whether more seeds per condition could decide this report's verdict (more_seeds.h); null when decided.
  j["more_seeds"] = r.more_seeds.to == 0 ? json(nullptr) : more_seeds_json(r.more_seeds);
  j["rule"] = {{"fdr", r.spec->rule.q},
               {"table_level", r.spec->rule.table_level},
               {"held_out", r.spec->rule.held_out == HeldOut::kLogDensity ? "log_density" : "chi2"},
               {"ratio", r.spec->rule.ratio},
               {"min_drop", r.spec->rule.min_drop},
               {"tie_delta", r.spec->rule.tie_delta},
               {"tie_noise", r.spec->rule.tie_noise},
               {"tie_draws", r.spec->rule.tie_draws}};
  j["where_summary"] = r.where;
  j["table"] = table_json(table_fit(r.gaps, r.spec->rule.table_level));
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
    if (after)
      c["after"] = {{"model", chosen->after[k].mean},
                    {"model_se", chosen->after[k].se},
                    {"z", chosen->gaps_after[k].z},
                    {"significant", bool(chosen->gaps_after[k].significant)}};
    if (const FreshCheck* f2 = r.second_fresh())
      c["after_second"] = {{"model", f2->after[k].mean},
                           {"model_se", f2->after[k].se},
                           {"z", f2->gaps_after[k].z},
                           {"significant", bool(f2->gaps_after[k].significant)}};
    j["cells"].push_back(c);
  }
  for (const Screened& s : r.screened)
    j["screen"].push_back({{"effect", s.effect}, {"score", s.score}, {"probe", s.strength}});
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
  j["ranking"] = json::array();
  for (const Candidate& c : r.verdict.ranking) {
    const CandidateRuns* cr = r.runs_of(c.effect);
    const EffectSpec& spec = effect_spec(c.effect);
    json x = {{"effect", c.effect},
              {"screen", c.screen},
              {"loco_chi2", c.loco},
              {"weight", r.verdict.null_loco > 0 ? 1.0 - c.loco / r.verdict.null_loco : 0.0},
              {"strength", c.fit.strength},
              {"strength_interval", {c.fit.lo, c.fit.hi}},
              {"strength_interval_open", {c.fit.open_lo, c.fit.open_hi}},
              {"strength_interval_2se", {c.fit.lo2, c.fit.hi2}},
              {"strength_interval_2se_open", {c.fit.open_lo2, c.fit.open_hi2}},
              {"strength_interval_delta_chi2", c.fit.delta},
              {"strength_interval_chi2", {c.fit.chi2_lo, c.fit.chi2_hi}},
              {"strength_jackknife_se_log10", c.fit.jackknife_se_log10},
              {"strength_emulator_se_log10", c.fit.emulator_se_log10},
              {"strength_interval_profile_members", c.fit.profile_members},
              {"strength_at_edge", c.fit.at_edge},
              {"strength_meaning", spec.strength},
              {"physical_range", {spec.phys_lo, spec.phys_hi}},
              {"at_physical_limit", cr ? cr->at_limit : 0},
              {"range_cut_at", cr && std::isfinite(cr->cut) ? json(cr->cut) : json(nullptr)},
              {"notes", cr ? cr->notes : std::vector<std::string>{}},
              {"text", strength_text(c, cr)}};
    // Against the chosen (first) candidate: the held-out difference's noise over paired emulator redraws and
    // the near-tie margin (verdict.h, tie_noise: within it, the candidate is run fresh); null where this
    // candidate has no draws.
    const Candidate& first = r.verdict.ranking.front();
    if (&c != &first && !c.loco_draws.empty() && !first.loco_draws.empty()) {
      x["loco_chi2_noise"] = held_out_noise(first, c);
      x["near_tie_margin"] = near_tie_margin(first, c, r.spec->rule);
    } else {
      x["loco_chi2_noise"] = nullptr;
      x["near_tie_margin"] = nullptr;
    }
    if (cr && c.shape < cr->shapes.size() && !std::isnan(cr->shapes[c.shape]))
      x["shape"] = {{"meaning", spec.shape}, {"value", cr->shapes[c.shape]}, {"probed", cr->shapes}};
    if (refit) x["refit"] = setting_json(c.refit);
    j["ranking"].push_back(x);
  }
  if (refit && !r.null_refit_gaps.empty()) {
    j["null_refit"] = setting_json(r.verdict.null_refit);
    j["null_refit"]["chi2"] = chi2_of(r.null_refit_gaps);
    j["null_refit"]["significant_cells"] = significant(r.null_refit_gaps);
  }
  for (const CandidateRuns& cr : r.fitted)
    for (size_t i = 0; i < cr.members.size(); ++i) {
      const Response& resp = cr.members[i];
      json x = {{"effect", resp.effect}, {"strengths", resp.strengths}};
      if (!std::isnan(cr.shapes[cr.shape_of[i]])) x["shape"] = cr.shapes[cr.shape_of[i]];
      if (refit) x["refit"] = setting_json(cr.refit_of[i]);
      for (const auto& p : resp.pred) {
        json row;
        for (const Prediction& q : p) row.push_back({q.mean, q.se});
        x["pred"].push_back(row);
      }
      j["responses"].push_back(x);
    }
  j["null_loco_chi2"] = r.verdict.null_loco;
  j["held_out_shrink"] = r.verdict.ranking.empty() ? json(nullptr) : json(r.verdict.held_out_shrink);
  j["held_out_gap_shrink"] = r.verdict.ranking.empty() ? json(nullptr) : json(r.verdict.held_out_gap_shrink);
  j["noise_floor_chi2"] = r.verdict.floor;
  j["chi2_before"] = chi2_of(r.gaps);
  j["dof"] = r.cells.size();
  j["fresh"] = json::array();
  for (const FreshCheck& f : r.fresh) {
    json x = {{"effect", f.effect}, {"strength", f.strength}, {"shape", app::number_or_null(f.shape)}};
    if (refit) x["refit"] = setting_json(f.refit);
    if (!f.failure.empty()) x["failure"] = f.failure;
    if (!f.after.empty()) {
      x["chi2_after"] = chi2_of(f.gaps_after);
      x["significant_cells"] = significant(f.gaps_after);
      x["table_after"] = table_json(table_fit(f.gaps_after, r.spec->rule.table_level));
    }
    j["fresh"].push_back(x);
  }
  j["confirmations"] = json::array();
  for (const FreshCheck& f : r.confirmations)
    j["confirmations"].push_back({{"effect", f.effect},
                                  {"strength", f.strength},
                                  {"shape", app::number_or_null(f.shape)},
                                  {"chi2_after", chi2_of(f.gaps_after)},
                                  {"significant_cells", significant(f.gaps_after)}});
  if (after) {
    j["chosen_strength"] = chosen->strength;
    j["chosen_shape"] = app::number_or_null(chosen->shape);
    if (refit) j["chosen_refit"] = setting_json(chosen->refit);
    j["chi2_after"] = chi2_of(chosen->gaps_after);
    j["shrink"] = 1.0 - chi2_of(chosen->gaps_after) / std::max(1e-300, chi2_of(r.gaps));
    json rem = json::array();
    for (size_t k = 0; k < r.cells.size(); ++k)
      if (chosen->gaps_after[k].significant)
        rem.push_back(r.cell_condition[k] + " / " + r.cells[k].observable);
    j["remaining_gap"] = rem;
  }
  if (!r.next.effect_a.empty() || !r.next.note.empty()) j["next_experiment"] = next_json(r);
  if (!r.bound.effect.empty()) j["bound_experiment"] = bound_json(r);
  j["second"] = second_json(r);
  j["reach"] = reach_json(r);
  j["limits"] = limits_json(r);
  j["limits_free_shape"] = free_shape_limits_json(r);
  j["measure_next"] = asked_json(r);
  j["within_inflation"] = r.within_inflation;
  // Unseen: the probes cannot show them apart from noise (power.h); such a candidate is named only as tied
  // on its held-out score and kept on fresh runs, or first where fresh runs favour it (name_only_seen).
  j["unseen"] = r.unseen;
  std::vector<std::string> not_named;
  for (const std::string& e : r.unseen)
    if (e != r.verdict.effect &&
        std::find(r.verdict.tied.begin(), r.verdict.tied.end(), e) == r.verdict.tied.end())
      not_named.push_back(e);
  j["not_named_unseen"] = not_named;
  // Unseen on their probes but shown by their fresh runs against the control (power.h, fresh_shift).
  j["seen_on_fresh"] = r.seen_on_fresh;
  // Unseen on their probes, named first in a tie because their fresh runs confirm them (fresh_ties.cpp).
  j["confirmed_on_fresh"] = r.confirmed_on_fresh;
  j["notes"] = r.notes;
  j["not_measured"] = r.not_measured;
  j["assays_in_table"] = r.assays_in_table;
  j["runs"] = r.runs;
  j["runs_computed"] = r.computed;
  j["store"] = r.store;
  j["device"] = r.device;
  j["wall_s"] = r.wall_s;
  j["stages"] = nlohmann::json::array();
  for (const StageCost& c : r.stages)
    j["stages"].push_back({{"stage", c.stage}, {"wall_s", c.wall_s}, {"runs_computed", c.runs_computed}});
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
      for (const char* f : {"gap_map", "observables", "ranking", "reach", "limits", "next_experiment"})
        if (fs::exists(fs::path(dir) / "figures" / (std::string(f) + ".png")))
          figs += fmt::format("![{}](figures/{}.png)\n\n", f, f);
  }
  std::string md = "# Sim-to-real diagnosis: " + r.spec->name + "\n\n" + verdict_paragraph(r) + "\n\n";
  md += asked_markdown(r);
  md += "## Where\n\n";
  for (const std::string& w : r.where) md += "- " + w + "\n";
  {
    const TableFit t = table_fit(r.gaps, r.spec->rule.table_level);
    md += "- the table as a whole: " + table_text(t) +
          (t.beyond && significant(r.gaps) == 0 ? ": a gap spread over the cells, none significant alone"
                                                : "") +
          "\n";
  }
  md += "\n| condition | observable | observed | model (baseline) | z | significant |";
  md += after ? fmt::format(" with `{}` | z after |\n|---|---|---|---|---|---|---|---|\n", chosen->effect)
              : "\n|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < r.cells.size(); ++k) {
    md += fmt::format("| {} | {} | {:.4g} ± {:.2g} | {:.4g} ± {:.2g} | {:+.2f} | {} |", r.cell_condition[k],
                      r.cells[k].observable, r.cells[k].y, r.cells[k].sigma, r.baseline[k].mean,
                      r.baseline[k].se, r.gaps[k].z, r.gaps[k].significant ? "yes" : "no");
    if (after)
      md += fmt::format(" {:.4g} ± {:.2g} | {:+.2f}{} |", chosen->after[k].mean, chosen->after[k].se,
                        chosen->gaps_after[k].z,
                        chosen->gaps_after[k].significant ? " (still significant)" : "");
    md += "\n";
  }
  for (const std::string& a : r.assays_in_table)
    md += fmt::format(
        "\n`{}` was an assay of the diagnosis file ([assays]) and the table measures it now: its rows are "
        "observations like the others, fitted with their own σ, and a new measurement of it carries the "
        "table's σ, not the file's.\n",
        a);
  if (!r.not_measured.empty()) {
    md += "\nRows of the table that say a quantity was not measured (left out): ";
    for (const std::string& s : r.not_measured) md += s + "; ";
    md += "\n";
  }
  md += "\n## Candidates\n\n| effect | screen score | held-out χ² (LOCO) | fitted strength (interval) |";
  md += refit ? " re-fitted (all cells) | notes |\n|---|---|---|---|---|---|\n"
              : " notes |\n|---|---|---|---|---|\n";
  if (refit)
    md += fmt::format("| (none: the model without an added effect) | | {:.2f} | | {} | |\n",
                      r.verdict.null_loco, r.settings.at(r.verdict.null_refit).label);
  else
    md += fmt::format("| (none: the model as calibrated) | | {:.2f} | | |\n", r.verdict.null_loco);
  for (const Candidate& c : r.verdict.ranking) {
    const CandidateRuns* cr = r.runs_of(c.effect);
    std::string notes;
    if (cr)
      for (const std::string& n : cr->notes) notes += (notes.empty() ? "" : "; ") + n;
    if (std::find(r.unseen.begin(), r.unseen.end(), c.effect) != r.unseen.end())
      notes += std::string(notes.empty() ? "" : "; ") +
               "**unseen**: its probes move no cell by 3 σ, so it is never named first on this score";
    if (std::find(r.seen_on_fresh.begin(), r.seen_on_fresh.end(), c.effect) != r.seen_on_fresh.end())
      notes += std::string(notes.empty() ? "" : "; ") +
               "**seen on its fresh runs**: its probes alone move no cell by 3 σ, its fresh runs against the "
               "model without it do";
    if (std::find(r.confirmed_on_fresh.begin(), r.confirmed_on_fresh.end(), c.effect) !=
        r.confirmed_on_fresh.end())
      notes += std::string(notes.empty() ? "" : "; ") +
               "**confirmed on its fresh runs**: its probes alone move no cell by 3 σ, its fresh runs lower "
               "χ² below the model's on the same seeds by more than the seed luck";
    md += fmt::format("| {} | {:.2f} | {:.2f} | {} {} |", c.effect, c.screen, c.loco,
                      effect_spec(c.effect).strength, strength_text(c, cr));
    md += refit ? fmt::format(" {} |", r.settings.at(c.refit).label) : "";
    md += " " + notes + " |\n";
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
  for (const Screened& s : r.screened) md += fmt::format("{} {:.2f}; ", s.effect, s.score);
  md += fmt::format(
      "\n\nRule: `effect` when the best held-out χ² ≤ floor + {} × (the null's − floor) and lower than the "
      "null's by ≥ {} (the null's {:.1f}, its noise floor {:.1f}: the mean z² of the cells not significant, "
      "times the cells, at most 1 a cell), and the fresh-seed runs at its fitted strength leave no gap (no "
      "cell significant, χ² over the table within its {:.3g} % point; else `partial`); a runner-up that also "
      "passes is *tied* unless its held-out χ² exceeds the best's by ≥ {} × max(1, χ²_best/n); one within "
      "twice that, or within {} standard deviations of the difference over {} paired redraws of the two "
      "emulators within their runs' SE (the probes' own noise), is run with fresh seeds and tied if its "
      "fresh χ² is not clearly worse, and a tie whose fresh χ² is clearly worse (by more than that margin "
      "and the model's own seed luck) is not named; the fresh "
      "runs must lower χ² below the model's on the same fresh seeds by ≥ {} or "
      "the model's own seed luck ({:.1f}), whichever is more; a candidate the probes cannot show is never "
      "named first on its held-out score; cells significant by Benjamini-Hochberg at {}. Intervals: Δχ² = "
      "max(1, χ²_min/(n − "
      "1)), widened to the fit ± the standard errors of the jackknife over conditions and of the emulator's "
      "redraws where they are wider; at 2 SE: "
      "each side's distance from the fit in log10 doubled.\n\n",
      r.spec->rule.ratio, r.spec->rule.min_drop, r.verdict.null_loco, r.verdict.floor,
      100 * r.spec->rule.table_level, r.spec->rule.tie_delta, r.spec->rule.tie_noise, r.spec->rule.tie_draws,
      r.spec->rule.min_drop, r.verdict.seed_luck, r.spec->rule.q);
  md += next_markdown(r);
  md += bound_markdown(r);
  md += second_markdown(r);
  md += reach_markdown(r);
  md += limits_markdown(r);
  if (!r.notes.empty()) {
    md += "## Runs that could not be made\n\n";
    for (const std::string& n : r.notes) md += "- " + n + "\n";
    md += "\n";
  }
  md += figs;
  md += fmt::format("Runs: {} in the store ({} computed now), device {}, wall time {:.0f} s", r.runs,
                    r.computed, r.device.empty() ? "-" : r.device, r.wall_s);
  std::string per_stage;
  for (const StageCost& c : r.stages)
    per_stage += fmt::format("{}{} {:.0f} s ({} runs)", per_stage.empty() ? "" : "; ", c.stage, c.wall_s,
                             c.runs_computed);
  md += per_stage.empty() ? ".\n" : " (" + per_stage + ").\n";
  app::write_file_atomic((fs::path(dir) / "report.md").string(), md);
  return j;
}

}  // namespace wetdem::diagnose
