// `wetdem twin T.toml --out DIR` (diagnosis.md §5): observations from a model with an effect the diagnosis
// is not told about (the truth), to check the procedure on data whose answer is known.
#pragma once

#include <nlohmann/json.hpp>
#include <random>

#include "diagnose/driver.h"
#include "diagnose/files.h"

namespace wetdem::diagnose {

// The truth runs, then observations.csv (noisy means, sigma) and, apart, truth.json. Returns truth.json.
// Every condition is validated before any run (a case no run could make, a slice too thin for the neighbour
// reach at some condition, an observable the model cannot produce). With o.check it stops there: nothing is
// run or written, and it returns {"checked": true, "conditions": N, "runs": N x seeds}.
nlohmann::json run_twin(const TwinSpec& t, const DiagnoseOptions& o);

// A measurement of `mean` with noise sd that never leaves the observable's physically possible range
// (observables.h: a fraction stays in [0, 1], a size >= 1) and whose expectation is the mean: Gaussian far
// from the bounds, a gamma or beta of the same mean and sd within 6 sd of one (a truncated Gaussian there
// would bias the twin). A mean outside the range is first put on its edge; a mean on an edge is returned as
// is.
double noisy_measurement(const std::string& observable, double mean, double sd, std::mt19937_64& rng);

}  // namespace wetdem::diagnose
