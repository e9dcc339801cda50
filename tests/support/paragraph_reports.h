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

// `first` chosen (kind "effect" or "partial") at held-out χ² loco_first, `second` tied with it at loco_second
// and fitted at strength_second, both with their fresh runs made.
inline diagnose::Report tie_with_fresh_runs(const std::string& kind, const std::string& first,
                                            double loco_first, const std::string& second, double loco_second,
                                            double strength_second) {
  using namespace diagnose;
  Report r = chosen_with_fresh_runs(kind);
  r.verdict.effect = first;
  r.verdict.ranking[0].effect = first;
  r.verdict.ranking[0].loco = loco_first;
  r.fresh[0].effect = first;
  Candidate e;
  e.effect = second;
  e.loco = loco_second;
  e.fit.strength = strength_second;
  r.verdict.ranking.push_back(e);
  r.verdict.tied = {second};
  r.fresh.resize(2);
  r.fresh[1].effect = second;
  r.fresh[1].after.resize(3);
  r.fresh[1].gaps_after.resize(3);
  return r;
}

}  // namespace wetdem::test
