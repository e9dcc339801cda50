// The plain-language verdict of report.md: what a process engineer can act on. It says which effect explains
// the gap and how sure that is (an open interval, a physical limit, a tie with the runner-up and the
// measurement that would separate them), or which cells stay unexplained.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "diagnose/effects.h"
#include "diagnose/more_seeds.h"
#include "diagnose/paragraph_next.h"
#include "diagnose/paragraph_silent.h"
#include "diagnose/power.h"
#include "diagnose/report.h"

namespace wetdem::diagnose {

namespace {

// What the null model with refit leaves (only with refit and a fitted null): a sentence for the paragraph.
std::string null_refit_sentence(const Report& r) {
  if (!has_refit(r) || r.null_refit_gaps.empty()) return "";
  return fmt::format(
      " Without any added effect, the model with {} scores a held-out χ² of {:.1f} and leaves {} of {} cells "
      "significant.",
      refit_phrase(r, r.verdict.null_refit), r.verdict.null_loco, significant(r.null_refit_gaps),
      r.cells.size());
}

// The table's χ² test on a gap set, in words (where.h, table_fit).
std::string table_words(const Report& r, const std::vector<CellGap>& g) {
  return table_text(table_fit(g, r.spec->rule.table_level));
}

// What a model leaves: its significant cells ("aor_deg_std at 5 % (z = +3.4); ..."), or, when none is but
// the table's χ² is beyond its point (where.h, table_fit), that χ².
std::string left_text(const Report& r, const std::vector<CellGap>& g) {
  std::string left;
  for (size_t k = 0; k < g.size() && k < r.cells.size(); ++k)
    if (g[k].significant)
      left += fmt::format("{}{} at {} (z = {:+.1f})", left.empty() ? "" : "; ", r.cells[k].observable,
                          r.cell_condition[k], g[k].z);
  if (!left.empty()) return left;
  return "no cell alone, but the cells together (" + table_words(r, g) + ")";
}

const Candidate* candidate(const Report& r, const std::string& e) {
  for (const Candidate& c : r.verdict.ranking)
    if (c.effect == e) return &c;
  return nullptr;
}

// Why a runner-up clearly worse held out was run fresh, when its probes' noise (VerdictRule::tie_noise,
// verdict.h) rather than twice the tie margin made it a near tie; empty otherwise.
std::string noise_words(const Candidate& best, const Candidate& c, const VerdictRule& rule) {
  if (c.loco - best.loco < 2.0 * tie_margin(best, rule)) return "";
  return fmt::format(
      " (a difference within {:g} standard deviations ({:.1f}) of what the noise of the two candidates' "
      "probe runs alone moves it, so both were run with fresh seeds)",
      rule.tie_noise, held_out_noise(best, c));
}

// The tie and the next experiment, when the runner-up is not clearly worse.
std::string tie_sentence(const Report& r) {
  if (r.verdict.tied.empty()) return "";
  const Candidate* best = candidate(r, r.verdict.effect);
  std::string s;
  for (const std::string& e : r.verdict.tied) {
    const Candidate* c = candidate(r, e);
    if (!c || !best) continue;
    const FreshCheck *fc = r.fresh_of(e), *fb = r.chosen();
    const bool on_fresh = std::find(r.verdict.tied_on_fresh.begin(), r.verdict.tied_on_fresh.end(), e) !=
                          r.verdict.tied_on_fresh.end();
    // Tied though clearly worse held out: the fresh runs kept it (a first named on them, shrink.cpp).
    const bool kept =
        fc && fb && !fc->after.empty() && !fb->after.empty() && clearly_worse(*best, *c, r.spec->rule);
    const Verdict::ReorderedTie& ro = r.verdict.reordered;
    if (ro.effect == e && fc && fb && !fc->after.empty() && !fb->after.empty()) {
      // The first named on the weight of the evidence (fresh_ties.cpp, order_tie_by_evidence).
      if (ro.held_out_z < 0) {
        // Both leans favour the new first: it was named first only because its own probes could not show
        // it, until its fresh runs confirmed it.
        const bool confirmed = std::find(r.confirmed_on_fresh.begin(), r.confirmed_on_fresh.end(),
                                         r.verdict.effect) != r.confirmed_on_fresh.end();
        s += fmt::format(
            " **`{}` explains the data nearly as well**: held out it scored {:.1f} against {:.1f}, and "
            "on fresh runs its χ² is {:.1f} against {:.1f}. Neither is clearly worse; both lean to `{}` "
            "({:.2f} and {:.2f} standard deviations of their noise), which is named first.{} Both are "
            "reported ({} = {}).",
            e, c->loco, best->loco, chi2_of(fc->gaps_after), chi2_of(fb->gaps_after), r.verdict.effect,
            -ro.held_out_z, ro.fresh_z,
            confirmed && !r.null_fresh.after.empty()
                ? fmt::format(" `{}`'s own probes move no cell of the table by 3 σ, but its fresh runs "
                              "give χ² {:.1f} against {:.1f} for the model without it on the same seeds, "
                              "lower by more than the model's own seed luck ({:.1f}): its held-out score "
                              "is not its probes' noise alone.",
                              r.verdict.effect, chi2_of(fb->gaps_after), chi2_of(r.null_fresh.gaps_after),
                              r.verdict.seed_luck)
                : std::string(),
            effect_spec(e).strength, strength_text(*c, r.runs_of(e)));
      } else {
        s += fmt::format(
            " **`{}` explains the data nearly as well**: held out it scored {}{:.1f} against {:.1f} "
            "({:.2f} standard deviations of that difference's noise in its favour), but on fresh runs its "
            "χ² is {:.1f} against {:.1f} ({:.2f} standard deviations of the model's own seed luck against "
            "it). Neither is clearly worse; the two, each weighed by its noise, favour `{}`, which is "
            "named first. Both are reported ({} = {}).",
            e, c->loco < best->loco ? "better, " : "", c->loco, best->loco, ro.held_out_z,
            chi2_of(fc->gaps_after), chi2_of(fb->gaps_after), ro.fresh_z, r.verdict.effect,
            effect_spec(e).strength, strength_text(*c, r.runs_of(e)));
      }
      continue;
    }
    s +=
        kept ? fmt::format(
                   " **`{}` explains the data nearly as well**: held out it scored {:.1f} against {:.1f}{}, "
                   "but on fresh runs its χ² is {:.1f} against {:.1f}, not clearly worse by the tie rule "
                   "and the model's own seed luck ({:.1f}). The data do not single one out, and both are "
                   "reported ({} = {}).",
                   e, c->loco, best->loco, noise_words(*best, *c, r.spec->rule), chi2_of(fc->gaps_after),
                   chi2_of(fb->gaps_after), r.verdict.seed_luck, effect_spec(e).strength,
                   strength_text(*c, r.runs_of(e)))
        : on_fresh && fc && fb && !fc->after.empty() && !fb->after.empty()
            ? fmt::format(
                  " **`{}` explains the data nearly as well**: held out it scored {:.1f} against {:.1f}, "
                  "close enough that both were run with fresh seeds, and there its χ² is {:.1f} against "
                  "{:.1f}, not clearly worse by the tie rule ({} = {}). The data do not single one out, "
                  "and both are reported.",
                  e, c->loco, best->loco, chi2_of(fc->gaps_after), chi2_of(fb->gaps_after),
                  effect_spec(e).strength, strength_text(*c, r.runs_of(e)))
            : fmt::format(
                  " **`{}` explains the data {}** (held-out χ² {:.1f} against {:.1f}, {}; {} = {}): the data "
                  "do not single one out, and both are reported.",
                  e, c->loco < best->loco ? "as well" : "nearly as well", c->loco, best->loco,
                  c->loco < best->loco ? "lower" : "not clearly worse by the tie rule",
                  effect_spec(e).strength, strength_text(*c, r.runs_of(e)));
    if (std::find(r.unseen.begin(), r.unseen.end(), e) != r.unseen.end())
      s += fmt::format(
          " Its own probes move no cell of the table by 3 σ, so its held-out score alone could be their "
          "noise; {}",
          fc && !fc->after.empty() ? "its fresh runs at the fitted strength keep it in the tie."
                                   : "no fresh runs of it were made.");
  }
  return s + next_sentence(r);
}

std::string limit_sentence(const Report& r, const std::string& e) {
  const CandidateRuns* cr = r.runs_of(e);
  if (!cr) return "";
  if (cr->at_limit > 0)
    return fmt::format(
        " The fit runs into the end of the range that could be probed ({}); the true strength may lie "
        "beyond it.",
        std::isfinite(cr->cut) ? fmt::format("runs from {:.3g} on could not be made", cr->cut)
                               : fmt::format("the physical limit {:g}", effect_spec(e).phys_hi));
  return "";
}

// The share of the gap a candidate removes held out (verdict.h, held_out_gap_shrink). Above 1 its held-out χ²
// fell below the noise floor, which is estimated from the baseline's own cells (not from the emulator's wider
// predictions): "all the gap", not "120 % of the gap".
std::string gap_removed(double share) {
  return share >= 1.0 ? "all the gap above the noise floor" : fmt::format("{:.0f} % of the gap", 100 * share);
}

// Names as code in a sentence: "`a`", "`a` and `b`", "`a`, `b` and `c`" ("" for none).
std::string code_list(const std::vector<std::string>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i)
    s += (i == 0 ? "`" : i + 1 == v.size() ? " and `" : ", `") + v[i] + "`";
  return s;
}

std::string verdict_core(const Report& r);

}  // namespace

namespace {

// The fresh comparisons the model's own seed luck decided (Verdict::held_by_luck): what more replicates
// could settle.
std::string luck_sentence(const Report& r) {
  const std::vector<std::string>& h = r.verdict.held_by_luck;
  if (h.empty()) return "";
  std::vector<std::string> k;
  std::string unconfirmed, on_top;
  // The second round's candidate was not in a tie: the luck decided its confirmation on top of the first.
  const bool second = r.second.outcome == "unconfirmed" && r.chosen();
  for (const std::string& e : h)
    if (e == r.verdict.effect && r.verdict.fresh_rejected)
      unconfirmed = e;
    else if (second && e == r.second.fresh.effect)
      on_top = e;
    else
      k.push_back(e);
  const std::string kept = code_list(k);
  std::string what;
  if (!kept.empty()) what = "kept " + kept + " in the tie";
  if (!unconfirmed.empty())
    what += (what.empty() ? "" : ", and ") + fmt::format("left `{}` unconfirmed", unconfirmed);
  if (!on_top.empty())
    what += (what.empty() ? "" : ", and ") +
            fmt::format("left `{}` unconfirmed on top of `{}`", on_top, r.chosen()->effect);
  // The outlook (more_seeds.h) may say that lower luck is unlikely to decide it: then the sentence says so,
  // and more_seeds_sentence gives the numbers.
  const bool futile = r.more_seeds.to != 0 && !r.more_seeds.worth();
  return fmt::format(
      " **The seed luck decided:** the fresh runs {} although their χ² differ by more than the tie margin "
      "(or min_drop), because the same model moves on average by {:.1f} between two seed sets of {} run{} "
      "per condition. {}",
      what, r.verdict.seed_luck, r.spec->replicates, r.spec->replicates == 1 ? "" : "s",
      futile
          ? std::string("Lower luck alone is unlikely to decide ") + (h.size() == 1 ? "it" : "them") +
                " (below)."
          : std::string("More replicates (`replicates` in the diagnosis file, or `--replicates`; each adds "
                        "one run per condition to the baseline and to every fresh check) would lower that "
                        "luck and could decide ") +
                (h.size() == 1 ? "it" : "them") + ".");
}

// Whether more seeds could decide the ties (more_seeds.h): the separation the table allows between the two
// fitted models, against the tie margin, and what the diagnosis did about it.
std::string more_seeds_sentence(const Report& r) {
  const MoreSeeds& m = r.more_seeds;
  if (m.to == 0) return "";
  std::string known;
  for (const TieOutlook& t : m.ties) {
    if (!t.known) continue;
    known += fmt::format(
        "{}from `{}` by a χ² of {:.1f} at {} seeds per condition ({:.1f} with exact models) "
        "against a tie margin of {:.1f}",
        known.empty() ? "" : "; ", t.effect, t.at_more, m.to, t.exact, t.margin);
    if (!t.could_decide())
      known += t.seeds_needed > 0
                   ? fmt::format(", reached from about {} seeds", t.seeds_needed)
                   : fmt::format(
                         ", by no number of seeds up to {}: the two fitted models leave one fingerprint on "
                         "what this table measures",
                         kMostSeeds);
  }
  if (known.empty()) return "";
  const std::string chosen = r.verdict.effect;
  if (!m.worth())
    return fmt::format(
        " **More seeds alone are unlikely to decide the tie:** by the fitted models' fresh runs, the table "
        "would "
        "separate `{}` {}{}. More seeds also re-fit both models, which can move them apart; a measurement "
        "where "
        "they differ is the surer way (the next experiment).",
        chosen, known,
        r.escalation_held_back
            ? fmt::format(", so the diagnosis did not run again at {} seeds (`escalate_when = "
                          "\"decidable\"`)",
                          m.to)
            : "");
  return fmt::format(
      " **More seeds could decide the tie:** by the fitted models' fresh runs, the table would separate `{}` "
      "{} "
      "(the expected χ² difference when one of them is the truth). Run the diagnosis at {} seeds per "
      "condition "
      "(`replicates`, or `escalate_replicates = {}`, which runs again only when a verdict is undecided).",
      chosen, known, m.to, m.to);
}

// An escalated diagnosis (driver.cpp): what the first pass found and why it ran again.
std::string escalation_sentence(const Report& r) {
  const Escalation& e = r.escalation;
  if (e.from == 0) return "";
  std::string why;
  if (!e.tied.empty()) why = "the tie with " + code_list(e.tied) + " held on fresh runs";
  if (!e.held_by_luck.empty())
    why += (why.empty() ? "" : ", and ") +
           fmt::format("the model's seed luck ({:.1f}) decided {}", e.seed_luck, code_list(e.held_by_luck));
  if (e.baseline_only)
    why += (why.empty() ? "" : ", and ") +
           std::string(
               "its gap showed on the baseline's seeds only (no candidate's fresh runs confirmed it, and "
               "the model itself departed from no cell on the fresh seeds)");
  if (e.outlook.to != 0 && !e.outlook.worth())
    why +=
        " (the fitted models' fresh runs gave more seeds too little to separate them by; the second pass "
        "re-fits them)";
  for (const TieOutlook& t : e.outlook.ties)
    if (t.known && t.could_decide())
      why += fmt::format(
          " (the fitted models of `{}` differed by enough for more seeds to decide: χ² {:.1f} "
          "expected at {} seeds against a margin of {:.1f})",
          t.effect, t.at_more, e.to, t.margin);
  return fmt::format(
      " **Run again with more seeds:** at {} seed{} per condition the verdict was {}: {}. This report is the "
      "diagnosis at {} seeds per condition (`escalate_replicates`), which reused the first pass's runs it "
      "needed.",
      e.from, e.from == 1 ? "" : "s", e.verdict, why, e.to);
}

// The candidates its single probe runs could not show but its fresh runs did (power.h, fresh_shift): why a
// candidate the table "cannot see" by its probes is named all the same.
std::string seen_sentence(const Report& r) {
  std::string s;
  for (const std::string& e : r.seen_on_fresh)
    for (const Reach& x : r.reach)
      if (x.effect == e && x.fresh)
        s += fmt::format(
            " `{}`'s own probes (one run each) move no cell of the table by 3 σ, but its fresh runs "
            "at {:.3g} do against the model without it on the same seeds ({:.1f} σ on {} at {}; the "
            "table's χ² by {:.1f}): the table sees it.",
            e, x.fresh_at, x.fresh_max_z, r.cells[x.fresh_cell].observable, r.cell_condition[x.fresh_cell],
            x.fresh_chi2_excess);
  return s;
}

// The candidate the held-out score put first whose fresh runs did not confirm it (promote_confirmed): why the
// named one is not the best held out.
std::string passed_over_sentence(const Report& r) {
  const auto& po = r.verdict.passed_over;
  if (po.effect.empty() || r.verdict.ranking.empty()) return {};
  return fmt::format(
      " `{}` came first held out ({:.1f} against {:.1f} for `{}`), but its fresh runs at {:.3g} did not "
      "reproduce it (χ² {:.1f} against {:.1f} for the model without it on the same fresh seeds), so it is "
      "not named.",
      po.effect, po.loco, r.verdict.ranking.front().loco, r.verdict.ranking.front().effect, po.strength,
      po.fresh_chi2, po.control_chi2);
}

}  // namespace

std::string verdict_paragraph(const Report& r) {
  return verdict_core(r) + limits_sentence(r) + bound_sentence(r) + passed_over_sentence(r) +
         seen_sentence(r) + escalation_sentence(r) + luck_sentence(r) + more_seeds_sentence(r) +
         blind_sentence(r) + strong_only_sentence(r);
}

namespace {

std::string verdict_core(const Report& r) {
  const size_t n = r.cells.size(), ns = significant(r.gaps);
  if (r.verdict.kind == "no_gap")
    return fmt::format(
        "**No gap.** The calibrated model agrees with the observations within their uncertainties: none of "
        "the {} measured cells differs significantly (false-discovery rate {:.0f} %), and the cells together "
        "stay within what their errors allow ({}). No effect needs to be added; a new measurement (another "
        "liquid content or speed) is what would test the model further.",
        n, 100 * r.spec->rule.q, table_words(r, r.gaps));
  // The observables with significant cells only: the report's Where section lists every one.
  std::string where;
  for (const std::string& w : describe_where(r.cells, r.gaps, true)) where += (where.empty() ? "" : "; ") + w;
  // Where the model departs: its significant cells, or the table as a whole (where.h, table_fit).
  const std::string departs =
      ns ? fmt::format("at {} of {} cells ({})", ns, n, where)
         : fmt::format("over the table as a whole: no cell alone is significant, but together they are ({})",
                       table_words(r, r.gaps));
  if (r.verdict.kind == "effect" || r.verdict.kind == "partial") {
    const Candidate& c = r.verdict.ranking.front();
    const EffectSpec& e = effect_spec(c.effect);
    const FreshCheck* f = r.chosen();
    const bool ok = f && !f->after.empty();
    const std::string control = r.null_fresh.after.empty()
                                    ? std::string()
                                    : fmt::format(" (the model without it on the same fresh seeds: {:.1f})",
                                                  chi2_of(r.null_fresh.gaps_after));
    const std::string fresh =
        ok ? fmt::format("fresh runs at {} = {:.3g} bring χ² from {:.1f} to {:.1f} over the {} cells{}",
                         e.strength, f->strength, chi2_of(r.gaps), chi2_of(f->gaps_after), n, control)
           : std::string("its fresh-seed runs could not be made");
    const std::string head = fmt::format(
        "The model departs from the observations {}. Of the candidates, `{}` ({}) explains it best: with {} "
        "= {}{} it predicts the conditions it was not fitted to {:.0f} % better than the model without it "
        "(held-out shrink), and {}",
        departs, c.effect, e.fingerprint, e.strength, strength_text(c, r.runs_of(c.effect)),
        has_refit(r) ? " and " + refit_phrase(r, c.refit) : "", 100 * r.verdict.held_out_shrink, fresh);
    if (const Candidate* b = r.second_named()) {
      const FreshCheck* f2 = r.second_fresh();
      const EffectSpec& eb = effect_spec(b->effect);
      const std::string left2 = f2 ? left_text(r, f2->gaps_after) : std::string();
      // Taken on through the joint fit (pair_fit.h): the pair's held-out χ² has both strengths re-fitted.
      const SecondRound& s2 = r.second;
      const std::string joint =
          s2.joint
              ? fmt::format(
                    " (fitted jointly: `{}` re-fitted to {:.3g}{} with it)", c.effect, s2.pair_first,
                    std::isnan(s2.pair_first_shape) || s2.pair_first_shape == s2.base_shape
                        ? ""
                        : fmt::format(" at {} = {:.3g}", effect_spec(c.effect).shape, s2.pair_first_shape))
              : "";
      const double held = s2.joint ? s2.joint_loco : b->loco;
      const std::string pair = fmt::format(
          "`{}` alone left cells significant, so the other candidates were fitted on top of it{}: `{}` ({}) "
          "with {} = {} explains what it leaves (held-out χ² {:.1f} against {:.1f} for `{}` alone){}",
          c.effect, joint, b->effect, eb.fingerprint, eb.strength,
          s2.joint ? fmt::format("{:.3g}", s2.fresh.strength)
                   : strength_text(*b, r.second_runs_of(b->effect)),
          held, r.second.verdict.null_loco, c.effect,
          f2 ? fmt::format(", and fresh runs of both bring χ² to {:.1f}", chi2_of(f2->gaps_after)) : "");
      if (r.verdict.kind == "effect")
        return fmt::format(
            "**Gap explained by `{}` and `{}` together.** {}. {}, none still significant.{}{}{} Add both to "
            "the model (or measure them directly) before trusting predictions at new conditions.",
            c.effect, b->effect, head, pair, limit_sentence(r, c.effect), null_refit_sentence(r),
            tie_sentence(r));
      return fmt::format(
          "**Gap explained in part by `{}` and `{}`.** {}. {}, but cells stay significant: {}. These need "
          "another cause; treat the fitted strengths as provisional until they are understood.{}{}",
          c.effect, b->effect, head, pair, left2.empty() ? "unknown (no fresh runs)" : left2,
          null_refit_sentence(r), tie_sentence(r));
    }
    if (r.verdict.kind == "effect") {
      // A tie is not a finding for the first-ranked effect: the headline and the advice name every tied one,
      // and adding one waits for the measurement that tells them apart (tie_sentence names it).
      std::string names = "`" + c.effect + "`";
      for (size_t i = 0; i < r.verdict.tied.size(); ++i)
        names += (i + 1 < r.verdict.tied.size() ? ", `" : " or `") + r.verdict.tied[i] + "`";
      const bool tie = !r.verdict.tied.empty();
      const std::string advice =
          tie ? fmt::format(
                    " Do not add {} to the model on this table alone: make the measurement that "
                    "separates them (or measure one directly), then add the one it supports before "
                    "trusting predictions at new conditions.",
                    r.verdict.tied.size() == 1 ? "either" : "any of them")
              : fmt::format(
                    " Add {} to the model (or measure it directly) before trusting predictions at new "
                    "conditions.",
                    names);
      return fmt::format("**Gap explained by {}{}** {}, none still significant.{}{}{}{}", names,
                         tie ? ": the data do not single one out." : ".", head, limit_sentence(r, c.effect),
                         null_refit_sentence(r), tie_sentence(r), advice);
    }
    const size_t n_left = ok ? significant(f->gaps_after) : 0;
    const std::string left = ok ? left_text(r, f->gaps_after) : std::string();
    return fmt::format(
        "**Gap explained in part by `{}`.** {}{}.{} What `{}` does not explain: {}. These cells need another "
        "cause (a second effect, a parameter to re-calibrate, or a measurement bias); treat the fitted "
        "strength as provisional until they are understood.{}{}{}",
        c.effect, head,
        !ok      ? std::string("")
        : n_left ? fmt::format(", but {} cell(s) stay significant", n_left)
                 : std::string(", but the table as a whole still departs"),
        limit_sentence(r, c.effect), c.effect, ok ? left : std::string("unknown (no fresh runs)"),
        null_refit_sentence(r), tie_sentence(r),
        r.second.outcome == "none"
            ? " No other candidate, fitted on top of it, explains them by the rule's margin."
        : r.second.outcome == "noise"
            ? fmt::format(" With the baseline's seeds the model with `{}` leaves no cell significant: "
                          "the cells its fresh seeds left may be seed-to-seed scatter.",
                          c.effect)
        : r.second.outcome == "unconfirmed"
            ? fmt::format(
                  " `{}`, fitted on top of it, explains part of them with seeds 1..R, but its fresh "
                  "runs do not beat `{}` alone by the model's seed luck ({:.1f}), so it is not named; "
                  "more replicates would decide.",
                  r.second.fresh.effect, c.effect, r.verdict.seed_luck)
            : "");
  }
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
        "observations {}.{}{} Re-calibrate the model with these values rather than add an effect.",
        departs, null_refit_sentence(r), best);
  }
  // Unexplained because the chosen effect's fresh runs did not reproduce its improvement (verdict.h,
  // fresh_confirms).
  if (r.verdict.fresh_rejected && !r.verdict.ranking.empty() && r.chosen() && !r.chosen()->after.empty()) {
    const Candidate& c = r.verdict.ranking.front();
    const FreshCheck& f = *r.chosen();
    // The model itself departs from no cell on the fresh seeds (procedure.h, gap_on_baseline_seeds_only):
    // the remedy is more seeds of the model before any measurement is repeated.
    const bool null_clean =
        gap_on_baseline_seeds_only(r.verdict.fresh_rejected, r.null_fresh, r.spec->rule.table_level);
    const std::string cause =
        null_clean ? fmt::format(
                         " The model itself, run on those fresh seeds, departs from no cell ({}): the gap "
                         "shows on the baseline's seeds only and may be their seed noise. More seeds of the "
                         "model (`replicates` in the diagnosis file, or `--replicates`) would tell, before "
                         "any measurement is repeated.",
                         table_words(r, r.null_fresh.gaps_after))
                   : std::string(
                         " The cause may lie outside the candidates, or the gap may be noise; repeating the "
                         "measurements at the cells above would tell.");
    return fmt::format(
        "**Gap not explained.** The model departs from the observations {}. The best "
        "candidate, `{}` ({}), passed the held-out rule at {} = {:.3g} (held-out χ² {:.1f} against the "
        "model's {:.1f}), but fresh runs at that strength do not reproduce it: χ² {:.1f} over the {} cells "
        "against {:.1f} for the model without it{}, not lower by {:.3g} (min_drop, or how far χ² moves "
        "between two seed sets of the model alone where that is more). Its fit followed the seed noise of "
        "its probe runs, not the data, so no effect is named.{}{}",
        departs, c.effect, effect_spec(c.effect).fingerprint, effect_spec(c.effect).strength, f.strength,
        c.loco, r.verdict.null_loco, chi2_of(f.gaps_after), n,
        r.null_fresh.after.empty() ? chi2_of(r.gaps) : chi2_of(r.null_fresh.gaps_after),
        r.null_fresh.after.empty() ? "" : " on the same fresh seeds",
        std::max(r.spec->rule.min_drop, r.verdict.seed_luck), cause, null_refit_sentence(r));
  }
  // Unexplained: either the best candidate helps but not by the rule's margin (a lead worth more data), or
  // none helps (the cause lies outside the candidates).
  // The shares are of the gap: the null's held-out χ² above its noise floor (verdict.h).
  if (!r.verdict.ranking.empty() && r.verdict.held_out_gap_shrink >= 0.5 * (1.0 - ratio)) {
    const Candidate& c = r.verdict.ranking.front();
    // A lead that passes the held-out rule is not named only because its own probes cannot show it in this
    // table (verdict.h, name_only_seen): the paragraph says so, not "short of the rule"; the section on what
    // the table cannot see follows with the measurement that would show it.
    if (passes_margin(c.loco, r.verdict, r.spec->rule) &&
        std::find(r.unseen.begin(), r.unseen.end(), c.effect) != r.unseen.end()) {
      // Its fresh runs against the control (shrink.cpp, try_unseen_lead), when they were made.
      std::string fresh;
      if (const FreshCheck* f = r.fresh_of(c.effect); f && !f->after.empty() && !r.null_fresh.after.empty()) {
        const Shift sh = fresh_shift(r.cells, r.null_fresh.after, f->after);
        const double before = chi2_of(r.null_fresh.gaps_after), after = chi2_of(f->gaps_after);
        fresh = fmt::format(
            " Its fresh runs at that strength ({} seeds at every condition) move {} at {} by {:.1f} σ at "
            "most against the model without it on the same seeds, and give χ² {:.1f} against {:.1f}: {}.",
            r.spec->replicates, r.cells[sh.cell].observable, r.cell_condition[sh.cell], sh.max_z, after,
            before,
            shows(sh, r.cells.size())
                ? "they show it but do not lower χ² by the margin (min_drop or the model's own seed luck)"
                : "they cannot show it either");
      }
      return fmt::format(
          "**Gap not explained (a lead: `{}`).** The model departs from the observations {}. The best "
          "candidate, `{}` ({}), passes the held-out rule (at {} = {:.3g}; held-out χ² {:.1f} against the "
          "model's {:.1f}, noise floor {:.1f}), but its own probe runs move no cell of this table by 3 σ "
          "even at the strongest strength probed, so a held-out score that good may be their seed noise "
          "and it is not named.{} The data point to it; a measurement where it would show (below) can "
          "confirm or exclude it.{}",
          c.effect, departs, c.effect, effect_spec(c.effect).fingerprint, effect_spec(c.effect).strength,
          c.fit.strength, c.loco, r.verdict.null_loco, r.verdict.floor, fresh, null_refit_sentence(r));
    }
    return fmt::format(
        "**Gap not explained (a lead: `{}`).** The model departs from the observations {}. The best "
        "candidate, `{}` ({}), removes {} in the held-out predictions (at {} "
        "= {:.3g}; held-out χ² {:.1f} against the model's {:.1f}, noise floor {:.1f}), short of the rule: "
        "{:.0f} % of the gap and a drop of {:g}. The data point to it but do not single it out. To decide, "
        "measure more conditions where its fingerprint is strongest, or repeat the measurements to shrink "
        "their error bars.{}",
        c.effect, departs, c.effect, effect_spec(c.effect).fingerprint,
        gap_removed(r.verdict.held_out_gap_shrink), effect_spec(c.effect).strength, c.fit.strength, c.loco,
        r.verdict.null_loco, r.verdict.floor, 100 * (1.0 - ratio), r.spec->rule.min_drop,
        null_refit_sentence(r));
  }
  std::string best = r.verdict.ranking.empty()
                         ? "none was fitted"
                         : fmt::format("the best, `{}`, removes only {:.0f} % of the gap held out",
                                       r.verdict.ranking.front().effect, 100 * r.verdict.held_out_gap_shrink);
  return fmt::format(
      "**Gap not explained.** The model departs from the observations {}, but none of the candidate effects "
      "explains it by the rule's margin ({}). The cause is likely outside the candidates (another mechanism, "
      "a measurement bias, or a model parameter to re-calibrate).{}",
      departs, best, null_refit_sentence(r));
}

}  // namespace

}  // namespace wetdem::diagnose
