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
// significant gap" otherwise (left out with gaps_only, as the report's paragraph does: the Where section
// lists them). Trends are stated along a condition key only when the cells differ in that key alone.
std::vector<std::string> describe_where(const std::vector<Cell>& cells, const std::vector<CellGap>& gaps,
                                        bool gaps_only = false);

// χ² of a gap set (finite z only) and its significant cells.
double chi2_of(const std::vector<CellGap>& g);
size_t significant(const std::vector<CellGap>& g);

// The table as a whole (Pearson's goodness-of-fit test). A gap spread thinly over many cells, none of which
// passes Benjamini-Hochberg alone, still shows in the sum of z² over the cells: with the table's σ and the
// model's SE right, χ² over n cells with a finite z follows χ²_n, so the model departs from the table when
// P(χ²_n >= χ²) < level (the flowing matrix's absorption-strong: largest |z| 3.4, BH asks ~3.3 σ of one of 48
// cells, but the cells together sum to ~74, past χ²_48's 1 % point 73.7). Conservative where the σ are
// (a twin's: a right model scores ~0.5 a cell on the flowing drum). level 0 turns the test off.
// χ²_n's upper `level` point: P(χ²_n >= x) = level (infinite for n = 0 or a level outside (0, 1)).
double chi2_upper_point(size_t n, double level);

struct TableFit {
  double chi2 = 0.0;
  size_t n = 0;           // cells with a finite z
  double p = 1.0;         // P(χ²_n >= chi2), the regularized upper incomplete gamma Q(n/2, chi2/2)
  double critical = 0.0;  // χ²_n's (1 - level) point (infinite when the test is off)
  double level = 0.0;     // the level it was tested at (0: off)
  bool beyond = false;    // p < level
};
TableFit table_fit(const std::vector<CellGap>& g, double level);

// "χ² 86.7 over 48 cells, beyond χ²_48's 1 % point 73.7 (p = 0.0012)" ("within" when not beyond); the
// report's and the paragraph's words for table_fit.
std::string table_text(const TableFit& t);

// The model departs from the table: a significant cell, or the table's χ² beyond its level (table_fit).
bool has_gap(const std::vector<CellGap>& g, double level);

}  // namespace wetdem::diagnose
