// What the table can see (diagnose/power.h): the largest shift of a probe over the baseline, in units of each
// cell's noise, against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "diagnose/power.h"

namespace wetdem::diagnose {
namespace {

Cell cell(double sigma) {
  Cell c;
  c.observable = "aor_deg_mean";
  c.sigma = sigma;
  return c;
}

TEST(DiagnosePower, TheLargestShiftIsCountedInEachCellsNoise) {
  // Cell 0: a shift of 2 against sigma 1 and se 0: 2 sigma. Cell 1: a shift of 6 against sqrt(3^2 + 4^2) = 5:
  // 1.2 sigma, though larger in absolute terms. Cell 2: a shift of -0.9 against sqrt(0.3^2 + 0.4^2) = 0.5:
  // 1.8 sigma (the sign does not matter).
  const std::vector<Cell> cells = {cell(1.0), cell(3.0), cell(0.3)};
  const std::vector<Prediction> base = {{10.0, 0.5}, {20.0, 0.5}, {0.0, 0.5}};
  const std::vector<Prediction> probe = {{12.0, 0.0}, {26.0, 4.0}, {-0.9, 0.4}};
  const auto [z, k] = largest_shift(cells, base, probe);
  EXPECT_NEAR(z, 2.0, 1e-12);
  EXPECT_EQ(k, 0u);
  EXPECT_LT(z, kVisibleZ) << "2 sigma in one cell is not a shift a lab would call significant";
}

TEST(DiagnosePower, CellsAProbeDoesNotReportAreSkipped) {
  // A probe that reports no value at a cell (NaN: the quantity does not exist there) never makes the largest
  // shift, and a probe identical to the baseline has none.
  const std::vector<Cell> cells = {cell(1.0), cell(1.0)};
  const std::vector<Prediction> base = {{1.0, 0.1}, {5.0, 0.1}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto [z, k] = largest_shift(cells, base, {{nan, nan}, {8.5, 0.0}});
  EXPECT_NEAR(z, 3.5, 1e-12);
  EXPECT_EQ(k, 1u);
  EXPECT_EQ(largest_shift(cells, base, base).first, 0.0);
}

}  // namespace
}  // namespace wetdem::diagnose
