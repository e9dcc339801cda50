// The measurements a report asks for (report.h, asked_measurements): the list report.md's checklist, the
// diagnosis.json "measure_next" and scripts/twin_measure.py read. Each rule is checked against the paragraph
// that states it (every listed measurement is one the paragraph names, and how often), so the two cannot
// part.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnose/next_experiment.h"
#include "diagnose/power.h"
#include "diagnose/report.h"

using namespace wetdem::diagnose;

namespace {

// A report with three table cells of aor_deg_mean (σ 0.8, 1.0, 1.4: median 1.0) and one of surface velocity.
Report base_report() {
  static DiagnosisSpec spec;
  Report r;
  r.spec = &spec;
  r.cells.resize(4);
  r.gaps.resize(4);
  r.cell_condition = {"liquid.content=0 %", "liquid.content=5 %", "liquid.content=10 %",
                      "liquid.content=10 %"};
  const double sigma[] = {0.8, 1.4, 1.0, 0.02};
  for (size_t k = 0; k < 4; ++k) {
    r.cells[k].observable = k < 3 ? "aor_deg_mean" : "surface_velocity_mps";
    r.cells[k].sigma = sigma[k];
  }
  r.verdict.kind = "no_gap";
  return r;
}

// cohesion chosen, with its fresh runs made (what the paragraph of an `effect` verdict reads).
Report chosen_report() {
  Report r = base_report();
  r.verdict.kind = "effect";
  r.verdict.effect = "cohesion";
  Candidate c;
  c.effect = "cohesion";
  c.fit.strength = 0.02;
  r.verdict.ranking = {c};
  r.verdict.held_out_shrink = r.verdict.held_out_gap_shrink = 0.8;
  r.fresh.resize(1);
  r.fresh[0].effect = "cohesion";
  r.fresh[0].after.resize(4);
  r.fresh[0].gaps_after.resize(4);
  return r;
}

Reach unseen(const std::string& effect, const std::string& condition, double z, size_t repeats) {
  Reach x;
  x.effect = effect;
  x.strongest = 0.1, x.max_z = 1.2, x.cell = 0;
  x.beyond_tried = {condition, "liquid.content=15 %"};
  x.beyond_condition = condition, x.beyond_observable = "aor_deg_mean";
  x.beyond_z = z, x.beyond_seeds = 2, x.beyond_repeats = repeats;
  return x;
}

Proposal proposal(const std::string& condition, const std::string& observable, double separation,
                  double sigma) {
  Proposal q;
  q.condition = condition, q.observable = observable, q.separation = separation, q.sigma = sigma;
  q.model_a = 0.5, q.model_b = 0.5 + separation * sigma, q.seeds = 2;
  return q;
}

// Every listed measurement is named in the paragraph, with its count when it is made more than once.
void expect_in_paragraph(const Report& r) {
  const std::string text = verdict_paragraph(r);
  for (const AskedMeasurement& m : asked_measurements(r)) {
    EXPECT_NE(text.find(m.observable), std::string::npos) << m.observable << "\n" << text;
    EXPECT_NE(text.find(m.condition), std::string::npos) << m.condition << "\n" << text;
    if (m.repeats > 1) {
      EXPECT_NE(text.find(std::to_string(m.repeats) + " times**"), std::string::npos) << text;
    }
  }
}

}  // namespace

// Where an unseen candidate would show: once where one measurement reaches 3 σ, k times where only the
// measurement's noise hides it, not at all where the runs' own error does; a visible candidate asks nothing.
// The noise is the table's median σ of the observable (what the report assumed).
TEST(DiagnoseAsked, AnUnseenCandidateIsMeasuredWhereItWouldShow) {
  Report r = base_report();
  Reach seen = unseen("cohesion", "liquid.content=2.5 %", 5.0, 0);
  seen.visible = true;
  r.reach = {unseen("viscous", "liquid.content=20 %", 1.8, 4),
             unseen("hysteresis", "liquid.content=15 %", 1.2, 0),
             unseen("evaporation", "liquid.content=2.5 %", 3.4, 0), seen};
  const std::vector<AskedMeasurement> a = asked_measurements(r);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].reason, "reach");
  EXPECT_EQ(a[0].effect, "viscous");
  EXPECT_EQ(a[0].condition, "liquid.content=20 %");
  EXPECT_EQ(a[0].repeats, 4u);
  EXPECT_DOUBLE_EQ(a[0].sigma, 1.0);
  EXPECT_EQ(a[1].effect, "evaporation");
  EXPECT_EQ(a[1].repeats, 1u);
  EXPECT_DOUBLE_EQ(a[1].separation, 3.4);
  expect_in_paragraph(r);
  const std::string md = asked_markdown(r);
  EXPECT_NE(
      md.find("| see `viscous` (at eta (Pa s) = 0.1) | `aor_deg_mean` | liquid.content=20 % | 4 | 1 | 1.8 |"),
      std::string::npos)
      << md;
  r.reach.clear();
  EXPECT_TRUE(asked_measurements(r).empty());
  EXPECT_EQ(asked_markdown(r), "");  // no section when nothing is asked
}

// An open interval: the best measurement when it bounds by 2 σ; else the one that does when repeated (the
// fewest repeats on the baseline's seeds); else nothing, and the paragraph says the interval stays open.
TEST(DiagnoseAsked, AnOpenIntervalAsksForTheMeasurementThatBoundsIt) {
  Report r = chosen_report();
  r.bound.effect = "cohesion", r.bound.closed = 0.02, r.bound.open = 0.1, r.bound.above = true,
  r.bound.seeds = 2;
  r.bound.proposals = {proposal("liquid.content=15 %", "aor_deg_mean", 3.7, 1.0)};
  std::vector<AskedMeasurement> a = asked_measurements(r);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].reason, "bound");
  EXPECT_EQ(a[0].repeats, 1u);
  EXPECT_DOUBLE_EQ(a[0].separation, 3.7);
  expect_in_paragraph(r);
  r.bound.proposals = {proposal("liquid.content=15 %", "aor_deg_mean", 1.8, 1.0),
                       proposal("liquid.content=20 %", "aor_deg_mean", 1.5, 1.0)};
  r.bound.proposals[0].repeats = 3, r.bound.proposals[1].repeats = 2;
  a = asked_measurements(r);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].condition, "liquid.content=20 %");  // the fewest repeats
  EXPECT_EQ(a[0].repeats, 2u);
  expect_in_paragraph(r);
  r.bound.proposals[1].seeds = 1;  // one seed: a screen's number, not asked for
  a = asked_measurements(r);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].condition, "liquid.content=15 %");
  r.bound.proposals[0].repeats = r.bound.proposals[1].repeats = 0;  // the runs' own error: nothing will do
  EXPECT_TRUE(asked_measurements(r).empty());
  EXPECT_NE(verdict_paragraph(r).find("stays open"), std::string::npos);
}

// A tie: the best single measurement, made as often as it must be to decide; the pair instead when it beats
// the single one made twice (pair_beats_single). A measurement two stages ask for is listed once, for the
// first.
TEST(DiagnoseAsked, ATieAsksForItsSingleMeasurementOrItsPair) {
  Report r = base_report();
  r.verdict.kind = "effect";
  r.verdict.effect = "absorption";
  r.verdict.tied = {"evaporation"};
  Candidate a, b;
  a.effect = "absorption", b.effect = "evaporation";
  r.verdict.ranking = {a, b};
  r.next.effect_a = "absorption", r.next.effect_b = "evaporation";
  Proposal q = proposal("liquid.content=2.5 %", "liquid_free_fraction", 2.8, 0.0256);
  q.refit_separation = 1.9, q.assay = true;
  r.next.proposals = {q};
  r.next.repeats = 3;
  std::vector<AskedMeasurement> asked = asked_measurements(r);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].reason, "tie");
  EXPECT_EQ(asked[0].effect, "absorption or evaporation");
  EXPECT_EQ(asked[0].repeats, 3u);
  EXPECT_DOUBLE_EQ(asked[0].separation, 1.9);  // after re-fit
  EXPECT_TRUE(asked[0].assay);
  ProposalPair w{q, proposal("liquid.content=15 %", "liquid_free_fraction", 3.0, 0.0256), 3.7, 2.6};
  r.next.pairs = {w};  // 2.6 < √2 × 1.9: the single one
  EXPECT_EQ(asked_measurements(r).size(), 1u);
  r.next.pairs[0].refit_separation = 3.0;  // 3.0 > √2 × 1.9 and ≥ 2 σ: the pair
  asked = asked_measurements(r);
  ASSERT_EQ(asked.size(), 2u);
  EXPECT_EQ(asked[0].condition, "liquid.content=2.5 %");
  EXPECT_EQ(asked[1].condition, "liquid.content=15 %");
  EXPECT_EQ(asked[0].repeats, 1u);
  EXPECT_DOUBLE_EQ(asked[1].separation, 3.0);  // the pair's, jointly
  // The reach asks for the pair's second measurement too: listed once, for the tie.
  r.reach = {unseen("viscous", "liquid.content=15 %", 3.5, 0)};
  r.reach[0].beyond_observable = "liquid_free_fraction";
  r.spec = [] {
    static DiagnosisSpec s;
    s.assays["liquid_free_fraction"] = 0.03;
    return &s;
  }();
  asked = asked_measurements(r);
  ASSERT_EQ(asked.size(), 2u);
  EXPECT_EQ(asked[1].reason, "tie");
  r.reach[0].beyond_condition = "liquid.content=20 %";  // elsewhere: its own row, the assay's stated noise
  asked = asked_measurements(r);
  ASSERT_EQ(asked.size(), 3u);
  EXPECT_EQ(asked[2].reason, "reach");
  EXPECT_DOUBLE_EQ(asked[2].sigma, 0.03);
  EXPECT_TRUE(asked[2].assay);
}
