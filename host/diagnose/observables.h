// The observables a diagnosis accepts in its table (diagnosis.md §2): the scalar outputs of every run
// (summary.json keys), each with the instrument that measures it in a laboratory, whether a laboratory
// measures it routinely, and its physically possible range (a twin's noise never leaves it).
#pragma once

#include <string>
#include <vector>

namespace wetdem::diagnose {

struct ObservableSpec {
  std::string name;                // summary.json key
  std::string unit;                // "deg", "m", "m/s", "-", "particles"
  std::string instrument;          // what measures it
  std::string routine;             // "yes", "common", "rare", "no (simulation only)"
  double lo = -1e300, hi = 1e300;  // physically possible values
  bool needs_plates = false;       // exists only in a closed drum (end plates)
  bool lab() const { return routine == "yes" || routine == "common"; }
};

// Every observable, in a fixed order (laboratory ones first).
const std::vector<ObservableSpec>& observable_catalogue();
// nullptr when the name is not an observable.
const ObservableSpec* find_observable(const std::string& name);
// "aor_deg_mean, aor_deg_std, ...": every name, for messages.
std::string observable_names();

}  // namespace wetdem::diagnose
