// Reports the paragraph tests build on (test_diagnose_paragraph*.cpp): an `unexplained` verdict with cohesion
// ranked first, and cohesion chosen with its fresh runs made.
#pragma once

#include "diagnose/report.h"

namespace wetdem::test {

inline diagnose::Report unexplained(double shrink) {
  using namespace diagnose;
  static DiagnosisSpec spec;  // rule: ratio 0.5 (a 50 % held-out shrink for `effect`)
  Report r;
  r.spec = &spec;
  r.cells.resize(3);
  r.gaps.resize(3);
  r.gaps[1].significant = true;
  r.verdict.kind = "unexplained";
  Candidate c;
  c.effect = "cohesion";
  c.fit.strength = 0.114;
  r.verdict.ranking.push_back(c);
  r.verdict.held_out_shrink = shrink;
  r.verdict.held_out_gap_shrink = shrink;  // of the gap above the noise floor (verdict.h)
  return r;
}

// cohesion chosen (kind "effect" or "partial") with its fresh runs made.
inline diagnose::Report chosen_with_fresh_runs(const std::string& kind) {
  using namespace diagnose;
  Report r = unexplained(0.8);
  r.verdict.kind = kind;
  r.verdict.effect = "cohesion";
  r.fresh.resize(1);
  r.fresh[0].effect = "cohesion";
  r.fresh[0].after.resize(3);
  r.fresh[0].gaps_after.resize(3);
  return r;
}

}  // namespace wetdem::test
