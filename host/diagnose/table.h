// The observation table of a diagnosis (studies.md, "Observation table"), read into conditions and cells.
// Every check that the table alone allows is made here, before any run; errors name the file and the row.
#pragma once

#include <string>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/runbook.h"

namespace wetdem::diagnose {

struct Table {
  std::string path;
  std::vector<Condition> conditions;
  std::vector<size_t> cell_condition;  // per cell: index into conditions
  std::vector<size_t> cell_line;       // per cell: its line in the file
  std::vector<Cell> cells;
  std::vector<std::string> not_measured;  // rows that say a quantity was not measured ("line 7: ...")
};

// Reads the table: unknown observables, fewer than two conditions, and an observable (or a whole table)
// that carries no information at any condition (every row not measured: empty or NA value, or sigma inf)
// are DiagnoseError naming the file and the rows. Rows that are not measured are dropped (and listed).
Table read_table(const std::string& path);

// The lines of the table's rows at condition `ci`, for an error about that condition: "line 3", "lines 3-10",
// "lines 3, 7-9" (runs of consecutive lines joined).
std::string condition_lines(const Table& t, size_t ci);

// Refuses, naming the row, an observable the model cannot produce: an end-plate quantity (aor_plate_deg,
// aor_centre_deg) in a periodic slice, which has no plates.
void check_producible(const Table& t, bool periodic_slice);

}  // namespace wetdem::diagnose
