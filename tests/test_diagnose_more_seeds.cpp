// Would more seeds decide a tie (more_seeds.h)? The predicted separation against hand-computed sums, its
// bias correction and its limit with exact models, the decision it feeds, and what the report says.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnose/more_seeds.h"
#include "diagnose/report.h"
#include "support/paragraph_reports.h"

using namespace wetdem::diagnose;

namespace {

std::vector<Cell> table_of(std::vector<double> sigma) {
  std::vector<Cell> c(sigma.size());
  for (size_t i = 0; i < c.size(); ++i) c[i].sigma = sigma[i], c[i].observable = "aor_deg_mean";
  return c;
}

}  // namespace

TEST(MoreSeeds, ExactModelsSeparateByTheirChi2) {
  // No noise: Σ Δ² / σ² = (2/1)² + (1/0.5)² = 8, whatever the seed ratio.
  const auto cells = table_of({1.0, 0.5});
  const std::vector<Prediction> a = {{10.0, 0.0}, {3.0, 0.0}}, b = {{8.0, 0.0}, {2.0, 0.0}};
  const std::vector<double> w = {0.0, 0.0};
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, w, 0.0), 8.0);
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, w, 0.5), 8.0);
  EXPECT_DOUBLE_EQ(predicted_separation(cells, b, a, w, 0.5), 8.0) << "symmetric";
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, a, w, 0.5), 0.0) << "a model against itself";
}

TEST(MoreSeeds, TheModelsOwnNoiseIsNotASeparation) {
  // Δ̂ = 1 with Var(Δ̂) = 0.5: Δ² is estimated at 1 - 0.5 = 0.5. With σ = 1, se_a = se_b = 0.5 and R/R' = 1/2
  // the denominator is 1 + 0.5 x 0.5 = 1.25: 0.4; with exact models 0.5.
  const auto cells = table_of({1.0});
  const std::vector<Prediction> a = {{1.0, 0.5}}, b = {{0.0, 0.5}};
  const std::vector<double> w = {0.5};
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, w, 0.5), 0.4);
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, w, 0.0), 0.5);
  EXPECT_LT(predicted_separation(cells, a, b, w, 1.0), predicted_separation(cells, a, b, w, 0.5))
      << "fewer seeds, more noise in the comparison";
  // A difference within the models' noise predicts nothing, never a negative χ².
  const std::vector<Prediction> close = {{0.3, 0.5}};
  EXPECT_DOUBLE_EQ(predicted_separation(cells, close, b, w, 0.5), 0.0);
  // Runs that share their seeds differ less than their own noise: the same Δ̂ with a small paired variance is
  // a separation.
  EXPECT_DOUBLE_EQ(predicted_separation(cells, close, b, {0.01}, 0.0), 0.09 - 0.01);
}

TEST(MoreSeeds, CellsWithoutBothPredictionsAreLeftOut) {
  const auto cells = table_of({1.0, 1.0, 1.0});
  const std::vector<Prediction> a = {{2.0, 0.0}, {std::nan(""), 0.0}, {5.0, 0.0}};
  const std::vector<Prediction> b = {{0.0, 0.0}, {1.0, 0.0}};  // the third cell missing
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, {0.0, 0.0, 0.0}, 0.5), 4.0);
  EXPECT_DOUBLE_EQ(predicted_separation(cells, a, b, {std::nan(""), 0.0, 0.0}, 0.5), 0.0) << "no variance";
}

TEST(MoreSeeds, PairedDifferencesGiveTheVarianceOfTheirMean) {
  // Two seeds, one cell: differences 3 - 1 = 2 and 5 - 4 = 1, mean 1.5, sample variance 0.5, over R = 2:
  // 0.25. With two seeds Δ̂² - w is the product of the two differences (2.25 - 0.25 = 2): unbiased when they
  // are.
  const std::vector<std::vector<Prediction>> a = {{{3.0, 0.0}}, {{5.0, 0.0}}},
                                             b = {{{1.0, 0.0}}, {{4.0, 0.0}}};
  const std::vector<double> w = paired_difference_variance(a, b);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_DOUBLE_EQ(w[0], 0.25);
  const std::vector<Prediction> ma = {{4.0, 1.0}}, mb = {{2.5, 1.5}};
  EXPECT_DOUBLE_EQ(predicted_separation(table_of({1.0}), ma, mb, w, 0.0), 2.0);
  // Runs that move together (the same seed's luck in both) leave a small variance whatever each one's spread.
  const std::vector<std::vector<Prediction>> c = {{{10.0, 0.0}}, {{20.0, 0.0}}},
                                             d = {{{9.0, 0.0}}, {{19.0, 0.0}}};
  EXPECT_DOUBLE_EQ(paired_difference_variance(c, d)[0], 0.0);
  // One seed: no variance to be had.
  EXPECT_TRUE(std::isnan(paired_difference_variance({a[0]}, {b[0]})[0]));
}

TEST(MoreSeeds, WorthWhenSomeTieCouldBeDecidedOrSomethingElseIsOpen) {
  MoreSeeds m;
  m.from = 2, m.to = 4;
  TieOutlook sinks;
  sinks.effect = "evaporation", sinks.known = true, sinks.at_more = 1.5, sinks.exact = 2.0,
  sinks.margin = 5.2;
  m.ties = {sinks};
  EXPECT_FALSE(m.worth()) << "the fitted models too close for the margin at 4 seeds";
  TieOutlook unknown;
  unknown.effect = "spread";  // no fresh runs to estimate from: escalate as before
  m.ties.push_back(unknown);
  EXPECT_TRUE(m.worth());
  m.ties = {sinks};
  m.other = {"`absorption` unconfirmed"};
  EXPECT_TRUE(m.worth()) << "the chosen effect's confirmation is open";
  m.other.clear();
  m.ties[0].at_more = 5.2;
  EXPECT_TRUE(m.worth()) << "at the margin";
}

TEST(MoreSeeds, TheReportSaysWhetherMoreSeedsCouldDecide) {
  Report r = wetdem::test::tie_with_fresh_runs("effect", "absorption", 12.7, "evaporation", 16.7, 0.3);
  r.verdict.held_by_luck = {"evaporation"};
  r.verdict.seed_luck = 10.4;
  const std::string before = verdict_paragraph(r);
  EXPECT_NE(before.find("would lower that luck and could decide it."), std::string::npos) << before;
  EXPECT_EQ(before.find("More seeds"), std::string::npos) << "no outlook, no claim";

  // One fingerprint: no number of seeds reaches the margin.
  r.more_seeds.from = 2, r.more_seeds.to = 4;
  TieOutlook t;
  t.effect = "evaporation", t.known = true, t.at_more = 1.2, t.exact = 1.9, t.margin = 5.2;
  r.more_seeds.ties = {t};
  const std::string futile = verdict_paragraph(r);
  EXPECT_NE(futile.find("Lower luck alone is unlikely to decide it (below)."), std::string::npos) << futile;
  EXPECT_EQ(futile.find("could decide it."), std::string::npos) << futile;
  EXPECT_NE(
      futile.find("**More seeds alone are unlikely to decide the tie:** by the fitted models' fresh runs, "
                  "the table would separate `absorption` from `evaporation` by a χ² of 1.2 at 4 seeds per "
                  "condition (1.9 with exact models) against a tie margin of 5.2, by no number of seeds up "
                  "to 64: the two fitted models leave one fingerprint on what this table measures. More "
                  "seeds also re-fit both models"),
      std::string::npos)
      << futile;
  EXPECT_EQ(futile.find("did not run again"), std::string::npos) << "the file did not hold it back";
  // Reached at more seeds than the outlook's, and held back by the file.
  r.more_seeds.ties[0].exact = 12.8, r.more_seeds.ties[0].seeds_needed = 6;
  r.escalation_held_back = true;
  const std::string later = verdict_paragraph(r);
  EXPECT_NE(
      later.find("against a tie margin of 5.2, reached from about 6 seeds, so the diagnosis did not run "
                 "again at 4 seeds (`escalate_when = \"decidable\"`)."),
      std::string::npos)
      << later;

  r.escalation_held_back = false;
  r.more_seeds.ties[0].at_more = 9.0;
  r.more_seeds.ties[0].exact = 12.0;
  const std::string could = verdict_paragraph(r);
  EXPECT_NE(
      could.find("**More seeds could decide the tie:** by the fitted models' fresh runs, the table would "
                 "separate `absorption` from `evaporation` by a χ² of 9.0 at 4 seeds per condition (12.0 "
                 "with exact models) against a tie margin of 5.2 (the expected"),
      std::string::npos)
      << could;
  EXPECT_NE(could.find("`escalate_replicates = 4`"), std::string::npos) << could;
  EXPECT_NE(could.find("would lower that luck and could decide it."), std::string::npos) << could;
}
