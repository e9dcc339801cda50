// Model parameters re-fitted with each effect (diagnosis.md §1 and §4 step 4; docs/diagnosis.md, "Re-fitted
// parameters"): `refit = ["liquid.v_max"]` with `[refit_values] "liquid.v_max" = ["0.5 %", "2 %"]` in the
// diagnosis file. The calibrated value is always tried (setting 0); every value is checked against the case
// schema before any run.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace wetdem::diagnose {

struct RefitValue {
  std::string written;  // as in the file ("0.5 %", "0.002")
  std::string toml;     // as a --set value
  double si = 0.0;
};
struct RefitKey {
  std::string key;  // dotted case key, e.g. "liquid.v_max"
  double calibrated_si = 0.0;
  std::vector<RefitValue> values;  // the values to try besides the calibrated one, in file order
};

// One point of the refit grid: every refit key at one value. Setting 0 is the calibrated model (no override);
// the others follow in the order of the Cartesian product of [calibrated] + values per key (last key
// fastest).
struct RefitSetting {
  std::vector<std::string> overrides;  // "key=toml" (none for setting 0)
  std::string label;                   // "liquid.v_max=0.5 %" ("calibrated" for setting 0)
  std::map<std::string, double> si;    // every refit key -> its SI value in this setting
};

// At most this many settings: the baseline and the fitted candidates' runs multiply by their number.
constexpr size_t kMaxRefitSettings = 16;

// Reads `refit` and [refit_values] of the diagnosis file `path` (root), for the case `case_path` with the
// overrides `set`; `effect_keys` maps the case keys the candidate effects set to the effect (a refit key may
// not be one of them: the fit could not tell the effect from the re-fitted parameter).
// Throws DiagnoseError naming the file and the key.
std::vector<RefitKey> parse_refit(const toml::table& root, const std::string& path,
                                  const std::string& case_path, const std::vector<std::string>& set,
                                  const std::map<std::string, std::string>& effect_keys);

// The refit grid (one setting, the calibrated model, when `keys` is empty).
std::vector<RefitSetting> refit_settings(const std::vector<RefitKey>& keys);

}  // namespace wetdem::diagnose
