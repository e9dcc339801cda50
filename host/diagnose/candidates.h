// Steps 3-5 of the diagnosis (diagnosis.md §4): which candidate effect explains the gap, at what strength,
// and how far the gap shrinks. Pure statistics on predictions the runs produced; nothing here runs a model.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "diagnose/cells.h"

namespace wetdem::diagnose {

// A candidate's predictions at a few strengths of its key (in the key's SI units), one vector per strength.
struct Response {
  std::string effect;
  std::vector<double> strengths;              // > 0, ascending
  std::vector<std::vector<Prediction>> pred;  // [strength][cell]
};

// Screen (§4.3): projection of the z-vector of the baseline on the candidate's response pattern
// r_k = (ŷ_probe,k - ŷ_base,k) / sqrt(σ_k² + SE_k²), normalised: Σ z_k r_k / |r|. Positive when the effect
// moves the model towards the observations; 0 when it changes nothing.
double screen_score(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                    const std::vector<Prediction>& probe);

// The response of every cell over u = log10(strength): piecewise-linear interpolation through the baseline
// (placed at u_lo = log10 of a tenth of the weakest strength probed, where the effect is taken as absent) and
// the probes, in mean and in SE. Interpolation, not a smoothing fit: with three or four points per cell a
// polynomial overshoots steep responses (f_wet against a wetted fraction), and an emulator that misplaces the
// response misplaces the fitted strength. Outside [u_lo, u_hi] the end values hold (no extrapolation).
class Emulator {
 public:
  Emulator(const std::vector<Prediction>& baseline, const Response& r);
  Prediction at(size_t cell, double u) const;
  std::vector<Prediction> at(double u) const;
  double u_lo() const { return u_.front(); }  // the anchor of the baseline
  double u_hi() const { return u_.back(); }   // the strongest strength probed
  size_t cells() const { return mean_.size(); }

 private:
  std::vector<double> u_;                       // knots: anchor, then log10 of every probe
  std::vector<std::vector<double>> mean_, se_;  // per cell, per knot
};

struct StrengthFit {
  double strength = 0.0;      // best fit (10^u)
  double lo = 0.0, hi = 0.0;  // Δχ² = 1 interval (clipped to the probed range)
  double chi2 = 0.0;          // at the best fit, over the cells fitted
  bool at_edge = false;       // the optimum sits at the probed range's edge
};
// Weighted least squares of the strength against the cells `idx` (all when empty): χ²(u) on a dense grid over
// [u_lo, u_hi], refined by golden-section search around the grid minimum.
StrengthFit fit_strength(const std::vector<Cell>& cells, const Emulator& em,
                         const std::vector<size_t>& idx = {});

// Refinement of a candidate's response: the emulator interpolates between probes a factor 3-10 apart, and a
// response that bends between them misplaces the fitted strength (measured on the micro twins: an absorption
// capacity fitted at twice its true value). next_knot: the fitted strength (3 significant digits) when no
// knot lies within 2 % of it in log strength, else 0 (refined). add_knot: inserts a run's predictions there.
double next_knot(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline, const Response& r);
void add_knot(Response& r, double strength, std::vector<Prediction> pred);

// Leave-one-condition-out score: for every condition c, fit the strength without c's cells, predict c's
// cells, and add their χ². The null model (no effect, nothing fitted) scores Σ χ² of the baseline.
double loco_score(const std::vector<Cell>& cells, const Emulator& em);
double loco_null(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline);
// With refit: the setting is refitted with the strength in every fold (one emulator per setting), and the
// null's setting too (one baseline per setting; with one setting this is the plain χ² above).
double loco_score(const std::vector<Cell>& cells, const std::vector<Emulator>& ems);
double loco_null(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines);

// Re-fitted parameters (refit.h): the models form a family indexed by a refit setting j (0 = as calibrated),
// each with its own baseline and, per candidate, its own response (runs at j). The fit is a discrete profile:
// at each j the strength is fitted as above; the (j, strength) of least χ² is kept, the lowest j on a tie.
struct RefitFit {
  size_t setting = 0;
  StrengthFit fit;
};
RefitFit fit_refit(const std::vector<Cell>& cells, const std::vector<Emulator>& ems,
                   const std::vector<size_t>& idx = {});
// The null model with the same refit: the setting whose baseline has the least χ² over idx (lowest on a tie).
size_t fit_null_refit(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
                      const std::vector<size_t>& idx = {});
// Refinement with refit: the knot next_knot asks for at the setting the profile fit chooses: (setting,
// strength), strength 0 when refined. baselines[j] and responses[j] belong to setting j.
std::pair<size_t, double> next_refit_knot(const std::vector<Cell>& cells,
                                          const std::vector<std::vector<Prediction>>& baselines,
                                          const std::vector<Response>& responses);

struct Candidate {
  std::string effect;
  double screen = 0.0;
  double loco = 0.0;
  StrengthFit fit;   // on all cells
  size_t refit = 0;  // the refit setting fitted with it on all cells (0 without refit)
};

// The verdict rule (docs/diagnosis.md):
//  no_gap      no cell significant at FDR q (Benjamini-Hochberg);
//  effect      else, the candidate with the lowest LOCO score when it beats the null by a clear margin:
//              LOCO_best <= ratio x LOCO_null and LOCO_null - LOCO_best >= min_drop;
//  refit       (with refit only) else, when the null at its re-fitted setting leaves no cell significant at
//              FDR q: re-fitting closes the gap, no effect is chosen;
//  unexplained otherwise (the ranking is still reported).
struct VerdictRule {
  double q = 0.05;
  double ratio = 0.5;
  double min_drop = 4.0;
};
struct Verdict {
  std::string kind;                // "no_gap", "effect", "refit", "unexplained"
  std::string effect;              // the chosen effect when kind == "effect"
  std::vector<Candidate> ranking;  // by LOCO score, best first
  double null_loco = 0.0;
  size_t null_refit = 0;         // the null's refit setting fitted on all cells (0 without refit)
  double held_out_shrink = 0.0;  // 1 - LOCO_best / LOCO_null (the left-out predictions)
};
Verdict decide(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Response>& responses, const std::vector<double>& screens,
               const VerdictRule& rule = {});
// With refit: baselines[j] per setting (baselines[0], as calibrated, decides where the gap is) and
// responses[i][j] per candidate and setting; the rule is the same, on the refitted LOCO scores.
Verdict decide(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
               const std::vector<std::vector<Response>>& responses, const std::vector<double>& screens,
               const VerdictRule& rule = {});

}  // namespace wetdem::diagnose
