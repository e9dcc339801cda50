// The candidate effects the diagnosis can switch on (diagnosis.md §3), each as one positive "strength" on a
// log axis whose limit 0 is the model without the effect, and the case overrides that realise a strength.
// The case keys and laws are the model's own (README, "Candidate effects"); this table only maps strengths.
#pragma once

#include <string>
#include <vector>

namespace wetdem::diagnose {

struct EffectSpec {
  std::string name;            // "viscous", "absorption", ...
  std::string strength;        // what the strength is, with its unit ("eta (Pa s)", "1/tau (1/s)", ...)
  std::vector<double> probes;  // default strengths probed (ascending, > 0, inside the physical range)
  std::string fingerprint;     // what it leaves in the observables (for the report)
  // The --set overrides ("key=toml") that switch the effect on at strength s, given the case's own contact
  // angle (rad) where the strength is relative to it.
  std::vector<std::string> overrides(double s, double theta_rad) const;
};

// Every effect the diagnosis knows, in a fixed order.
const std::vector<EffectSpec>& effect_catalogue();
// The spec of one effect; throws std::invalid_argument naming the known ones when the name is unknown.
const EffectSpec& effect_spec(const std::string& name);

}  // namespace wetdem::diagnose
