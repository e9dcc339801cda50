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
// reach at some condition, an observable the model cannot produce).
nlohmann::json run_twin(const TwinSpec& t, const DiagnoseOptions& o);

// A measurement of `mean` with noise sd: Gaussian, truncated to the observable's physically possible range
// (observables.h: a fraction stays in [0, 1], a size >= 1), by redrawing, so a bounded observable never gets
// an impossible value (a negative f_wet at 0 % liquid). A mean outside the range is first put on its edge.
double noisy_measurement(const std::string& observable, double mean, double sd, std::mt19937_64& rng);

}  // namespace wetdem::diagnose
