// What one new measurement would carry (diagnosis.md §4, the next experiment and the measurement that bounds
// an open interval): the noise of each observable measured once more (the table's, or an assay's file), how
// far two models' predictions of it lie apart in that noise, and how often a laboratory would repeat it to
// reach a given separation. Shared by the tie's next experiment, the interval's bound and the reach.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// The noise of a new measurement of each observable: the table's median sigma for it.
std::map<std::string, double> median_sigma(const std::vector<Cell>& cells);

// What a new measurement of each observable would carry: its noise σ (the table's median σ; an assay's, the
// σ its file gives), the factor that scales one run's own window SE to the model's seed spread, and the
// model's typical squared SE of a table cell's mean (the median over the table's cells of the baseline's,
// per table observable; sigma_at).
struct MeasurementNoise {
  std::map<std::string, double> sigma, inflation, typical_se2;
};
MeasurementNoise measurement_noise(const Procedure& p);

// One new measurement's noise at a condition where the two models' means carry se_x and se_y. A table row's
// σ holds the instrument's noise and the spread of the runs the laboratory averaged, σ² = σ_i² + s²/n, and
// the model's SE over its R seeds estimates the second part (n ≈ R). Where the runs spread more than at the
// table's typical cell (a wet bed that sticks and slips at 20 % liquid), a measurement there carries the
// excess: σ_c² = σ² + max(0, (se_x² + se_y²)/2 − typical_se2). Never below the table's σ (calmer conditions
// are not trusted to be quieter); σ itself where typical_se2 has no entry (assays: their file's σ is whole).
// On the flowing viscous-weak twin the row at 60 rpm, 20 % came back with σ 0.031 m/s against the 0.0155
// assumed (docs/validation.md, "A measurement repeated").
double sigma_at(const MeasurementNoise& n, const std::string& observable, double se_x, double se_y);

// |x - y| / sqrt(σ_c² + se_x² + se_y²), σ_c = sigma_at: how far two models' predictions of one measurement
// lie apart in its noise.
double separation_of(const MeasurementNoise& n, const std::string& observable, const Prediction& x,
                     const Prediction& y);

// How many times a laboratory would repeat one measurement (entering their mean, with σ/√k) for two
// predictions |delta| apart to lie `target` σ apart: the smallest k ≤ kMaxRepeats with
// |delta| / sqrt(σ²/k + se²) ≥ target, se² the two models' own squared errors (repeats shrink the
// measurement's noise, not the runs'). 0 when none does: the runs' own error alone holds |delta| under
// target σ (more seeds of them first), or more than kMaxRepeats would be needed. 1: one measurement does.
// Pure (tests).
inline constexpr size_t kMaxRepeats = 16;
size_t repeats_for(double delta, double sigma, double se2, double target);

}  // namespace wetdem::diagnose
