// What the table can see (diagnosis.md §4, stage 8, after the others): for every candidate, the largest shift
// any of its probe runs makes in any cell, in units of that cell's noise. A candidate that moves no cell by
// kVisibleZ even at the strongest strength of its catalogue is one this table cannot show: a `no_gap` does
// not exclude it, and an `unexplained` does not rule it out. The report says so, with the cell where it comes
// closest, so the engineer knows which effects the verdict is silent on.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/table.h"
#include "diagnose/verdict.h"

namespace wetdem::diagnose {

class Procedure;

// One cell shifted by kVisibleZ is what a lab would call a significant difference; the issue's "just
// detectable" strength is the one that reaches it at one condition.
constexpr double kVisibleZ = 3.0;

// The screen threshold of the probe seeds' runs beyond the table (run_reach: P = probe_seeds each side) when
// the claim is made over R seeds each: kVisibleZ sqrt(P / R). A shift that reaches kVisibleZ over R seeds
// each shows over P seeds at about that much where the seeds' spread dominates the noise (the standard error
// of P runs' mean is sqrt(R / P) times the R seeds'), so a pair screened at kVisibleZ itself misses most of
// the shifts the R seeds would confirm (70 % of those at 3.5 sigma when R = 2, P = 1:
// tests/test_diagnose_power.cpp). Measured on the flowing drum (29 Nov 2026): lubrication at 0.1 Pa s slows
// the surface at 90 rpm, 10 % by 4.4 sigma over four seeds each, while the one pair of the diagnosis (seed 1)
// showed 2.4 sigma. P >= R: kVisibleZ (nothing left to confirm with).
double reach_screen_z(size_t replicates, size_t probe_seeds = 1);

// Whether run_reach's largest shift of a candidate beyond the table, run on `seeds` seeds each side (0:
// unconfirmable), is run again on all `base_seeds`: it reaches the screen (reach_screen_z), or the runs
// already differ by kVisibleZ of their own error and only the measurement's noise hides it (repeats > 0,
// repeats_for), so the report may ask a laboratory to repeat that measurement. Pure (tests).
bool confirms_beyond(double z, size_t repeats, size_t seeds, size_t base_seeds, double screen);

// A shift can also be visible through the whole table without any one cell at kVisibleZ (many cells moved by
// 1-2 sigma in the direction of a gap): its χ² over the n cells in excess of what the probe runs' own noise
// gives, sum(z²) - sum(se²/(σ² + se²)), at least the upper 1 % point of a χ²_n less its mean n
// (chi2_upper_point, where.h). For the flowing table's 48 cells that is 25.7; for 3 cells, 8.3.
double visible_chi2_excess(size_t cells);

// A probe's shift over the baseline in units of each cell's noise, z_k = (probe - baseline) / sqrt(σ² +
// se²): its largest |z| and cell, and its χ² over the cells in excess of the probe runs' own noise. The
// probe's SE already counts the run-to-run spread against the baseline (Procedure::probe).
struct Shift {
  double max_z = 0.0;
  size_t cell = 0;
  double chi2_excess = 0.0;
  size_t cells = 0;  // with finite values
};
Shift shift_of(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Prediction>& probe);

// Whether a shift shows: some cell at kVisibleZ, or the table's χ² excess at visible_chi2_excess.
bool shows(const Shift& s, size_t cells);

// The same shift with R runs on each side: a fitted candidate's fresh runs (R seeds at its fitted strength,
// shrink.h) against the control's (the model without an effect, the same seeds), z_k = (fresh - control) /
// sqrt(σ² + se_f² + se_c²), the excess over both sides' own noise. One probe run against the baseline carries
// one run's window error, and a sink's is large (the bed dries within the window: evaporation-strong's probe
// at 1/τ = 1 had ±5.6 on an agglomerate size of 2.6); its R fresh runs against the control's are the
// strongest evidence the diagnosis has of what the candidate does to the table.
Shift fresh_shift(const std::vector<Cell>& cells, const std::vector<Prediction>& control,
                  const std::vector<Prediction>& fresh);

// An unseen candidate that alone passes the held-out rule (shrink.cpp, try_unseen_lead), judged on its fresh
// runs at the fitted strength against the control on the same seeds over n cells: named only when they show
// it (shows(sh, n): what its probes could not) and confirm the fit (fresh_confirms: χ² below the control's by
// min_drop or the model's own seed luck, where that is larger). Either alone is not enough: a shift that does
// not lower χ² moves the model away from the data, and a drop the table cannot tell from noise is what the
// probes' held-out score may already have followed.
bool names_unseen_lead(const Shift& sh, size_t n, double chi2_control, double chi2_fresh,
                       const VerdictRule& rule, double luck);

// The fresh shift of `effect` (its first fresh check in p.fresh) against p.null_fresh, when both ran and
// share the refit setting; false otherwise.
bool fresh_shift_of(const Procedure& p, const std::string& effect, Shift* out, double* strength);

// A weaker strength run beyond the table where the strongest showed (Reach::beyond_weaker): its shift there.
struct WeakerRun {
  double strength = 0.0;
  double z = 0.0;
};

struct Reach {
  std::string effect;
  double strongest = 0.0;    // the strongest strength with probe runs at every condition (0: none could run)
  double max_z = 0.0;        // the largest |probe - baseline| / sqrt(sigma² + se²) over cells and probes
  double at = 0.0;           // the strength it came from
  size_t cell = 0;           // and its cell
  double chi2_excess = 0.0;  // the largest table χ² excess over the probes (Shift)
  double chi2_at = 0.0;      // the strength it came from
  // The probes' shift shows (max_z >= kVisibleZ, or chi2_excess >= visible_chi2_excess); visible: that, or
  // the fresh runs' shift does (seen_on_fresh).
  bool by_probes = false;
  bool visible = false;
  // Not visible: the strongest probe and the baseline (seed 1 each) at conditions beyond the table
  // (propose_conditions around the cell where it comes closest), and where it would move most.
  std::vector<std::string> beyond_tried;  // the conditions that ran
  std::string beyond_condition, beyond_observable;
  double beyond_z =
      0.0;  // |probe - baseline| / sqrt(sigma² + se_probe² + se_baseline²), sigma the table's median
  size_t beyond_seeds = 1;  // runs each side behind beyond_z: the baseline's seeds where one pair reached 3 σ
  // How often a laboratory would repeat that measurement for the shift to reach kVisibleZ (repeats_for,
  // next_experiment.h; > 1 only where beyond_z is under it): 0 when no number of repeats would, or when the
  // baseline's seeds did not all run there (a shift seen on one pair is not a claim).
  size_t beyond_repeats = 0;
  double beyond_sigma = 0.0;  // one measurement's noise there, as assumed (sigma_at, next_experiment.h)
  // Where the strongest shows there by kVisibleZ on the baseline's seeds, weaker strengths run there too, on
  // the same seeds, up to kWeakerSteps of them (next_weaker_strength), each with its shift of the same
  // observable: a shift is linear in a weak strength only roughly. In the order run; empty when none ran.
  std::vector<WeakerRun> beyond_weaker;
  // The fresh runs at the fitted strength against the control (fresh_shift), where the shrink made them.
  bool fresh = false;
  double fresh_at = 0.0, fresh_max_z = 0.0, fresh_chi2_excess = 0.0;
  size_t fresh_cell = 0;
  bool seen_on_fresh = false;  // shows(fresh shift), whatever the probes showed
  // Past the file's strongest probe (extend_reach): the strongest strength that had run before (0: not
  // extended), the strength from which the probes show it (0: they never do), and why the steps stopped
  // while it did not show ("physical limit", "max_cost", "failed", "cannot run", "reach_steps").
  double extended_from = 0.0;
  double visible_from = 0.0;
  std::string extension_stop;
};

// How many weaker strengths run_beyond tries where the strongest shows beyond the table.
constexpr int kWeakerSteps = 2;

// The weakest strength that shows at that condition, as far as the runs there tell (the strongest, shifting
// by z, and the weaker runs): `from`, the weakest strength whose shift reaches kVisibleZ, and `below`, the
// strongest one under it whose shift fell short (0: none did). Pure (tests).
struct WeakerBracket {
  double from = 0.0, from_z = 0.0;
  double below = 0.0, below_z = 0.0;
};
WeakerBracket weaker_bracket(double strongest, double z, const std::vector<WeakerRun>& runs);

// The next weaker strength to run there: while none has fallen short, the one at which the weakest that
// shows would shift by kVisibleZ were the shift proportional to the strength (from × kVisibleZ / from_z);
// once one has, the geometric middle of the bracket. To 3 digits; 0 when that is within 10 % of a strength
// already run, or nothing shows (z under kVisibleZ). Pure (tests).
double next_weaker_strength(double strongest, double z, const std::vector<WeakerRun>& runs);

// The next strength past `strongest` for a candidate the table does not show (extend_reach): one step of the
// probes' largest ratio (at least 3x, as the fit extends its range: fit.h, next_edge_knot), to 3 digits,
// capped at `hi`; 0 when what is left below `hi` is less than a quarter more (nothing worth a run).
double next_reach_strength(double strongest, const std::vector<double>& probes, double hi);

// Before the verdict (stage 5): the fitted candidates whose runs so far (every strength the fit ran, its
// extended range included) move no cell by kVisibleZ and the table's χ² by less than visible_chi2_excess go
// into p.unseen, with a note. Such a candidate cannot be told from the runs' own noise, so a fit of it may
// follow that noise (a null twin with other PSD tails was "explained in part" by hysteresis at 1.8 σ): the
// verdict never names it first on its held-out score, and the second round never names it (decide_seen).
void mark_unseen(Procedure& p);

// Stage 5's verdict: decide() over every fitted candidate, then name_only_seen (verdict.h) with p.unseen and
// the unseen candidates fresh runs have already dropped (p.unseen_rejected): an unseen candidate that scores
// best or ties is reported as tied, and its fresh runs decide it (shrink.cpp). Its notes are added once.
Verdict decide_seen(Procedure& p);

// Every candidate's reach over the probe runs already in the store (the screen's, the fit's, the second
// round's at refit setting 0), in the order of p.effects.
std::vector<Reach> table_reach(const Procedure& p);

// Stage 8: table_reach, after running the strongest catalogue probe (one seed, every condition) of each
// candidate that no run so far shows: the screen runs the middle probe only, and "cannot see X up to the
// middle" says little. Such runs are shared by every diagnosis of the model in the store. A probe that the
// cost guard refuses or that fails is noted, and the reach stays at the strongest one that ran. Then, for
// each candidate still not visible, up to `reach_conditions` conditions beyond the table (the next-experiment
// stage's proposals around its closest cell: one step past the largest measured value of each condition key,
// the midpoints, another drum speed, a longer run) with its strongest probe and the baseline, seed 1 each
// (common random numbers): the measurement that could show it. Fills p.reach.
// Between the two, extend_reach: a candidate that does not show even at the file's strongest probe steps on
// (next_reach_strength, one run per condition, up to `reach_steps` steps), to the realisable end of its
// physical range or the strongest max_cost allows, until it shows. The report then says from which strength
// the table would show it, or that it stays unseen over the whole range that can be run.
void run_reach(Procedure& p);

}  // namespace wetdem::diagnose
