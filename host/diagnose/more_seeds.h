// After the verdict (stage 6c, docs/diagnosis.md): would more seeds per condition decide a tie? A tie between
// two fitted models stays a tie when the table cannot tell them apart, however exactly each is known: two
// liquid sinks that remove the same liquid at the same rate leave one fingerprint (the flowing matrix's
// absorption-weak, 7 Dec 2026: escalated from 2 to 4 seeds, the tie stayed and its order flipped by 0.23 sd;
// docs/twin_matrix_flowing.md). More seeds lower the models' own noise, never the table's, so the separation
// the table allows is bounded by what the fitted models' fresh runs already show. This stage estimates it, so
// that the escalation (driver.cpp) pays for a second pass only where it could decide, and the report says
// which it is.
#pragma once

#include <string>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// The χ² by which the table would separate two fitted models whose means over R seeds are a and b, when each
// is run at R' seeds instead (ratio = R / R'): Σ_i (Δ̂_i² − w_i) / (σ_i² + (se_a,i² + se_b,i²)·ratio) over the
// cells where all are finite, with Δ̂_i = a_i − b_i, w_i = Var(Δ̂_i) (so that Δ̂_i² − w_i estimates the true
// Δ_i² without the bias the models' noise adds) and σ_i the table's. It is the expected difference of the two
// models' χ² when one of them is the truth (the observation noise adds ±2√ of it). ratio = 0: exact models.
// A negative sum (models closer than their noise) gives 0. Pure (tests).
double predicted_separation(const std::vector<Cell>& cells, const std::vector<Prediction>& a,
                            const std::vector<Prediction>& b, const std::vector<double>& diff_var,
                            double ratio);

// Var(Δ̂_i) of the difference of two models' means over the same R seeds, from the per-seed differences d_s:
// their sample variance over R (R ≥ 2). The two models' runs share their seeds (the fresh seeds R+1..2R), so
// their difference can vary far less than se_a² + se_b² says; NaN where R < 2 or a value is missing. Pure.
std::vector<double> paired_difference_variance(const std::vector<std::vector<Prediction>>& a_by_seed,
                                               const std::vector<std::vector<Prediction>>& b_by_seed);

// The most seeds per condition the outlook looks for (TieOutlook::seeds_needed).
inline constexpr int kMostSeeds = 64;

// The outlook of an undecided verdict at `to` seeds per condition (to > p.d.replicates). Reads the fresh runs
// of the chosen and tied candidates (p.fresh), the control's seed luck and the table; runs nothing.
MoreSeeds more_seeds_outlook(const Procedure& p, int to);

// Whether more seeds could decide anything at all: a tie, a comparison the luck decided, a gap on the
// baseline's seeds only (the escalation's trigger; driver.cpp).
bool undecided(const Procedure& p);

}  // namespace wetdem::diagnose
