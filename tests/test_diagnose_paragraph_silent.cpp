// The verdict paragraph on what a table is silent on: how far its reach goes past the probes, the measurement
// that would bound an open interval or show an unseen candidate, and what a table without a gap rules out.
#include <gtest/gtest.h>

#include "diagnose/limits.h"
#include "diagnose/report.h"
#include "support/paragraph_reports.h"

using namespace wetdem::diagnose;
using wetdem::test::unexplained;

// What the table cannot see past the file's probes (power.h, extend_reach): a candidate that shows only at a
// strength stepped past the file's strongest probe is said with that strength, so the verdict's silence on it
// is bounded; one still unseen says why its steps stopped (the end of the range, the cost guard).
TEST(DiagnoseParagraph, TheReachPastTheProbesBoundsWhatTheVerdictIsSilentOn) {
  Report r = unexplained(0.05);
  r.verdict.kind = "no_gap";
  r.cell_condition = {"0 %, 30 rpm", "10 %, 30 rpm", "10 %, 60 rpm"};
  r.cells[2].observable = "surface_velocity_mps";
  r.cells[0].observable = "aor_deg_std";
  Reach v;
  v.effect = "viscous";
  v.strongest = 0.09, v.extended_from = 0.03, v.visible_from = 0.09;
  v.max_z = 3.4, v.at = 0.09, v.cell = 2, v.by_probes = v.visible = true;
  Reach h;
  h.effect = "hysteresis";
  h.strongest = 30, h.extended_from = 28, h.max_z = 1.2, h.cell = 0;
  h.extension_stop = "physical limit";
  Reach e;
  e.effect = "evaporation";
  e.strongest = 0.3, e.max_z = 0.8, e.cell = 0;
  e.extension_stop = "max_cost";
  r.reach = {v, h, e};
  const std::string s = verdict_paragraph(r);
  EXPECT_NE(s.find("**Seen only when strong:** `viscous` moves no cell by 3 σ up to the strongest "
                   "strength probed before, eta (Pa s) = 0.03, but does at 0.09 (3.4 σ on "
                   "surface_velocity_mps at 10 %, 60 "
                   "rpm)"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("up to theta - theta_r (deg) = 30, the end of its physical range (closest"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("up to 1/tau (1/s) = 0.3, the strongest max_cost lets run (closest"), std::string::npos)
      << s;
  // viscous shows, so it is not among what the table cannot see.
  const std::string blind =
      s.substr(s.find("cannot see:**"), s.find("**Seen only") - s.find("cannot see:**"));
  EXPECT_EQ(blind.find("`viscous`"), std::string::npos) << blind;
  EXPECT_NE(blind.find("`hysteresis`"), std::string::npos) << blind;
  // Without a step past the probes there is no such sentence.
  r.reach = {h, e};
  EXPECT_EQ(verdict_paragraph(r).find("Seen only when strong"), std::string::npos);
}

// An interval open at one side gets the measurement that would close it (next_bound.h): named when it tells
// the two ends apart by 2 σ, and said to stay open when no measurement tried does.
TEST(DiagnoseParagraph, AnOpenIntervalNamesTheMeasurementThatWouldBoundIt) {
  Report r = chosen_with_fresh_runs("effect");
  r.bound.effect = "cohesion";
  r.bound.closed = 0.0443;
  r.bound.open = 0.1;
  Proposal q{"liquid.content=15 %", "f_wet_mean", 0.61, 0.52, 0.01, 0.01, 0.02, 3.7, false, false, 2};
  r.bound.proposals = {q};
  const std::string bound = verdict_paragraph(r);
  EXPECT_NE(bound.find("**To bound `cohesion`:**"), std::string::npos) << bound;
  EXPECT_NE(bound.find("measure `f_wet_mean` at liquid.content=15 %"), std::string::npos) << bound;
  EXPECT_NE(bound.find("3.7 σ"), std::string::npos) << bound;
  EXPECT_NE(bound.find("open above"), std::string::npos) << bound;
  r.bound.proposals[0].separation = 1.2;
  const std::string open = verdict_paragraph(r);
  EXPECT_EQ(open.find("To bound"), std::string::npos) << open;
  EXPECT_NE(open.find("stays open"), std::string::npos) << open;
  EXPECT_NE(open.find("1.2 σ"), std::string::npos) << open;
  r.bound = {};  // the stage did not run: nothing said
  const std::string none = verdict_paragraph(r);
  EXPECT_EQ(none.find("stays open"), std::string::npos) << none;
  EXPECT_EQ(none.find("To bound"), std::string::npos) << none;
}

// An open interval no single measurement bounds: the paragraph asks for the one that does when repeated, how
// often, and what the ends' separation then is (cohesion-weak on the micro drum: f_wet at 15 rpm, 1.8 σ).
TEST(DiagnoseParagraph, AnIntervalOneMeasurementCannotBoundAsksForRepeats) {
  Report r = chosen_with_fresh_runs("effect");
  r.bound.effect = "cohesion";
  r.bound.closed = 0.024, r.bound.open = 0.1;
  Proposal q;
  q.condition = "drum.rpm=15", q.observable = "f_wet_mean";
  q.model_a = 0.50, q.model_b = 0.518, q.sigma = 0.01, q.seeds = 2;  // 1.8 σ in one measurement
  q.separation = 1.8, q.repeats = 2;
  r.bound.proposals = {q};
  const std::string asked = verdict_paragraph(r);
  EXPECT_NE(asked.find("measure `f_wet_mean` at drum.rpm=15 **2 times**"), std::string::npos) << asked;
  EXPECT_NE(asked.find("lie 2.5 σ apart"), std::string::npos) << asked;  // 0.018 / (0.01/√2)
  r.bound.proposals[0].repeats = 0;  // the runs' own error: no number of repeats would do
  const std::string open = verdict_paragraph(r);
  EXPECT_NE(open.find("stays open"), std::string::npos) << open;
  EXPECT_EQ(open.find("times**"), std::string::npos) << open;
}

// A candidate the table cannot see whose runs beyond the table differ from the model's by more than their own
// error, with the measurement's noise alone hiding it: the paragraph says how often to repeat that
// measurement (lubrication on the flowing drum: the AoR's standard deviation at 120 rpm, under 3 σ in one
// measurement).
TEST(DiagnoseParagraph, AnUnseenCandidateNamesTheRepeatsThatWouldShowIt) {
  Report r = unexplained(0.05);
  r.verdict.kind = "no_gap";
  r.cell_condition = {"0 %, 30 rpm", "10 %, 30 rpm", "10 %, 60 rpm"};
  r.cells[0].observable = "aor_deg_std";
  Reach v;
  v.effect = "viscous";
  v.strongest = 0.1, v.max_z = 1.4, v.cell = 0;
  v.beyond_tried = {"drum.rpm=90", "drum.rpm=120"};
  v.beyond_condition = "drum.rpm=120", v.beyond_observable = "aor_deg_std";
  v.beyond_z = 1.8, v.beyond_seeds = 4, v.beyond_repeats = 4;
  r.reach = {v};
  const std::string asked = verdict_paragraph(r);
  EXPECT_NE(
      asked.find("aor_deg_std at drum.rpm=120 moves by more than the runs' own error (1.8 σ of one "
                 "measurement at eta (Pa s) = 0.1, 4 runs each): **to see it, measure it there 4 times**"),
      std::string::npos)
      << asked;
  // One measurement shows it at 4 σ: at the strongest strength, the only one run there; a weaker one shifts
  // less, and 3 σ needs about 0.1 × 3/4 in proportion.
  r.reach[0].beyond_z = 4.0, r.reach[0].beyond_seeds = 2;
  const std::string once = verdict_paragraph(r);
  EXPECT_NE(
      once.find("**to see it, measure aor_deg_std at drum.rpm=120**, where 2 runs each of it at eta (Pa "
                "s) = 0.1 and of the model differ by 4.0 σ (a weaker one shifts less: in proportion to "
                "the strength, 3 σ there needs about 0.075)"),
      std::string::npos)
      << once;
  // Weaker strengths ran there too (run_beyond): what they measured replaces the estimate, both ways.
  r.reach[0].beyond_weaker = {{0.075, 3.3}};
  const std::string shown = verdict_paragraph(r);
  EXPECT_NE(
      shown.find(
          "(run there on the same seeds at 0.075 (3.3 σ) as well: a truth from about 0.075 shows there)"),
      std::string::npos)
      << shown;
  EXPECT_EQ(shown.find("needs about"), std::string::npos)
      << "an estimate beside the measured shift: " << shown;
  r.reach[0].beyond_weaker = {{0.075, 1.2}, {0.0866, 2.6}};
  const std::string under = verdict_paragraph(r);
  EXPECT_NE(under.find(
                "run there on the same seeds at 0.075 (1.2 σ), 0.0866 (2.6 σ), so 3 σ there needs a strength "
                "between 0.0866 and 0.1)"),
            std::string::npos)
      << under;
  r.reach[0].beyond_weaker.clear();
  r.reach[0].beyond_z = 1.8, r.reach[0].beyond_seeds = 4;
  r.reach[0].beyond_repeats = 0;  // the runs' own error hides it: no number of repeats would
  const std::string silent = verdict_paragraph(r);
  EXPECT_NE(
      silent.find("nor at 2 condition(s) beyond the table (at most 1.8 σ: aor_deg_std at drum.rpm=120)"),
      std::string::npos)
      << silent;
  EXPECT_EQ(silent.find("times**"), std::string::npos) << silent;
}

// A table without a gap says what it rules out (limits.h): a limit bracketed by runs with its interpolation,
// one under the weakest run, the shape a sink's limit holds at, and a visible candidate still allowed at its
// strongest run; a candidate the table cannot see is left to the blind sentence.
TEST(DiagnoseParagraph, NoGapSaysWhatTheTableRulesOut) {
  Report r = unexplained(0.0);
  r.verdict.kind = "no_gap";
  r.verdict.ranking.clear();
  r.gaps[1].significant = false;
  const std::string plain = verdict_paragraph(r);
  EXPECT_EQ(plain.find("rules out"), std::string::npos) << plain;
  r.limits = {limit_of("cohesion", {{0.003, 2.1}, {0.01, 41.0}}, kRuleOutDelta),
              limit_of("absorption", {{0.05, 753.4}}, kRuleOutDelta),
              limit_of("evaporation", {{0.1, 4.2}}, kRuleOutDelta),
              limit_of("viscous", {{0.1, 1.0}}, kRuleOutDelta)};
  r.limits[1].shape = 3.0;  // the sink's default rate
  for (const char* e : {"cohesion", "absorption", "evaporation", "viscous"}) {
    Reach x;
    x.effect = e;
    x.visible = std::string(e) != "viscous";
    r.reach.push_back(x);
  }
  const std::string p = verdict_paragraph(r);
  EXPECT_NE(p.find("**What this table rules out**"), std::string::npos) << p;
  EXPECT_NE(p.find("`cohesion` from w (J/m2) = 0.01 (Δχ² +41.0; 0.003 is allowed (+2.1), so the limit lies "
                   "between them, about 0.00"),
            std::string::npos)
      << p;
  EXPECT_NE(p.find("`absorption` from pore capacity (fraction of own volume) = 0.05 at rate k (1/s) = 3 "
                   "(Δχ² +753.4; no weaker strength was run; other values of the rate k (1/s) were not run)"),
            std::string::npos)
      << p;
  EXPECT_NE(p.find("Still allowed at the strongest strength run: `evaporation` (0.1, Δχ² +4.2);"),
            std::string::npos)
      << p;
  const std::string ruled = p.substr(0, p.find("cannot see"));
  EXPECT_EQ(ruled.find("`viscous`"), std::string::npos) << p;
  // A candidate the gap search sees only when strong, ruled out below that by the direct comparison: the
  // "seen only when strong" entry says so.
  r.cell_condition.assign(3, "liquid.content=5 %");
  r.limits.push_back(limit_of("scale", {{0.2, 18.1}, {0.4, 97.7}}, kRuleOutDelta));
  Reach x;
  x.effect = "scale";
  x.visible = true;
  x.strongest = 0.4, x.extended_from = 0.3, x.visible_from = 0.4, x.max_z = 4.2;
  r.reach.push_back(x);
  const std::string q = verdict_paragraph(r);
  const std::string strong = q.substr(q.find("Seen only when strong"));
  EXPECT_NE(strong.find("`scale` moves no cell by 3 σ up to the strongest strength probed before"),
            std::string::npos)
      << q;
  EXPECT_NE(strong.find("set against its runs directly, the observations rule it out from 0.2"),
            std::string::npos)
      << q;
  // Ruled out only where the gap search shows it too: nothing to add.
  r.limits.back() = limit_of("scale", {{0.2, 3.0}, {0.4, 97.7}}, kRuleOutDelta);
  const std::string same = verdict_paragraph(r);
  EXPECT_EQ(same.find("set against its runs directly"), std::string::npos) << same;
  // The sink's limit with its rate free: ruled out only where every rate run rules it out; a rate at which
  // no run is ruled out leaves it open.
  Report f = r;
  f.limits.push_back(limit_of("absorption", {{0.05, 3.0}, {0.125, 60.0}}, kRuleOutDelta));
  f.limits.back().shape = 0.3;
  f.limits.push_back(limit_of("absorption", {{0.05, 900.0}}, kRuleOutDelta));
  f.limits.back().shape = 30.0;
  const std::string both = verdict_paragraph(f);
  EXPECT_NE(
      both.find("at rate k (1/s) = 3 (Δχ² +753.4; no weaker strength was run; from pore capacity (fraction "
                "of own volume) = 0.125 with the rate k (1/s) free (0.3–30 run; set by rate k (1/s) = 0.3))"),
      std::string::npos)
      << both;
  f.limits[f.limits.size() - 2] = limit_of("absorption", {{0.05, 3.0}, {0.125, 6.0}}, kRuleOutDelta);
  f.limits[f.limits.size() - 2].shape = 0.3;
  const std::string open = verdict_paragraph(f);
  EXPECT_NE(open.find("; not ruled out with the rate k (1/s) free (0.3–30 run): at rate k (1/s) = 0.3 no run "
                      "up to pore capacity (fraction of own volume) = 0.125 is)"),
            std::string::npos)
      << open;
  // Open up to the end of the physical range (the climb's last run): the sentence says so.
  f.limits[f.limits.size() - 2] = limit_of("absorption", {{0.05, 3.0}, {0.3, 6.0}}, kRuleOutDelta);
  f.limits[f.limits.size() - 2].shape = 0.3;
  const std::string end = verdict_paragraph(f);
  EXPECT_NE(end.find("(fraction of own volume) = 0.3, the end of its physical range, is)"), std::string::npos)
      << end;
  // The other rates' rows are the free-shape clause's, not entries of their own.
  EXPECT_EQ(open.find("`absorption` from", open.find("`absorption` from") + 1), std::string::npos) << open;
}
