// Step 5 of the diagnosis (diagnosis.md §4): the verdict, from the held-out scores of the fitted candidates
// and the null model, and after the fresh-seed check (shrink.h) whether the chosen effect explains the whole
// gap or part of it. Pure statistics.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/emulator.h"
#include "diagnose/fit.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

// The candidates' held-out score (VerdictRule::held_out).
enum class HeldOut { kChi2, kLogDensity };

// The verdict rule (docs/diagnosis.md, "Verdict"):
//  no_gap      no cell significant at FDR q (Benjamini-Hochberg), and χ² over the table within χ²_n's
//              (1 - table_level) point (table_fit, where.h: a gap spread over many cells);
//  refit       (with refit only) else, when the null at its re-fitted setting leaves no gap by the same
//              two tests: re-fitting closes the gap, no effect is chosen;
//  effect      else, the candidate with the lowest held-out (LOCO) score when it beats the null by a clear
//              margin (passes_margin: it removes `ratio` of the null's held-out χ² above the noise floor, and
//              LOCO_null - LOCO_best >= min_drop), and (after the fresh-seed runs at its fitted strength) no
//              gap is left (no cell significant, χ² over the table within its point);
//  partial     as effect, but a gap is left after the fresh-seed runs: the effect explains part of it, the
//              report names the cells it leaves (or the table's χ² when no cell alone is significant);
//  unexplained otherwise (the ranking is still reported).
// Runner-up not clearly worse ("tied"): it also passes the effect margin against the null, and its held-out
// χ² exceeds the best's by less than tie_delta x max(1, LOCO_best / n) over n cells. With Gaussian errors a
// held-out χ² is -2 log of the held-out likelihood, so the difference is 2 log of the likelihood ratio of the
// two models on data neither was fitted to: tie_delta = 4 asks for a ratio of e² ≈ 7 ("substantial" on
// Jeffreys' scale); the factor max(1, χ²/n) widens it when even the best model leaves more scatter than the
// error bars allow (the scale factor of the strength intervals, fit.h). Both are then reported, with the
// measurement that would separate them (next_experiment.h).
struct VerdictRule {
  double q = 0.05;
  double table_level = 0.01;  // the whole table's test (table_fit); 0: off
  // The candidates' held-out score (loco_cells, fit.h; docs/diagnosis.md, "Known limit"): kChi2, Σ z² with
  // each prediction's own se (the default; it rewards a wide prediction); kLogDensity, Σ [z² + ln(v/v_null)],
  // the held-out log predictive density. Opt-in: with the probe knots' conservative se it names almost
  // nothing on the flowing twins, and the matrix must be re-run with an honest knot se first.
  HeldOut held_out = HeldOut::kChi2;
  double ratio = 0.5;
  double min_drop = 4.0;
  double tie_delta = 4.0;
  // The held-out scores' own noise: a runner-up is also a near tie (near_tie: it gets fresh runs beside the
  // chosen effect, and fresh_tie decides) while its held-out χ² exceeds the best's by less than tie_noise
  // standard deviations of that difference over tie_draws paired redraws of the two candidates' emulators
  // within their knots' SE (held_out_noise). Both scores are built on probe runs of a few seeds, whose seed
  // noise tie_delta does not measure: on the fast flowing table absorption scored 34.3 held out against
  // evaporation's 23.9, past twice tie_delta, and was never run fresh. The redrawn knots carry their noise
  // twice (the runs' and the redraw's), so the bootstrap overstates the difference's spread: by 1.5x on
  // synthetic cells with probes twice as noisy as the data
  // (DiagnoseVerdict.TheHeldOutTieCountsTheProbesNoise). 1.5 of its standard deviations are then ~2.3 of the
  // difference's own: a runner-up as good as the best misses its fresh runs by its probes' luck in ~2 % of
  // cases (twice tie_delta alone: 25 % there). The noise widens only who is run fresh, never the tie itself:
  // a runner-up whose fresh runs are clearly worse is dropped however noisy its probes. 0: off (twice
  // tie_delta alone).
  double tie_noise = 1.5;
  int tie_draws = 32;
};

// A candidate's family: one emulator per member (refit setting x shape), with the member's indices.
struct Family {
  std::string effect;
  double screen = 0.0;
  std::vector<Emulator> ems;
  std::vector<size_t> refit_of, shape_of;  // per member
};

struct Candidate {
  std::string effect;
  double screen = 0.0;
  double loco = 0.0;
  std::vector<double> loco_cells;  // held-out z² per cell
  // The held-out χ² over emulators redrawn within their knots' SE (loco_draws, fit.h), paired across
  // candidates by draw; empty where not computed (a candidate that fails the effect margin cannot tie).
  std::vector<double> loco_draws;
  StrengthFit fit;  // on all cells, at the member fitted
  size_t member = 0, refit = 0, shape = 0;
};

// The noise floor of the held-out χ²: what a model that explained the whole gap would still score, from the
// cells the baseline does not call significant (their mean z² times the cells with a finite z). The table's
// σ need not be exact (a twin's is conservative: a right model scores ~0.5 per cell on the flowing drum), and
// with 48 cells and a one-cell gap, halving the whole χ² is impossible even for the truth. At most 1 per
// cell, χ²'s expectation when the σ are right: quiet cells that score more carry the gap themselves (a gap
// spread over the table, table_fit), and a floor at their own χ² would ask nothing of an effect. 0 when every
// cell is significant. null_cells: the null's held-out z² per cell; gaps: the baseline's where().
double noise_floor(const std::vector<double>& null_cells, const std::vector<CellGap>& gaps);

struct Verdict {
  std::string kind;                // "no_gap", "effect", "partial", "refit", "unexplained"
  std::string effect;              // the chosen effect for "effect" and "partial"
  std::vector<std::string> tied;   // candidates not clearly worse than the chosen one
  std::vector<Candidate> ranking;  // by LOCO score, best first
  double null_loco = 0.0;
  std::vector<double> null_loco_cells;
  size_t null_refit = 0;         // the null's refit setting fitted on all cells (0 without refit)
  double held_out_shrink = 0.0;  // 1 - LOCO_best / LOCO_null (the left-out predictions)
  double floor = 0.0;            // noise_floor() of the null's held-out χ²
  // (LOCO_null - LOCO_best) / (LOCO_null - floor): of the gap, not the noise. Above 1 when the best's
  // held-out χ² falls below the floor, an estimate from the baseline's cells that knows nothing of the
  // emulator's wider predictions (docs/diagnosis.md, "The noise floor"); the report then says "all the gap".
  double held_out_gap_shrink = 0.0;
  // The chosen effect passed the rule, but its fresh-seed runs did not lower χ² over the cells by min_drop
  // (fresh_confirms): the verdict became "unexplained" and says so.
  bool fresh_rejected = false;
  // How far χ² moves with the seeds alone: the mean |χ²(A) - χ²(B)| over every split of the model's runs at
  // seeds 1..R and the control's R+1..2R into two seed sets of R (split_luck, shrink.h). The least margin of
  // the fresh-run comparisons (fresh_confirms, unseen_on_fresh, fresh_tie); 0 without the control.
  double seed_luck = 0.0;
  std::vector<std::string> tied_on_fresh;  // the tied candidates that were near ties held out (near_tie) and
                                           // tie on fresh runs (fresh_tie)
  // The fresh comparisons that the seed luck decided: the candidates kept tied, and the chosen effect left
  // unconfirmed, whose fresh χ² differ by more than the tie margin (or min_drop) but not by more than the
  // luck. More replicates would lower the luck and could decide them; the paragraph says so (luck_sentence).
  std::vector<std::string> held_by_luck;
  // The candidate first held out whose fresh runs did not confirm it, passed over for one the held-out score
  // did not separate from it and whose fresh runs did (shrink.cpp, promote_confirmed); effect empty if none.
  struct PassedOver {
    std::string effect;
    double strength = 0.0, loco = 0.0, fresh_chi2 = 0.0, control_chi2 = 0.0;
  } passed_over;
  // A tie whose order the weight of the evidence set (tie_order_evidence, fresh_ties.cpp): the effect named
  // first before (the held-out leader, or the candidate promote_confirmed put first), now named second, and
  // the two differences in units of their noise (the held-out one for it, the fresh one against it); effect
  // empty if the order stood.
  struct ReorderedTie {
    std::string effect;
    double held_out_z = 0.0, fresh_z = 0.0;
  } reordered;
};

// The effect margin against the null: LOCO <= floor + ratio x (LOCO_null - floor), i.e. the candidate removes
// at least `ratio` of the null's held-out χ² above the noise floor, and LOCO_null - LOCO >= min_drop. With
// floor 0 this is the rule LOCO <= ratio x LOCO_null.
bool passes_margin(double loco, const Verdict& v, const VerdictRule& rule);

// Everything but the fresh-seed check: kind is "no_gap", "refit", "effect" (provisional) or "unexplained".
Verdict decide(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
               const std::vector<Family>& families, const VerdictRule& rule = {});
// One refit setting and one shape per candidate (tests, and the diagnosis without refit).
Verdict decide(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Response>& responses, const std::vector<double>& screens,
               const VerdictRule& rule = {});

// The standard deviation of b.loco - a.loco over their paired redraws (loco_draws); 0 when either has none.
double held_out_noise(const Candidate& a, const Candidate& b);
// The tie margin against a held out: tie_delta x max(1, LOCO_a / n) over n cells.
double tie_margin(const Candidate& a, const VerdictRule& rule);
// Whether `b` is clearly worse than `a` on the held-out cells: b.loco - a.loco >= tie_margin (the tie rule).
bool clearly_worse(const Candidate& a, const Candidate& b, const VerdictRule& rule);

// The near-tie margin: max(2 x tie_margin, tie_noise x held_out_noise).
double near_tie_margin(const Candidate& a, const Candidate& b, const VerdictRule& rule);
// A runner-up within the near-tie margin of the best on the held-out cells. Two held-out scores built on
// probe runs of one or two seeds also differ by those runs' seed noise, so such a runner-up gets fresh runs
// (R seeds, no probe in them) beside the chosen effect's, and fresh_tie decides (shrink.cpp).
bool near_tie(const Candidate& a, const Candidate& b, const VerdictRule& rule);
// On fresh runs: b is tied with a unless its χ² over the n cells exceeds a's by tie_delta x max(1, χ²_a / n),
// or by `luck` where that is larger (the model's own seed luck, as in unseen_on_fresh: the fresh runs of two
// candidates are two seed sets, and on the flowing drum those alone move χ² by 9-100).
bool fresh_tie(double chi2_a, double chi2_b, size_t n, const VerdictRule& rule, double luck = 0.0);
// That margin: max(tie_delta x max(1, χ²_a / n), luck).
double fresh_tie_margin(double chi2_a, size_t n, const VerdictRule& rule, double luck = 0.0);
// The candidates tied held out that their fresh runs leave clearly worse than the one named first (its fresh
// χ² `first`): not fresh_tie with the model's own seed luck, the test a near tie and an unseen tie already
// meet. A held-out tie is two scores built on single-seed probes; the fresh runs carry no probe's noise.
// Found on the flowing absorption-0.03-at-30 twin at 4 seeds: `scale` tied held out (35.3 against 34.2) and
// was reported as explaining the data nearly as well, though its fresh runs gave χ² 220.6 against the first's
// 99.4 (luck 22.6), worse even than the model without any effect (211.7). `tied`: each tied candidate's
// fresh χ² (NaN: not run or failed; kept). Returns the indices into `tied` to drop. Pure (tests).
std::vector<size_t> ties_clearly_worse_on_fresh(double first, const std::vector<double>& tied, size_t n,
                                                const VerdictRule& rule, double luck);

// Which of two tied candidates to name first. Neither is clearly worse, yet each comparison leans one way:
// held out by b.loco - a.loco over the standard deviation of that difference (held_out_noise), and on the
// fresh runs by fresh_a - fresh_b over the standard deviation of a fresh χ² difference, the model's own seed
// luck (a mean |Δχ²|) times √(π/2), the ratio of a normal's standard deviation to its mean absolute
// deviation. The two are independent evidence (probes and emulators against R fresh seeds), so their sum
// weighs both: returned as fresh_z - held_z, with both z set (positive: the evidence favours b, named first
// on it). On the flowing spread-weak twin evaporation led held out by 5.9 against a noise of 21.5 (0.28 σ)
// and spread on fresh runs by 19.5 against 21.4 × 1.25 (0.73 σ): spread, the truth, is named first. NaN
// (the held-out order stands) without both noises. Pure (tests).
double tie_order_evidence(double loco_a, double loco_b, double held_noise, double fresh_a, double fresh_b,
                          double luck, double* held_z = nullptr, double* fresh_z = nullptr);

// The fresh-seed check: an `effect` whose runs leave a gap (has_gap at table_level) becomes `partial`.
void settle_verdict(Verdict& v, const std::vector<CellGap>& after, const VerdictRule& rule);

// Makes `effect` the chosen one: it moves to the front of the ranking (the others keep their order), and the
// held-out shrinks follow it. Used by decide(), name_only_seen and the fresh-run swap (shrink.cpp). By value:
// callers pass a ranking entry's own name, which the rotation moves.
void choose(Verdict& v, std::string effect);

// Only what the table can see is named first (diagnosis.md, "Verdicts"; power.h, mark_unseen). `v` is
// decide()'s verdict over every fitted candidate; `unseen` are those whose probe runs the table cannot tell
// from noise, `rejected` those of them that fresh runs have already shown clearly worse (unseen_on_fresh).
// For an `effect`: the chosen one is the best-ranked candidate that passes the margin and is neither unseen
// nor rejected, moved to the front of the ranking (held_out_shrink follows it); when none passes, the verdict
// is `unexplained`. Tied: every other candidate that passes the margin, is not clearly worse than the chosen
// one and is not rejected. An unseen candidate whose held-out score is the best, or ties the chosen one's,
// is therefore tied, never dropped silently (evaporation-strong: evaporation 13.4 held out against
// absorption's 17.1, truth evaporation), and its fresh runs decide it (unseen_on_fresh). Returns a note per
// change it made; other kinds are left as they are.
std::vector<std::string> name_only_seen(Verdict& v, const std::vector<std::string>& unseen,
                                        const std::vector<std::string>& rejected, const VerdictRule& rule);

// An unseen candidate tied on its held-out score, judged on the fresh runs (seeds R+1..2R, no probe in them)
// at its fitted strength against the chosen one's over the n cells. The margin is the tie rule's (fresh_tie),
// or `luck` where that is larger: how far χ² moves between two seed sets of the same model
// (Verdict::seed_luck, the mean over the splits of its 2R runs). On the flowing drum one split alone measured
// 9-100 (null-2: 59.9 on seeds 1-2, 129.7 on the fresh seeds), far above the tie rule's 4-10, and a candidate
// the probes cannot show may not win or lose on less. kDrop when it is worse by the margin (its held-out
// score followed its probes' seed noise), kSwap when the chosen one is worse by the margin (named first),
// kKeep otherwise.
enum class FreshJudgement { kDrop, kKeep, kSwap };
FreshJudgement unseen_on_fresh(double chi2_chosen, double chi2_unseen, size_t n, const VerdictRule& rule,
                               double luck = 0.0);

// An unseen candidate tied held out whose own fresh runs show it against the control (power.h, fresh_shift):
// the table sees it after all, so it is ranked as any seen candidate is, by its held-out score, with the
// fresh runs (R seeds each, no probe's noise) as the check. kDrop when its fresh χ² is clearly worse than the
// chosen one's (unseen_on_fresh, the luck included); kSwap when clearly better there, or better held out;
// kKeep (tied, second) otherwise.
FreshJudgement seen_on_fresh(const Candidate& chosen, const Candidate& other, double chi2_chosen,
                             double chi2_other, size_t n, const VerdictRule& rule, double luck = 0.0);

// When another candidate is named first on fresh runs, a candidate tied with the former first stays tied
// with the new one unless it is clearly worse both held out (clearly_worse) and on fresh runs (fresh_tie,
// the luck included): either score alone keeping it close is the tie rule's "not clearly worse".
bool stays_tied(const Candidate& first, const Candidate& c, double chi2_first, double chi2_c, size_t n,
                const VerdictRule& rule, double luck = 0.0);

// Whether the fresh-seed runs at the fitted strength reproduce an improvement: χ² over the cells (fresh seeds
// R+1..2R) at least min_drop below that of the model without the effect on the same fresh seeds (the
// control: seeds differ in luck, and a comparison with the baseline's seeds 1..R credits an effect with it).
// A fit that followed the probes' seed noise (a strength at a probe edge that the held-out score liked) gives
// fresh runs no better than the control, or worse; naming it, even as `partial`, would be a confident answer
// the data do not support.
// The margin is min_drop, or `luck` where that is larger: the model's own seed luck (unseen_on_fresh), since
// an effect may not be credited with less than two seed sets of the same model differ by. On null-2 (PSD
// tails, no effect) cohesion's fresh runs gave 117.3 against the control's 129.7, lower by 12.4 > min_drop,
// with a luck of 69.8: not confirmed.
bool fresh_confirms(double chi2_before, double chi2_fresh, const VerdictRule& rule, double luck = 0.0);

// The chosen effect's fresh runs did not confirm it. The fresh χ² of every fresh check (index 0 the chosen
// one; NaN where the runs failed) and whether each may be named in its place (a candidate the table can see,
// which the held-out score did not separate from it: tied or a near tie): the index of the least χ² that
// fresh_confirms against the control's `chi2_before`, or npos. The fresh runs carry no probe's seed noise and
// no emulator, so among candidates the held-out score cannot order they are the better evidence
// (shrink.cpp, promote_confirmed).
inline constexpr size_t kNone = static_cast<size_t>(-1);
size_t confirmed_instead(double chi2_before, const std::vector<double>& fresh_chi2,
                         const std::vector<bool>& eligible, const VerdictRule& rule, double luck);

// The confirmation rounds (shrink.cpp): the fresh χ² of the check each re-fit started from, oldest first, and
// of the last one run (NaN where the runs failed). All were run on the same fresh seeds, but in a flowing
// drum any change of the model decorrelates the runs from the control's (the seeds fix the start, not the
// avalanches), so two strengths' fresh χ² differ by the seed luck as well. The round whose check is the least
// and beats the last by more than `margin` (min_drop or the luck, the larger); else npos: the last re-fit is
// kept. A round that ran beats a last one that failed.
size_t best_fresh_round(const std::vector<double>& round_chi2, double last_chi2, double margin);

// What one fresh check decides: its χ² (NaN: the runs failed), whether it confirms the effect against the
// control on the same seeds (fresh_confirms, with the luck), and whether cells stay significant after it.
struct FreshOutcome {
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  bool confirms = false;
  bool gap = false;
};

// Within the margin, where best_fresh_round keeps the re-fit, the point still goes to the strength whose
// fresh runs match the table better, when that changes nothing the verdict would say: the round with the
// least χ² below the last's among those with the last's outcome (the same confirmation, cells left or none),
// or kNone. Why: in seven re-fits of the truth's own effect on flowing twins, the lower fresh χ² of a re-fit
// and of the strength it left named the one nearer the truth every time, while the margin alone kept the
// farther one in three (docs/validation.md, "The point of a re-fit", 7 Dec 2026): cohesion 0.012 J/m² was
// fitted at 0.0123 (χ² 86.4) and re-fitted to 0.0204 (105.4, luck 47.8). The outcome must match because the
// better of two draws is no confirmation: the verdict never rests on the pick (null-2: 78.3 at 0.00105
// against the re-fit's 109.7, `unexplained` on either).
size_t closer_fresh_round(const std::vector<FreshOutcome>& rounds, const FreshOutcome& last);

// After best_fresh_round: the other strengths the rounds ran for the kept effect, with their fresh χ² (NaN:
// failed), that the fresh runs cannot tell from the kept one (χ² not above kept_chi2 + margin). The interval
// [lo, hi] is widened to reach each; returns those that widened it, in the order given.
std::vector<double> widen_to_fresh_ties(double& lo, double& hi, double kept_chi2,
                                        const std::vector<std::pair<double, double>>& others, double margin);

// Lists `effect` in v.held_by_luck once: the first round and the second may both find its comparison decided
// by the luck (a tie kept, then the same candidate unconfirmed on top).
void hold_by_luck(Verdict& v, const std::string& effect);

}  // namespace wetdem::diagnose
