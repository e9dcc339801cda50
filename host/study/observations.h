// The observation table (CSV, shared with the diagnosis; spec studies.md): condition columns (case keys,
// values with units as in case files), then `observable` (a summary.json key), `value`, `sigma` (one standard
// deviation of the mean, same unit), optional `n` and `note`. Errors name the file and the row.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace wetdem::study {

struct Observation {
  size_t line = 0;  // 1-based line in the file (the header is line 1)
  std::vector<std::pair<std::string, std::string>> conditions;  // key, value as written
  std::vector<double> conditions_si;                            // filled by the caller (calibrate)
  std::string observable;
  double value = 0, sigma = 0;
  int n = 0;  // 0: not given
  std::string note;
  bool measured = true;  // false: a row that states a quantity was not measured (allow_missing only)
};

// Parses and checks the table's form (columns, numbers, positive sigma). Throws StudyError naming the row.
// With allow_missing, a row whose value is empty or "NA"/"nan", or whose sigma is "inf", is read as "not
// measured" (measured = false) instead of refused: a laboratory table often lists every cell it planned.
std::vector<Observation> read_observations(const std::string& path, bool allow_missing = false);

// Splits one CSV line (RFC 4180 quotes).
std::vector<std::string> split_csv(const std::string& line);

}  // namespace wetdem::study
