#include "diagnose/table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "diagnose/files.h"
#include "diagnose/observables.h"
#include "study/observations.h"

namespace wetdem::diagnose {

Table read_table(const std::string& path) {
  std::vector<study::Observation> rows;
  try {
    rows = study::read_observations(path, /*allow_missing=*/true);
  } catch (const std::exception& e) {
    throw DiagnoseError(e.what());
  }
  Table t;
  t.path = path;
  std::map<std::string, std::vector<size_t>> lines_of, measured_of;  // observable -> its rows' lines
  std::map<std::string, size_t> line_of_cell;                        // condition|observable -> its row
  for (const study::Observation& r : rows) {
    const ObservableSpec* o = find_observable(r.observable);
    if (!o)
      throw DiagnoseError(fmt::format("{}: line {}: unknown observable '{}' (known: {})", path, r.line,
                                      r.observable, observable_names()));
    lines_of[r.observable].push_back(r.line);
    std::vector<study::AxisValue> v;
    for (const auto& [k, w] : r.conditions) v.push_back({k, w, toml_text_of_written(w), std::nan("")});
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    const std::string label = condition_label(v);
    // One row per cell: two values for one cell would be two cells at one condition, each counted as an
    // independent observation (repeats enter as their mean, with n).
    if (const auto [it, fresh] = line_of_cell.emplace(label + "|" + r.observable, r.line); !fresh)
      throw DiagnoseError(fmt::format(
          "{}: lines {} and {} both give {} at {}: one row per condition and observable (enter repeated "
          "measurements as their mean, sigma of the mean and n)",
          path, it->second, r.line, r.observable, label));
    if (!r.measured) {
      t.not_measured.push_back(fmt::format("line {}: {} at {}", r.line, r.observable, label));
      continue;
    }
    // A value further outside the observable's possible range than its noise could put a measurement (a
    // negative fraction at 5 sigma) is a typing error, not a gap. Closer, it is kept: a washing assay may
    // recover 101 % of the liquid, within its error.
    if (r.value < o->lo - 5.0 * r.sigma || r.value > o->hi + 5.0 * r.sigma)
      throw DiagnoseError(fmt::format(
          "{}: line {}: {} = {:g} is outside its possible range [{:g}, {:g}] ({}) by more than 5 sigma "
          "({:g}): not a measurement's noise",
          path, r.line, r.observable, r.value, o->lo, o->hi, o->unit, r.sigma));
    measured_of[r.observable].push_back(r.line);
    size_t ci = 0;
    while (ci < t.conditions.size() && t.conditions[ci].label != label) ++ci;
    if (ci == t.conditions.size()) t.conditions.push_back({v, label, {}});
    t.cell_condition.push_back(ci);
    t.cell_line.push_back(r.line);
    Cell c;
    c.observable = r.observable;
    c.y = r.value;
    c.sigma = r.sigma;
    t.cells.push_back(c);
  }
  for (const auto& [obs, lines] : lines_of)
    if (!measured_of.count(obs)) {
      std::string ls;
      for (size_t l : lines) ls += (ls.empty() ? "" : ", ") + std::to_string(l);
      throw DiagnoseError(fmt::format(
          "{}: {} carries no information at any condition (lines {}: every value missing or sigma "
          "infinite); measure it or remove its rows",
          path, obs, ls));
    }
  if (t.conditions.size() < 2)
    throw DiagnoseError(
        fmt::format("{}: {} measured condition(s): a diagnosis needs at least two (no held-out check "
                    "is possible with one)",
                    path, t.conditions.size()));
  return t;
}

std::string condition_lines(const Table& t, size_t ci) {
  std::vector<size_t> lines;
  for (size_t k = 0; k < t.cell_line.size(); ++k)
    if (t.cell_condition[k] == ci) lines.push_back(t.cell_line[k]);
  std::sort(lines.begin(), lines.end());
  std::string out;
  for (size_t i = 0; i < lines.size();) {
    size_t j = i;
    while (j + 1 < lines.size() && lines[j + 1] == lines[j] + 1) ++j;
    out +=
        (out.empty() ? "" : ", ") + std::to_string(lines[i]) + (j > i ? "-" + std::to_string(lines[j]) : "");
    i = j + 1;
  }
  return (lines.size() == 1 ? "line " : "lines ") + out;
}

void check_producible(const Table& t, bool periodic_slice) {
  for (size_t k = 0; k < t.cells.size(); ++k) {
    const ObservableSpec* o = find_observable(t.cells[k].observable);
    if (o && o->needs_plates && periodic_slice)
      throw DiagnoseError(fmt::format(
          "{}: line {}: the model cannot produce {}: it is a periodic slice, which has no end plates (use a "
          "closed drum, drum.periodic_slice = false, or drop the row)",
          t.path, t.cell_line[k], t.cells[k].observable));
  }
}

}  // namespace wetdem::diagnose
