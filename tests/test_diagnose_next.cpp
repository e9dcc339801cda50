// The next experiment (next_experiment.h), on its pure parts: the conditions proposed beyond and between the
// table's, the merge of a second base's conditions, and the order of the proposals (a condition the table
// already has first unless a new one is clearly better).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "diagnose/next_experiment.h"

using namespace wetdem::diagnose;

// The next experiment proposes conditions beyond and between the table's, in the table's units, then another
// speed and a longer run.
TEST(DiagnoseVerdict, NextExperimentProposesConditionsBeyondTheTable) {
  auto cond = [](const std::string& w, double si) {
    Condition c;
    c.values = {{"liquid.content", w, "\"" + w + "\"", si}};
    c.label = "liquid.content=" + w;
    return c;
  };
  const std::vector<Condition> table = {cond("0 %", 0.0), cond("5 %", 0.05), cond("10 %", 0.10)};
  const std::vector<Condition> p = propose_conditions(table, table[2], 30.0, 3.0, 10);
  std::vector<std::string> labels;
  for (const Condition& c : p) labels.push_back(c.label);
  ASSERT_GE(labels.size(), 5u);
  EXPECT_EQ(labels[0], "liquid.content=15 %");
  EXPECT_EQ(labels[1], "drum.rpm=60, liquid.content=10 %");
  EXPECT_EQ(labels[2], "drum.rpm=15, liquid.content=10 %");
  EXPECT_EQ(labels[3], "liquid.content=10 %, run.duration=12 s");
  EXPECT_EQ(labels[4], "liquid.content=2.5 %");
  EXPECT_EQ(propose_conditions(table, table[2], 30.0, 3.0, 2).size(), 2u);
  // Around a second base (the camera's best condition when an assay moved the first): the conditions the
  // first lacks, at most the count asked, after the first's.
  const std::vector<Condition> around_low = propose_conditions(table, table[1], 30.0, 3.0, 10);
  const std::vector<Condition> both = merge_conditions(p, around_low, 2);
  ASSERT_EQ(both.size(), p.size() + 2);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(both[i].label, p[i].label);
  EXPECT_EQ(both[p.size()].label, "drum.rpm=60, liquid.content=5 %");
  EXPECT_EQ(both[p.size() + 1].label, "drum.rpm=15, liquid.content=5 %");
  EXPECT_EQ(merge_conditions(p, p, 3).size(), p.size()) << "nothing twice";
}

// The next experiment's order: a condition of the table wins unless a new one separates the pair by more than
// kNewConditionFactor (5 %) as much; otherwise the larger separation first, ties in their given order.
TEST(DiagnoseVerdict, NextExperimentPrefersAConditionTheTableHasUnlessANewOneIsClearlyBetter) {
  const auto q = [](const std::string& cond, double sep, bool in_table) {
    Proposal p;
    p.condition = cond, p.observable = "liquid_free_fraction", p.separation = sep, p.in_table = in_table;
    return p;
  };
  // The absorption-weak case: 9.98 sigma at a new 1.25 % against 9.96 at the table's 2.5 %.
  std::vector<Proposal> v = {q("1.25 %", 9.98, false), q("2.5 %", 9.96, true), q("7.5 %", 3.0, false)};
  rank_proposals(v);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].condition, "2.5 %") << "within 5 %: the sample the lab already has";
  EXPECT_EQ(v[1].condition, "1.25 %");
  EXPECT_EQ(v[2].condition, "7.5 %");
  // A new condition 6 % better wins.
  v = {q("2.5 %", 10.0, true), q("1.25 %", 10.6, false)};
  rank_proposals(v);
  EXPECT_EQ(v[0].condition, "1.25 %");
  // Exactly at the factor: not more, so the table's condition keeps first place (stable, table first).
  v = {q("2.5 %", 10.0, true), q("1.25 %", 10.5, false)};
  rank_proposals(v);
  EXPECT_EQ(v[0].condition, "2.5 %");
  // Without the preference (factor 1) the larger separation wins, and equal ones keep their order.
  v = {q("2.5 %", 9.96, true), q("1.25 %", 9.98, false), q("5 %", 9.98, false)};
  rank_proposals(v, 1.0);
  EXPECT_EQ(v[0].condition, "1.25 %");
  EXPECT_EQ(v[1].condition, "5 %");
  EXPECT_EQ(v[2].condition, "2.5 %");
  // Among the table's own conditions the factor cancels: the larger separation first.
  v = {q("5 %", 2.0, true), q("10 %", 3.0, true)};
  rank_proposals(v);
  EXPECT_EQ(v[0].condition, "10 %");
}
