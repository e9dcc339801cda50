// Stage 8b of the diagnosis (diagnosis.md §4, after the reach): what a `no_gap` table rules out. "The model
// agrees with the observations" says no effect is needed; it does not say how strong an effect could be and
// still hide in the noise, which is what an engineer deciding whether to model it asks. Every candidate's
// runs at every condition of the table (its probes and the stage's own runs) are set against the
// observations: a strength whose runs the observations reject against the model without the effect by a χ²
// difference past kRuleOutDelta is ruled out; the weakest strength from which every stronger run is ruled
// out, and the strongest run under it that is not, bracket the limit. The earlier stages' runs rarely bracket
// it (the screen ran one probe), so run_limits adds `limit_steps` rounds of one strength more per candidate.
// A candidate with a second parameter (a sink's rate) has a limit at each shape run and one with it free.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/power.h"

namespace wetdem::diagnose {

class Procedure;

// A run is ruled out when its Δ (limit_run) reaches kVisibleZ² (a 3 σ shift of one cell the observations did
// not show), times the table's own excess scatter (limit_scale), and kRuleOutNoiseZ times its own scatter
// without a shift (noise_sd): with single-seed probes a run that shifts nothing passes 9 alone in ~10 % of
// tables of 48 cells (DiagnoseLimits), ~3 % past both; a 3 σ shift is ruled out ~25 % of the time, 6 σ ~97 %.
constexpr double kRuleOutDelta = kVisibleZ * kVisibleZ;
constexpr double kRuleOutNoiseZ = 2.0;

// One run's comparison: the χ² of the observations against the run's predictions less that against the
// model's, both with one variance per cell, v = σ² + se_run² (the run's knot SE, Procedure::probe), less the
// part the run's own seed noise adds: Δ = Σ_k [(y - run)² - (y - model)² - share × se_run²] / v over the
// cells where the run differs from the model. A probe is the model's R-seed mean plus the difference of P
// probe runs from the model's runs on the same seeds; with seed noise s per run, (y - run)² exceeds
// (y - model)² by the shift² plus s² (2/P - 2/R) on average, and the knot SE is s √(2/P + 1/R) (knot_se),
// so share = (2/P - 2/R) / (2/P + 1/R) (limit_noise_share; 0.4 for P = 1, R = 2, 0 for P = R). Without it
// a run that shifts nothing scores ~+14 over a 48-cell table. The mean, for observations the model gives, is
// then the run's shift Σ z² as the reach measures it (shift_of). Positive: the observations favour the model
// without the effect. noise_sd: Δ's standard deviation for a run that shifts nothing, from the seeds' noise
// (~5.6 over 48 cells at P = 1, R = 2, σ = s). Pure (tests).
struct LimitRun {
  double strength = 0.0;
  double delta = 0.0;
  double noise_sd = 0.0;
};
double limit_noise_share(size_t probe_seeds, size_t replicates);
LimitRun limit_run(const std::vector<Cell>& cells, const std::vector<Prediction>& model,
                   const std::vector<Prediction>& run, size_t probe_seeds, size_t replicates);

// The table's scatter about the model, as the fit's intervals take it: max(1, χ²/(n - 1)) over the n
// finite cells (the Particle Data Group's scale factor; fit.h, fit_strength).
double limit_scale(const std::vector<Cell>& cells, const std::vector<Prediction>& model);

struct Limit {
  std::string effect;
  // The second parameter's value its runs had (effects.h; 0: the effect has none). An effect with one has a
  // limit per listed shape (a slow sink drains less within a run, so it hides more capacity).
  double shape = 0.0;
  std::vector<LimitRun> runs;        // ascending strength
  double threshold = kRuleOutDelta;  // kRuleOutDelta × limit_scale (each run's own: rule_out_at)
  // The weakest strength run from which every stronger run is ruled out (0: none is), and its Δ.
  double ruled_out_from = 0.0, ruled_delta = 0.0;
  // The strongest run under ruled_out_from (every run when none is ruled out; 0: none ran under it), its Δ.
  double allowed_to = 0.0, allowed_delta = 0.0;
  // Where Δ crosses the threshold between allowed_to and ruled_out_from (the larger of their rule_out_at),
  // √Δ (a shift in units of the noise) linear in log strength (0: not bracketed by runs on both sides).
  double about = 0.0;
};

// An effect with a second parameter, its limit with that parameter left free (a profile over the listed
// shapes, as the fit's): a strength is ruled out only where it is ruled out at every shape, so the limit is
// the largest of the shapes' ruled_out_from, set by `binding` (0 when some shape rules out none of its runs:
// `open` lists them, with the strongest strength each ran). Shapes outside the listed range are not tested.
struct FreeShapeLimit {
  std::string effect;
  std::vector<double> shapes;  // ascending, those with runs
  double ruled_out_from = 0.0;
  double binding = 0.0;
  std::vector<std::pair<double, double>> open;  // (shape, strongest strength run) where nothing is ruled out
};
// One per effect with limits at more than one shape (limits: table_limits'). Pure (tests).
std::vector<FreeShapeLimit> free_shape_limits(const std::vector<Limit>& limits);
// The limit at an effect's default shape (its only one when it has none); nullptr when it has none.
const Limit* default_limit(const std::vector<Limit>& limits, const std::string& effect);

// The Δ from which a run is ruled out: max(threshold, kRuleOutNoiseZ × noise_sd); and whether it is.
double rule_out_at(const LimitRun& x, double threshold);
bool ruled_out(const LimitRun& x, double threshold);

// The bracket of one candidate's runs (sorted by strength here). Pure (tests).
Limit limit_of(const std::string& effect, std::vector<LimitRun> runs, double threshold);

// Every candidate's limit from the runs the procedure has, for a `no_gap` verdict (empty otherwise): one per
// shape that has runs, the default shape first (the screen's probes, the reach's and run_limits' runs; the
// other listed shapes only run_limits').
std::vector<Limit> table_limits(const Procedure& p);

// A bracket wider than this ratio is split by run_limits.
constexpr double kLimitRatio = 2.5;

// The next strength to run to bracket a limit (0: none): when every run is ruled out, one step under the
// weakest (`step`, the probes' ratio: probe_step, fit.h), floored at phys_lo; when the bracket is wider than
// kLimitRatio, its geometric middle. To 3 digits; 0 when that is within 10 % of a strength already run, or
// nothing is ruled out (no limit to bracket: the reach says where a candidate would show), unless `climb`
// (a shape other than the default, run for the free-shape limit: nothing ruled out yet there means the
// limit with the shape free lies higher): then phys_hi, the end of the physical range, whose run either
// leaves the shape open over the whole range or makes a bracket the next rounds split. Pure.
double next_limit_strength(const Limit& l, double step, double phys_lo, double phys_hi = 0.0,
                           bool climb = false);

// Stage 8b: p.limits, after up to limit_steps rounds of next_limit_strength runs (one run per condition at
// the probe seeds, every candidate that asks for one in a round run together; the cost guard and failures as
// anywhere, noted). An effect with a second parameter, once its default shape rules a strength out, runs its
// other listed shapes from that strength, climbing where it is not ruled out and bracketing at the shape that
// binds, so that its limit holds with the shape free (free_shape_limits).
void run_limits(Procedure& p);

}  // namespace wetdem::diagnose
