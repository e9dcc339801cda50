// Step 4 of the diagnosis (diagnosis.md §4), the statistics: a candidate's strength fitted by weighted least
// squares through its emulator, profiled over the members of its family (refit settings x shapes), scored by
// leave-one-condition-out prediction; where to put the next run (refinement at the fit, extension past an
// edge of the probed range). Pure functions; the stage that runs the models is fit_stage.h.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/emulator.h"

namespace wetdem::diagnose {

struct StrengthFit {
  double strength = 0.0;      // best fit (10^u)
  double lo = 0.0, hi = 0.0;  // interval: χ² within `delta` of the minimum, on the probed range
  double chi2 = 0.0;          // at the best fit, over the cells fitted
  double delta = 1.0;         // the Δχ² of the interval: max(1, χ²_min / (n - 1)) (below)
  bool at_edge = false;       // the optimum sits at an end of the probed range (either)
  bool at_lo = false;         // ... below the weakest strength probed (between it and the baseline anchor)
  bool at_hi = false;         // ... at the strongest strength probed
  bool open_lo = false;       // the interval runs into the baseline anchor: "strength <= hi"
  bool open_hi = false;       // the interval runs into the strongest probe: "strength >= lo"
  // The Δχ² interval alone, before widen_by_condition_jackknife (equal to lo, hi until then).
  double chi2_lo = 0.0, chi2_hi = 0.0;
  // The leave-one-condition-out jackknife's standard error of log10(strength) (0: not computed).
  double jackknife_se_log10 = 0.0;
  // The spread of log10(strength) over emulators redrawn within their runs' SE (0: not computed).
  double emulator_se_log10 = 0.0;
  // The other members of the family (shapes, refit settings) whose χ² comes within `delta` of the minimum
  // somewhere: the interval spans their strengths there too (widen_by_profile; 0: none, or not computed).
  size_t profile_members = 0;
  // The interval at twice its width (set_two_se_interval): about 95 % where the reported one is about 68 %
  // (one standard error). 0, 0 until set.
  double lo2 = 0.0, hi2 = 0.0;
  bool open_lo2 = false, open_hi2 = false;
};

// Weighted least squares of the strength against the cells `idx` (all when empty): χ²(u) on a dense grid over
// [u_lo, u_hi], refined by golden-section search around the grid minimum. The interval is where χ² is within
// Δ of the minimum, with Δ = max(1, χ²_min/(n - 1)) for n cells: when the best fit leaves more scatter than
// the uncertainties allow (the emulator's interpolation error, seed noise of single-seed probes), the
// interval is widened by that excess (the scale factor of the Particle Data Group's averages) instead of
// claiming a precision the data do not carry.
StrengthFit fit_strength(const std::vector<Cell>& cells, const Emulator& em,
                         const std::vector<size_t>& idx = {});

// A family of models for one candidate: one emulator per member (a refit setting x a shape of the effect's
// second parameter). The fit is a discrete profile: at each member the strength is fitted as above; the
// member of least χ² is kept (the lowest index on a tie, so the calibrated setting and the middle shape win
// ties when they are listed first).
struct ProfileFit {
  size_t member = 0;
  StrengthFit fit;
};
ProfileFit fit_profile(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                       const std::vector<size_t>& idx = {});
// The interval of a family's strength with its second parameter profiled out. fit_profile's interval is that
// of the best member alone: the strength's interval *given* the best shape (and refit setting). The profile
// interval (the likelihood-ratio interval with a nuisance parameter) is every strength at which *some*
// member's χ² comes within the best fit's Δ of its minimum: on a few seconds of a drum a slow absorption rate
// with a large capacity drains the films about as fast as a fast rate with a small one, and the interval of
// the best rate alone then excludes the truth's capacity at the other rate. Widens f (fitted at member `best`
// of `ems`) to the union over the members; a member whose low region reaches an end of its own knots makes
// that side open, as fit_strength does for the best one. Returns how many other members reached (also in
// f.profile_members). The fit itself (strength, member) is unchanged.
size_t widen_by_profile(StrengthFit& f, const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                        size_t best, const std::vector<size_t>& idx = {});
// The null model with refit: the setting whose baseline has the least χ² over idx (lowest on a tie).
size_t fit_null_refit(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
                      const std::vector<size_t>& idx = {});

// Leave-one-condition-out: for every condition c, fit without c's cells and predict c's cells; the held-out
// z² of every cell. Throws std::invalid_argument with fewer than two conditions. loco_score is their sum.
// `fold_strengths`, when given, receives each fold's fitted strength (the best member's; for the jackknife
// below, without fitting the folds twice).
// A family of several members (shapes, refit settings) predicts c by the mixture of its members, each at
// its own fitted strength, weighted by exp(-χ²/2) on the fold's cells (a uniform prior over the members):
// the held-out log predictive density with the second parameter integrated out, not maximised. With one wet
// condition left in a fold a capacity and a rate are not both determined (a slow rate with a large capacity
// drains the films as a fast one with a small capacity does, at that liquid content), and the single best
// member picks one branch by a hair and predicts the other condition far off: the micro absorption twin
// at 0.05, 2 1/s scored 67 held out against evaporation's 25 (at its physical limit) and was called
// `evaporation + absorption`; the mixture scores 8.9 and it is `absorption`.
// A probe knot's se is s √(2 + 1/R), the null's s/√R, so z² alone is smaller for a candidate in every cell
// before it explains anything. With `null_se` (one per cell: the model without the effect), a cell scores
// z² + ln(v / v0) instead, v = σ² + se² of the held-out prediction and v0 = σ² + null_se²: the held-out log
// predictive density (-2 log, relative to the null's), whose differences are 2 log of likelihood ratios
// whatever the widths (VerdictRule::held_out).
std::vector<double> loco_cells(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                               std::vector<double>* fold_strengths = nullptr,
                               const std::vector<double>* null_se = nullptr);
double loco_score(const std::vector<Cell>& cells, const std::vector<Emulator>& ems);
double loco_score(const std::vector<Cell>& cells, const Emulator& em);
// The strengths fitted in the leave-one-condition-out folds (one per condition, in condition order).
std::vector<double> loco_strengths(const std::vector<Cell>& cells, const std::vector<Emulator>& ems);

// Widens a fit's interval by the jackknife over conditions. The Δχ² interval counts every cell as an
// independent measurement; the observables of one condition come from the same runs (one bed's avalanches
// move the AoR, its fluctuation and the surface speed together) and a probe's seed noise is common to all of
// a condition's cells, so that interval is too narrow (on synthetic cells with 90 % of the noise shared
// along the effect's fingerprint it covered the truth in 30 % of trials; DiagnoseStats.Jackknife...). The
// jackknife treats each condition as one unit: se² = (m - 1)/m Σ (u_(c) - ū)² over the m
// leave-one-condition-out fits u_(c) = log10 strength. The reported interval is the union of the Δχ² interval
// and u ± se; a side that passes an end of the probed range is open there.
void widen_by_condition_jackknife(StrengthFit& f, const std::vector<double>& loco_strengths, double u_lo,
                                  double u_hi);

// The reported interval at two standard errors: each side's distance from the fit in log10 doubled, bounded
// by the probed range [u_lo, u_hi] and open where it reaches it (an open side stays open). Every part of the
// reported interval is one standard error wide: the Δχ² interval (for χ² quadratic in u, Δχ² = 4Δ lies twice
// as far from the minimum as Δ), the jackknife's and the emulator's u ± se, and the profile's members within
// Δ; doubling the union doubles each part. The reported interval stays the 1-SE one (the matrix's coverage
// target); this one says how far a truth may still lie when the fit sits on a single-seed knot, whose noise
// the 1-SE interval knows only through the emulator's redraws (the strong-cohesion twins' truths at 1.04
// and 1.5 SE, docs/twin_matrix_flowing.md).
void set_two_se_interval(StrengthFit& f, double u_lo, double u_hi);

// Widens a fit's interval by the noise of the runs behind the emulator. The Δχ² interval counts the knots'
// SE in every cell's variance, but its curvature takes the emulator's slope between two knots as exact; with
// single-seed probes as noisy as the observations that slope is mostly noise, χ² is too sharply curved and
// the interval too narrow (DiagnoseStats.IntervalsStay...: 32 % coverage with knots four times noisier than
// the observations). The jackknife over conditions does not see this noise either: every fold uses the same
// knots. A parametric bootstrap does: `draws` emulators with every knot redrawn within its SE
// (Emulator::redrawn, a fixed seed, so the report is repeatable), each fitted like the original; se is the
// standard deviation of their log10 strengths, and the interval becomes the union with u ± se, open where it
// passes an end of the probed range (as the jackknife).
void widen_by_emulator_noise(StrengthFit& f, const std::vector<Cell>& cells, const Emulator& em,
                             int draws = 48, uint64_t seed = 20261125);

// The held-out score's own noise (VerdictRule::tie_noise): the leave-one-condition-out score of a family
// whose emulators are redrawn within their knots' SE (Emulator::redrawn), once per draw. anchors[d][r][k] is
// draw d's shift of refit setting r's baseline knot in cell k, in units of its SE (anchor_draws): every
// candidate gets the same shifts, so the draws of two candidates are paired over the baseline they share and
// the spread of their difference is that of their own probes. Each member's probes are redrawn from `seed`.
std::vector<double> loco_draws(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                               const std::vector<size_t>& refit_of,
                               const std::vector<std::vector<std::vector<double>>>& anchors, uint64_t seed,
                               const std::vector<double>* null_se = nullptr);
// Standard normal shifts [draw][refit setting][cell] for loco_draws, from a fixed seed (repeatable reports).
std::vector<std::vector<std::vector<double>>> anchor_draws(size_t draws, size_t settings, size_t cells,
                                                           uint64_t seed);

// The null model: with one baseline nothing is fitted and the score is its plain χ²; with refit settings the
// setting is re-fitted in every fold.
std::vector<double> loco_null_cells(const std::vector<Cell>& cells,
                                    const std::vector<std::vector<Prediction>>& baselines);
double loco_null(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines);
double loco_null(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline);

// Refinement: the emulator interpolates between probes a factor 3-10 apart, and a response that bends
// between them misplaces the fitted strength (measured on the micro twins: an absorption capacity fitted at
// twice its true value). The fitted strength (3 significant digits) when no knot lies within 2 % of it in log
// strength, else 0 (refined).
double next_knot(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline, const Response& r);

// Extension past an edge (diagnosis.md §4: "an effect fitted at the edge of its probes extends the probes,
// within the physical range"): when the interval of the fit runs into the strongest probe, the next strength
// up (a step of the probes' largest ratio, at least 3x) capped at phys_hi; when the best fit lies below the
// weakest probe, the next strength down, floored at phys_lo. 0 when neither applies or the physical range is
// exhausted (then `*at_limit` says which end: -1 low, +1 high).
double next_edge_knot(const StrengthFit& f, const Response& r, double phys_lo, double phys_hi,
                      int* at_limit = nullptr);
// A member probed at one strength only (a shape added at the strength fitted at another shape: fit_stage
// steps 2 and 4) has no knot on either side of its fit, so its interval is a point at the edge: interpolated
// from its one knot down to the baseline anchor, it bounds nothing the runs have measured (micro
// u-absorption-fast: 0.031 at 300 1/s, "0.0305 and above", the truth 0.03 outside). Its bracket: one step
// `step` down and one up (the listed probes' step, probe_step), each within [phys_lo, phys_hi] and dropped
// where it would be within a quarter of the knot (at a physical limit); empty for a member with two knots or
// more.
std::vector<double> one_knot_bracket(const Response& r, double step, double phys_lo, double phys_hi);

// The step by which a probed range is extended past its end: the strengths' largest ratio, at least 3x
// (next_edge_knot; the reach past the file's probes, power.h).
double probe_step(const std::vector<double>& strengths);

// The profile (fit_profile) compares the members at their own best strengths. A member probed at one strength
// only (a shape added at the strength fitted at the default shape) has its best beyond its knots when its
// shape needs another strength to show the same pattern (a slow rate needs a larger capacity), and compared
// at that edge it loses whatever its optimum. The member to extend next: of the members other than `best`
// whose own fit runs into an edge of their knots (next_edge_knot within [phys_lo, phys_hi]), the one of least
// χ², with the strength to probe; `member` is npos when none. `responses[i]` is the response behind `ems[i]`.
struct MemberEdge {
  static constexpr size_t npos = static_cast<size_t>(-1);
  size_t member = npos;
  double strength = 0.0;
  double chi2 = 0.0;  // the member's own fit at its edge: a bound on its best
};
MemberEdge next_member_edge(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                            const std::vector<const Response*>& responses, size_t best, double phys_lo,
                            double phys_hi);

// Refinement of the second parameter. The shapes are a decade apart (absorption's rate 0.3, 3, 30 1/s), and
// the response bends between them: a pore sink filling at 10 1/s drains about half the films in the micro
// drum's window, one at 3 1/s a third whatever its capacity, one at 30 1/s all of them up to its capacity, so
// a truth at 10 1/s fits neither neighbour (measured: the micro absorption-strong twin, 0.08 at 10 1/s,
// fitted at 0.2 at 3 1/s with f_wet still 8 sigma off and evaporation added on top to make up the rest). The
// strengths are refined where the fit lands (next_knot); the shapes are refined the same way, by bisection in
// log shape: when the best member does not explain the table (its χ², or its held-out χ² over the conditions
// (loco_score), above `unexplained_above`), the geometric middles between the best member's shape and each of
// its neighbours in the sorted list of shapes, rounded to 3 digits. Both sides, not the side of the better
// neighbour: the profile over log rate is lopsided (micro, truth 2 1/s with a capacity that does not bind:
// χ² 311 at 0.3 1/s, 10.9 at 3, 219 at 30; the better neighbour and a parabola through the three both point
// above 3, the truth lies below). The held-out χ² as well: there the best listed rate fitted the table at
// χ² 10.9, within its 1 % point 20.1, by a capacity that binds at 10 % only, and predicted each left-out
// content at 65.8, so evaporation (25.3 both ways, at its physical limit) was named instead. None when the
// member explains the table both ways, a neighbour is within `min_ratio` or its middle is listed already.
// `shape_of[i]` is member i's shape value (NaN: a family without shapes, never refined).
std::vector<double> next_shapes_between(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                                        const std::vector<double>& shape_of, size_t best,
                                        double unexplained_above, double min_ratio = 2.0);

}  // namespace wetdem::diagnose
