// Synthetic cells and responses with known answers for the diagnosis's statistics tests (the fit in
// test_diagnose_fit.cpp, the verdict in test_diagnose_verdict.cpp): one observable over five liquid contents,
// and responses linear in log10(strength). In a header, not in each file's anonymous namespace: test files
// are compiled in batches (unity build), where the two would be defined twice.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "diagnose/cells.h"
#include "diagnose/emulator.h"

namespace wetdem::test {

inline std::vector<diagnose::Cell> cells_at(const std::vector<double>& phi, const std::vector<double>& y,
                                            double sigma) {
  std::vector<diagnose::Cell> c;
  for (size_t i = 0; i < y.size(); ++i)
    c.push_back({{{"liquid.content", phi[i]}}, "aor_deg_mean", y[i], sigma});
  return c;
}

// A response linear in log10(s) from the anchor a decade below the weakest probe: base + slope (u -
// u_anchor).
inline diagnose::Response linear(const std::string& name, const std::vector<double>& strengths,
                                 const std::vector<double>& slope, double base, double se = 0.1) {
  diagnose::Response r;
  r.effect = name;
  r.strengths = strengths;
  const double u0 = std::log10(strengths.front()) - 1.0;
  for (double s : strengths) {
    std::vector<diagnose::Prediction> p;
    for (double k : slope) p.push_back({base + k * (std::log10(s) - u0), se});
    r.pred.push_back(p);
  }
  return r;
}

inline const std::vector<double> kPhi = {0.0, 0.025, 0.05, 0.075, 0.10};
inline const std::vector<double> kSlope = {0.0, 0.5, 1.0, 2.0, 3.0};

}  // namespace wetdem::test
