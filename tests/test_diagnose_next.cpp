// The next experiment (next_experiment.h), on its pure parts: the conditions proposed beyond and between the
// table's, the merge of a second base's conditions, and the order of the proposals (a condition the table
// already has first unless a new one is clearly better), and the separation left once each model re-fits.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "diagnose/next_bound.h"
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
  ASSERT_EQ(labels.size(), 7u);
  EXPECT_EQ(labels[0], "liquid.content=15 %");
  EXPECT_EQ(labels[1], "drum.rpm=60, liquid.content=10 %");
  EXPECT_EQ(labels[2], "drum.rpm=15, liquid.content=10 %");
  EXPECT_EQ(labels[3], "liquid.content=10 %, run.duration=12 s");
  EXPECT_EQ(labels[4], "liquid.content=20 %") << "two steps past, before the midpoints";
  EXPECT_EQ(labels[5], "liquid.content=2.5 %");
  EXPECT_EQ(labels[6], "liquid.content=7.5 %");
  EXPECT_EQ(propose_conditions(table, table[2], 30.0, 3.0, 2).size(), 2u);
  // Uneven steps: the step is the gap between the two largest values (10 - 4), in the table's unit.
  const std::vector<Condition> uneven = {cond("0 %", 0.0), cond("4 %", 0.04), cond("10 %", 0.10)};
  const std::vector<Condition> pu = propose_conditions(uneven, uneven[2], 30.0, 3.0, 10);
  ASSERT_GE(pu.size(), 5u);
  EXPECT_EQ(pu[0].label, "liquid.content=16 %");
  EXPECT_EQ(pu[4].label, "liquid.content=22 %");
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

// A drum speed beyond the table stays where a laboratory measures a free surface: at most max_froude
// (Fr = ω²R/g). The 60 mm drum's critical speed (Fr = 1) is 42.3/√D rpm = 172.7 rpm; after a 120 rpm row
// the steps past (180 and 240 rpm) centrifuge and are not proposed, the midpoints are.
TEST(DiagnoseVerdict, NextExperimentProposesNoDrumSpeedPastTheFroudeLimit) {
  constexpr double kRpm = 2.0 * 3.14159265358979323846 / 60.0;
  EXPECT_NEAR(max_drum_omega(0.03, 1.0) / kRpm, 42.3 / std::sqrt(0.06), 0.1);
  EXPECT_NEAR(max_drum_omega(0.03, 0.5) / kRpm, 122.1, 0.1);
  EXPECT_TRUE(std::isinf(max_drum_omega(0.0, 0.5))) << "no radius, no limit";
  auto cond = [&](double rpm) {
    Condition c;
    const std::string w = fmt::format("{:g}", rpm);
    c.values = {{"drum.rpm", w, w, rpm * kRpm}};
    c.label = "drum.rpm=" + w;
    return c;
  };
  const std::vector<Condition> table = {cond(30), cond(60), cond(120)};
  const auto labels = [](const std::vector<Condition>& cs) {
    std::vector<std::string> l;
    for (const Condition& c : cs) l.push_back(c.label);
    return l;
  };
  const std::vector<std::string> free = labels(propose_conditions(table, table[2], 30.0, 3.0, 10));
  EXPECT_EQ(free, (std::vector<std::string>{"drum.rpm=180", "drum.rpm=120, run.duration=12 s", "drum.rpm=240",
                                            "drum.rpm=45", "drum.rpm=90"}));
  const std::vector<std::string> capped =
      labels(propose_conditions(table, table[2], 30.0, 3.0, 10, max_drum_omega(0.03, 0.5)));
  EXPECT_EQ(capped,
            (std::vector<std::string>{"drum.rpm=120, run.duration=12 s", "drum.rpm=45", "drum.rpm=90"}));
  // Without a speed key the model's speed doubled, unless that passes the limit; halved always.
  Condition c10;
  c10.values = {{"liquid.content", "10 %", "\"10 %\"", 0.10}};
  c10.label = "liquid.content=10 %";
  Condition c5 = c10;
  c5.values[0] = {"liquid.content", "5 %", "\"5 %\"", 0.05};
  c5.label = "liquid.content=5 %";
  const std::vector<std::string> fast =
      labels(propose_conditions({c5, c10}, c10, 100.0, 3.0, 10, max_drum_omega(0.03, 0.5)));
  EXPECT_EQ(std::count(fast.begin(), fast.end(), "drum.rpm=200, liquid.content=10 %"), 0);
  EXPECT_EQ(std::count(fast.begin(), fast.end(), "drum.rpm=50, liquid.content=10 %"), 1);
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

// The refit separation (refit_rise), on two liquid sinks a table of camera cells cannot tell apart. A
// saturating sink of capacity c leaves 1 - c/phi of the liquid free at content phi; a steady one leaves the
// same fraction 1 - s at every content. Both fit the table (one cell that neither moves); the truth (the
// steady sink at s = 0.5) leaves half the liquid free at 15 % and 30 %, the saturating one fitted at c = 0.05
// predicts 0.667 and 0.833 there. One free-liquid value separates the fitted models by 5.6 sigma, but either
// model re-fits its strength to match it: the single measurement separates nothing. Two contents together
// cannot both be matched by one fraction: the steady sink re-fitted to the saturating one's pair (0.667,
// 0.833) is best at 0.75 and leaves 2 (0.083/0.03)² = 15.4, the saturating one re-fitted to the steady one's
// pair leaves 55.6; the pair separates them by sqrt(min) = 3.93 sigma. A rival whose response at the new cell
// does not depend on its strength cannot re-fit at all: its rise is the plain z² exactly.
TEST(DiagnoseVerdict, TheRefitSeparationLetsEachModelRefitToTheOthersValue) {
  const double sigma = 0.03;
  const std::vector<Cell> table = {{{}, "aor_deg_mean", 30.0, 1.0}};
  const std::vector<Prediction> baseline = {{30.0, 0.0}};
  const std::vector<double> caps = {0.01, 0.03, 0.1}, fractions = {0.1, 0.3, 0.7};
  const auto response = [&](const std::string& effect, const std::vector<double>& strengths) {
    Response r;
    r.effect = effect;
    r.strengths = strengths;
    for (size_t k = 0; k < strengths.size(); ++k) r.pred.push_back({{30.0, 0.0}});
    return r;
  };
  const Response saturating = response("absorption", caps), steady = response("evaporation", fractions);
  // The extra free-liquid cell at content phi, observed y (the other model's value), with the rival's null
  // (all liquid free) and its knots there.
  const auto extra = [&](double y, const std::vector<double>& knots) {
    ExtraMeasurement e;
    e.cell = {{}, "liquid_free_fraction", y, sigma};
    e.null = {1.0, 0.0};
    for (double x : knots) e.knots.push_back({x, 0.0});
    return e;
  };
  const auto saturating_at = [&](double phi) {
    std::vector<double> v;
    for (double c : caps) v.push_back(1.0 - c / phi);
    return v;
  };
  const std::vector<double> steady_knots = {0.9, 0.7, 0.3};  // 1 - s at every content
  const double sat15 = 1.0 - 0.05 / 0.15, sat30 = 1.0 - 0.05 / 0.30;
  // One measurement at 15 %: each re-fits to the other's value.
  const double rise_sat = refit_rise(table, baseline, saturating, {extra(0.5, saturating_at(0.15))});
  const double rise_steady = refit_rise(table, baseline, steady, {extra(sat15, steady_knots)});
  EXPECT_LT(rise_sat, 0.01);
  EXPECT_LT(rise_steady, 0.01);
  EXPECT_LT(refit_separation(rise_sat, rise_steady), 0.1);
  // Both contents together.
  const double pair_sat = refit_rise(table, baseline, saturating,
                                     {extra(0.5, saturating_at(0.15)), extra(0.5, saturating_at(0.30))});
  const double pair_steady =
      refit_rise(table, baseline, steady, {extra(sat15, steady_knots), extra(sat30, steady_knots)});
  EXPECT_NEAR(pair_steady, 2.0 * std::pow((sat30 - sat15) / 2.0 / sigma, 2), 0.01);
  EXPECT_NEAR(pair_sat, 55.56, 0.1);
  EXPECT_NEAR(refit_separation(pair_sat, pair_steady), 3.93, 0.01);
  // A rival that cannot move the new cell: the plain z², whatever the table.
  const double fixed = refit_rise(table, baseline, saturating, {extra(0.5, {sat15, sat15, sat15})});
  EXPECT_NEAR(fixed, std::pow((sat15 - 0.5) / sigma, 2), 1e-9);
  EXPECT_THROW(refit_rise(table, baseline, saturating, {extra(0.5, {0.5})}), std::invalid_argument)
      << "knots that do not match the response's strengths";
  // The pair is the better experiment: more than the single measurement made twice.
  Proposal single;
  single.separation = std::fabs(sat15 - 0.5) / sigma;
  single.refit_separation = refit_separation(rise_sat, rise_steady);
  ProposalPair pair{single, single, std::hypot(single.separation, single.separation),
                    refit_separation(pair_sat, pair_steady)};
  EXPECT_TRUE(pair_beats_single(pair, single));
  single.refit_separation = 3.0;  // a single measurement that survives the re-fit: a pair must beat 4.24
  EXPECT_FALSE(pair_beats_single(pair, single));
  // Twice as good as a single one that cannot decide, but undecided itself (the micro twin: 1.1 against 0.7).
  single.refit_separation = 0.7;
  pair.refit_separation = 1.1;
  EXPECT_FALSE(pair_beats_single(pair, single));
}

// Proposals whose refit separation is known rank by it, before those without one.
TEST(DiagnoseVerdict, NextExperimentRanksByTheSeparationLeftAfterTheRefit) {
  const auto q = [](const std::string& cond, double sep, double refit) {
    Proposal p;
    p.condition = cond, p.observable = "liquid_free_fraction", p.separation = sep, p.refit_separation = refit;
    return p;
  };
  std::vector<Proposal> v = {q("15 %", 6.9, 0.4), q("20 %", 4.1, 2.5), q("2.5 %", 1.0, std::nan("")),
                             q("10 %", 3.0, 2.0)};
  rank_proposals(v);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[0].condition, "20 %");
  EXPECT_EQ(v[1].condition, "10 %");
  EXPECT_EQ(v[2].condition, "15 %") << "the largest plain separation, matched by a re-fit";
  EXPECT_EQ(v[3].condition, "2.5 %") << "no refit separation: after every proposal with one";
}

// The separation a measurement needs to decide the tie on fresh runs: √ of fresh_tie's margin.
TEST(DiagnoseVerdict, TheNextExperimentKnowsWhatTheVerdictNeeds) {
  VerdictRule rule;  // tie_delta 4
  EXPECT_NEAR(needed_separation(30.0, 50, rule, 0.0), 2.0, 1e-12) << "χ²/n below 1: tie_delta alone";
  EXPECT_NEAR(needed_separation(100.0, 50, rule, 0.0), std::sqrt(8.0), 1e-12) << "scatter past χ²/n = 1";
  EXPECT_NEAR(needed_separation(34.1, 50, rule, 16.1), std::sqrt(16.1), 1e-12)
      << "evaporation-strong: the model's own seed luck";
  // The rule it mirrors: a rise just short of the margin stays tied, just past it does not.
  const double need = needed_separation(34.1, 50, rule, 16.1);
  EXPECT_TRUE(fresh_tie(34.1, 34.1 + need * need - 0.01, 50, rule, 16.1));
  EXPECT_FALSE(fresh_tie(34.1, 34.1 + need * need + 0.01, 50, rule, 16.1));
}

// A rival with a second parameter re-fits over its members: a rate whose response can match the new value
// takes the re-fit at the price of its own table χ²; a member whose response there is not known cannot.
TEST(DiagnoseVerdict, TheRefitSeparationProfilesTheRivalsSecondParameter) {
  const std::vector<Cell> table = {{{}, "aor_deg_mean", 30.0, 1.0}};
  const std::vector<Prediction> baseline = {{30.0, 0.0}};
  const auto response = [](double table_value) {
    Response r;
    r.effect = "absorption";
    r.strengths = {0.01, 0.03, 0.1};
    for (size_t k = 0; k < 3; ++k) r.pred.push_back({{table_value, 0.0}});
    return r;
  };
  // The fitted rate fits the table exactly and cannot move the new cell; the other rate fits the table
  // 1 worse (its AoR one σ off at every strength) and spans the new value.
  const Response fitted = response(30.0), other = response(31.0);
  ExtraMeasurement stuck, spans;
  stuck.cell = spans.cell = {{}, "liquid_free_fraction", 0.5, 0.03};
  stuck.null = spans.null = {1.0, 0.0};
  stuck.knots = {{0.667, 0.0}, {0.667, 0.0}, {0.667, 0.0}};
  spans.knots = {{0.9, 0.0}, {0.7, 0.0}, {0.3, 0.0}};
  const double z2 = std::pow((0.667 - 0.5) / 0.03, 2);
  std::vector<RivalMember> family = {{&baseline, &fitted, {stuck}, true}, {&baseline, &other, {spans}, true}};
  EXPECT_NEAR(refit_rise(table, family), 1.0, 1e-6) << "the other rate re-fits, at its table price";
  EXPECT_NEAR(refit_rise(table, {family[0]}), z2, 1e-9) << "alone, the fitted rate pays the plain z²";
  family[1].known = false;
  EXPECT_NEAR(refit_rise(table, family), z2, 1e-9) << "a member not run there cannot take the re-fit";
  family[0].known = false;
  EXPECT_TRUE(std::isnan(refit_rise(table, family))) << "no member known";
}

// The ends of an interval the table leaves open (next_bound.h): the closed end the data fix and the end of
// the probed range it runs into; none for a closed interval or one whose ends are too close to be worth a
// measurement.
TEST(DiagnoseVerdict, AnOpenIntervalHasAClosedAndAnOpenEnd) {
  StrengthFit f;
  f.strength = 0.3, f.lo = 0.0616, f.hi = 0.3;
  EXPECT_FALSE(open_interval(f).has_value()) << "a closed interval";
  f.open_hi = true;  // absorption-slow's capacity: 0.3 (0.0616 and above)
  auto o = open_interval(f);
  ASSERT_TRUE(o.has_value());
  EXPECT_TRUE(o->above);
  EXPECT_FALSE(o->both);
  EXPECT_DOUBLE_EQ(o->closed, 0.0616);
  EXPECT_DOUBLE_EQ(o->open, 0.3);
  f.open_hi = false, f.open_lo = true;  // open below: strength <= 0.3
  o = open_interval(f);
  ASSERT_TRUE(o.has_value());
  EXPECT_FALSE(o->above);
  EXPECT_DOUBLE_EQ(o->closed, 0.3);
  EXPECT_DOUBLE_EQ(o->open, 0.0616);
  f.open_hi = true;  // not determined: from the weakest to the strongest
  o = open_interval(f);
  ASSERT_TRUE(o.has_value());
  EXPECT_TRUE(o->both);
  EXPECT_DOUBLE_EQ(o->closed, 0.0616);
  f.lo = 0.25;  // within kMinOpenRatio of each other: nothing worth measuring
  EXPECT_FALSE(open_interval(f).has_value());
  f.lo = 0.0;  // no positive end to run
  EXPECT_FALSE(open_interval(f).has_value());
}

// How often a measurement must be repeated for two predictions to lie `target` σ apart: the smallest k with
// |Δ| / √(σ²/k + se²) ≥ target, checked against the formula itself; none where the runs' own error alone
// holds them closer, or where more than kMaxRepeats would be needed.
TEST(DiagnoseVerdict, RepeatsShrinkTheMeasurementsNoiseNotTheRuns) {
  const auto sep = [](double d, double s, double se2, size_t k) {
    return std::fabs(d) / std::sqrt(s * s / k + se2);
  };
  // cohesion-weak's bound: 1.8 σ in one measurement (Δ = 1.8, σ = 1, no run error) → 2 repeats (2.55 σ).
  EXPECT_EQ(repeats_for(1.8, 1.0, 0.0, 2.0), 2u);
  EXPECT_EQ(repeats_for(-1.8, 1.0, 0.0, 2.0), 2u) << "the sign of the difference does not matter";
  EXPECT_EQ(repeats_for(2.5, 1.0, 0.0, 2.0), 1u) << "one measurement already does";
  // With run error: Δ = 1, σ = 0.5, se² = 0.1 → k = 0.25 / (0.25 − 0.1) = 1.67 → 2.
  EXPECT_EQ(repeats_for(1.0, 0.5, 0.1, 2.0), 2u);
  for (double d : {0.3, 0.9, 1.7, 4.0})
    for (double se2 : {0.0, 0.01, 0.05})
      if (const size_t k = repeats_for(d, 0.4, se2, 3.0)) {
        EXPECT_GE(sep(d, 0.4, se2, k), 3.0 - 1e-12) << d << " " << se2;
        if (k > 1) {
          EXPECT_LT(sep(d, 0.4, se2, k - 1), 3.0) << "not the smallest: " << d << " " << se2;
        }
      } else {
        EXPECT_LT(sep(d, 0.4, se2, kMaxRepeats), 3.0) << "kMaxRepeats would do: " << d << " " << se2;
      }
  EXPECT_EQ(repeats_for(1.0, 1.0, 0.25, 2.0), 0u) << "the runs' own error alone holds Δ at 2 σ";
  EXPECT_EQ(repeats_for(0.5, 1.0, 0.0, 2.0), 16u) << "exactly 2 σ at 16 repeats";
  EXPECT_EQ(repeats_for(0.49, 1.0, 0.0, 2.0), 0u) << "17 would be needed: none";
}

// A new measurement's noise at a condition where the runs spread more than at the table's typical cell
// (sigma_at). A table made as a laboratory makes it: each row the mean of n = 2 runs with per-run sd s_k,
// plus an instrument noise σ_i = 0.01, so σ_k² = σ_i² + s_k²/2; the model's SE over its R = 2 seeds is
// s_k/√2. At a new condition whose runs spread with s_c = 0.045, a measurement's sd is √(σ_i² + s_c²/2) =
// 0.0334: sigma_at recovers it from the table and the model's SEs alone, where the table's median σ (0.0146)
// is 2.3× short.
TEST(DiagnoseVerdict, ANewMeasurementCarriesTheSpreadOfTheRunsThere) {
  const double si = 0.01;
  std::vector<Cell> cells;
  std::vector<double> se2;
  for (double s : {0.01, 0.015, 0.02, 0.015, 0.01, 0.02}) {
    Cell c;
    c.observable = "surface_velocity_mps";
    c.sigma = std::sqrt(si * si + s * s / 2);
    cells.push_back(c);
    se2.push_back(s * s / 2);
  }
  MeasurementNoise n;
  n.sigma = median_sigma(cells);
  std::vector<Cell> se_cells = cells;
  for (size_t k = 0; k < cells.size(); ++k) se_cells[k].sigma = se2[k];
  n.typical_se2 = median_sigma(se_cells);
  const double sc = 0.045, se_c = sc / std::sqrt(2.0);
  const double truth = std::sqrt(si * si + sc * sc / 2);
  EXPECT_NEAR(sigma_at(n, "surface_velocity_mps", se_c, se_c), truth, 1e-12);
  EXPECT_LT(n.sigma.at("surface_velocity_mps"), truth / 2);
  // The separation counts it: a shift of 0.08 is 1.69 σ against the median, 1.43 σ against what a measurement
  // there carries.
  const Prediction x{0.10, se_c}, y{0.02, se_c};
  EXPECT_NEAR(separation_of(n, "surface_velocity_mps", x, y),
              0.08 / std::sqrt(truth * truth + 2 * se_c * se_c), 1e-12);
  EXPECT_NEAR(separation_of(n, "surface_velocity_mps", x, y), 1.428, 1e-3);
  // A calmer condition is not trusted to be quieter; an observable without a typical SE (an assay) keeps σ.
  EXPECT_DOUBLE_EQ(sigma_at(n, "surface_velocity_mps", 0.001, 0.001), n.sigma.at("surface_velocity_mps"));
  n.sigma["liquid_free_fraction"] = 0.03;
  EXPECT_DOUBLE_EQ(sigma_at(n, "liquid_free_fraction", 0.5, 0.5), 0.03);
  // Two models spreading differently: their mean squared SE.
  EXPECT_NEAR(sigma_at(n, "surface_velocity_mps", se_c, 0.0),
              std::sqrt(n.sigma.at("surface_velocity_mps") * n.sigma.at("surface_velocity_mps") +
                        0.5 * se_c * se_c - n.typical_se2.at("surface_velocity_mps")),
              1e-12);
}

// The bound experiment asks for a repeated measurement only when no single one reaches kDecisive, and then
// the one that needs the fewest repeats.
TEST(DiagnoseVerdict, AnIntervalNoSingleMeasurementBoundsAsksForTheFewestRepeats) {
  BoundExperiment b;
  EXPECT_EQ(repeated_bound(b), nullptr);
  const auto prop = [](const std::string& cond, double sep, size_t repeats) {
    Proposal q;
    q.condition = cond, q.separation = sep, q.repeats = repeats, q.seeds = 1;
    return q;
  };
  b.proposals = {prop("a", 1.8, 2), prop("b", 1.5, 2), prop("c", 1.4, 0), prop("d", 1.0, 4)};
  ASSERT_NE(repeated_bound(b), nullptr);
  EXPECT_EQ(repeated_bound(b)->condition, "a") << "the better ranked of two with 2 repeats";
  b.proposals[0].repeats = 3;
  EXPECT_EQ(repeated_bound(b)->condition, "b");
  b.seeds = 2;  // the baseline's seeds: "a" and "b" ran on one (a first round beyond the table), "c" on two
  b.proposals = {prop("a", 1.8, 2), prop("b", 1.5, 3), prop("c", 1.4, 4), prop("d", 1.3, 5)};
  b.proposals[2].seeds = 2;
  b.proposals[3].in_table = true;  // emulated at the table's condition: counts
  EXPECT_EQ(repeated_bound(b)->condition, "c") << "a one-seed proposal is not asked for";
  EXPECT_EQ(repeated_bound(b, true)->condition, "a") << "unconfirmed: the fewest repeats";
  b.proposals[2].repeats = 6;
  EXPECT_EQ(repeated_bound(b)->condition, "d");
  b.seeds = 1;
  b.proposals = {prop("a", 2.1, 1), prop("b", 1.5, 2)};
  EXPECT_EQ(repeated_bound(b), nullptr) << "one measurement bounds it";
  b.proposals = {prop("a", 1.2, 0), prop("b", 1.1, 0)};
  EXPECT_EQ(repeated_bound(b), nullptr) << "no number of repeats would";
}

// The tie's best single measurement made k times: the difference its separation after re-fit implies, as
// repeats_for sees it; none on a screen's one-seed number, and one when it already reaches what is needed.
TEST(DiagnoseVerdict, TheTiesMeasurementIsRepeatedUntilItDecides) {
  Proposal q;
  q.sigma = 1.0, q.se_a = q.se_b = 0.0, q.separation = 3.0, q.refit_separation = 2.0, q.seeds = 2;
  EXPECT_EQ(tie_repeats(q, 4.0, 2), 4u) << "2 σ after re-fit, 4 σ needed: 2 × √4";
  EXPECT_EQ(tie_repeats(q, 2.0, 2), 1u);
  q.refit_separation = std::nan("");
  EXPECT_EQ(tie_repeats(q, 4.0, 2), 2u) << "no re-fit: the plain 3 σ, 3 × √2 = 4.2";
  q.seeds = 1;
  EXPECT_EQ(tie_repeats(q, 4.0, 2), 0u) << "one seed of two: a screen";
  q.in_table = true;
  EXPECT_EQ(tie_repeats(q, 4.0, 2), 2u) << "the table's own condition, through the emulator";
  q.se_a = q.se_b = 1.0;  // Δ = 3 √3 = 5.2; the runs' own error alone: 5.2 / √2 = 3.7 < 4
  EXPECT_EQ(tie_repeats(q, 4.0, 2), 0u);
}
