// The plain-language verdict of report.md says what a process engineer can act on: for `unexplained`, whether
// the best candidate is a lead worth more data (it helps, but less than the rule asks) or nothing helps.
#include <gtest/gtest.h>

#include "diagnose/report.h"

using namespace wetdem::diagnose;

namespace {

Report unexplained(double shrink) {
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
  return r;
}

}  // namespace

TEST(DiagnoseParagraph, UnexplainedNamesALeadOnlyWhenTheBestCandidateHelps) {
  const std::string lead = verdict_paragraph(unexplained(0.29));
  EXPECT_NE(lead.find("a lead: `cohesion`"), std::string::npos) << lead;
  EXPECT_NE(lead.find("29 %"), std::string::npos) << lead;
  EXPECT_NE(lead.find("short of the 50 %"), std::string::npos) << lead;
  const std::string none = verdict_paragraph(unexplained(0.05));
  EXPECT_EQ(none.find("a lead"), std::string::npos) << none;
  EXPECT_NE(none.find("outside the candidates"), std::string::npos) << none;
}
