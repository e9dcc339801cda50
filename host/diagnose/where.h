// Step 2 of the diagnosis (diagnosis.md §4): where do simulation and observation disagree? Per cell the gap
// y - ŷ, its z-score and two-sided p-value; significance by the Benjamini-Hochberg rule over all cells, so a
// table with many cells does not find gaps by chance (the expected share of false discoveries is at most q).
#pragma once

#include <string>
#include <vector>

#include "diagnose/cells.h"

namespace wetdem::diagnose {

struct CellGap {
  double gap = 0.0;  // y - ŷ
  double z = 0.0;
  double p = 1.0;  // two-sided, normal: erfc(|z|/√2)
  bool significant = false;
};

// Benjamini-Hochberg (1995) at false-discovery rate q: sort p ascending, find the largest k with
// p_(k) <= k q / m, declare the k smallest significant. Returns one flag per input, in input order.
std::vector<bool> benjamini_hochberg(const std::vector<double>& p, double q);

std::vector<CellGap> where(const std::vector<Cell>& cells, const std::vector<Prediction>& pred,
                           double q = 0.05);

// Plain-language summaries: one line per observable with significant cells ("aor_deg_mean: observation above
// the model at 3 of 4 conditions (liquid.content 0.05-0.1), gap growing with liquid.content"), and "no
// significant gap" otherwise. Trends are stated along a condition key only when the cells differ in that key
// alone.
std::vector<std::string> describe_where(const std::vector<Cell>& cells, const std::vector<CellGap>& gaps);

// χ² of a gap set (finite z only) and its significant cells.
double chi2_of(const std::vector<CellGap>& g);
size_t significant(const std::vector<CellGap>& g);

}  // namespace wetdem::diagnose
