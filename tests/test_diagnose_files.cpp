// Bad diagnosis and twin input is refused before anything runs, with the file and the key (or row) named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "diagnose/driver.h"
#include "diagnose/effects.h"
#include "diagnose/files.h"
#include "diagnose/procedure.h"
#include "diagnose/table.h"
#include "diagnose/twin.h"
#include "support/diagnose_input.h"

namespace fs = std::filesystem;
using namespace wetdem::diagnose;

using wetdem::test_support::DiagnoseDir;
using wetdem::test_support::expect_diagnose_error;
using wetdem::test_support::kDiagnoseMicroCase;
using wetdem::test_support::quiet_options;

TEST(DiagnoseFiles, ShippedFilesParse) {
  const std::string dir = std::string(WETDEM_SOURCE_DIR) + "/assets/diagnosis/micro/";
  const DiagnosisSpec d = parse_diagnosis_file(dir + "diagnose.toml");
  EXPECT_EQ(d.effects, (std::vector<std::string>{"cohesion", "absorption", "evaporation", "spread"}));
  EXPECT_EQ(d.replicates, 2);
  EXPECT_EQ(d.probes.at("cohesion"), (std::vector<double>{0.01, 0.03, 0.1}));
  EXPECT_EQ(d.shapes.at("absorption"), effect_spec("absorption").shapes);
  EXPECT_TRUE(d.refit.empty());
  const DiagnosisSpec r = parse_diagnosis_file(dir + "diagnose_refit.toml");
  ASSERT_EQ(r.refit.size(), 1u);
  EXPECT_EQ(refit_settings(r.refit).size(), 3u);
  const DiagnosisSpec l = parse_diagnosis_file(dir + "diagnose_refit_scaling.toml");
  ASSERT_EQ(l.refit.size(), 1u);
  std::vector<std::string> l_settings;
  for (const RefitSetting& s : refit_settings(l.refit)) l_settings.push_back(s.label);
  EXPECT_EQ(l_settings, (std::vector<std::string>{"calibrated", "scaling=4.25", "scaling=5.4"}));
  EXPECT_TRUE(d.second_effect) << "a partial verdict fits a second effect unless the file says not";
  EXPECT_EQ(d.reach_conditions, 5u) << "a candidate the table cannot see is tried beyond it by default";
  EXPECT_EQ(d.reach_steps, 2) << "and past the file's strongest probe, two steps";
  EXPECT_EQ(d.limit_steps, 2) << "a no_gap's limits get two rounds of bracketing runs";
  EXPECT_EQ(d.next_refit, 3u)
      << "the next experiment re-fits both tied models at three conditions by default";
  EXPECT_FALSE(
      parse_diagnosis_file(std::string(WETDEM_SOURCE_DIR) + "/tests/diagnose/micro_ci_one_effect.toml")
          .second_effect);
  EXPECT_EQ(parse_twin_file(dir + "twin_spread_absorption.toml").truth.size(), 3u);
  EXPECT_EQ(parse_twin_file(dir + "twin_spread_vmax.toml").truth.size(), 2u);
  EXPECT_EQ(parse_twin_file(dir + "twin_vmax.toml").truth,
            (std::vector<std::string>{"liquid.v_max=\"2 %\""}));
  const TwinSpec t = parse_twin_file(dir + "twin_cohesion.toml");
  EXPECT_EQ(t.truth, (std::vector<std::string>{"cohesion.surface_energy=\"0.08 J/m2\""}));
  EXPECT_EQ(t.condition_toml.at(0).size(), 3u);
  EXPECT_DOUBLE_EQ(t.noise.at("aor_deg_mean"), 0.5);
  // The flowing table, and the same with two 120 rpm rows (twin_null_fast.toml, scripts/twin_matrix.py
  // --twin-base): the first six rows and the noise are twin_null.toml's.
  const std::string flowing = std::string(WETDEM_SOURCE_DIR) + "/assets/diagnosis/flowing/";
  const TwinSpec slow = parse_twin_file(flowing + "twin_null.toml");
  const TwinSpec fast = parse_twin_file(flowing + "twin_null_fast.toml");
  ASSERT_EQ(slow.points.size(), 6u);
  ASSERT_EQ(fast.points.size(), 8u);
  for (size_t i = 0; i < slow.points.size(); ++i) EXPECT_EQ(fast.points[i], slow.points[i]) << i;
  for (size_t i = 6; i < 8; ++i)
    EXPECT_NE(std::find(fast.points[i].begin(), fast.points[i].end(),
                        std::make_pair(std::string("drum.rpm"), std::string("120"))),
              fast.points[i].end())
        << i;
  EXPECT_EQ(fast.noise, slow.noise);
  EXPECT_EQ(fast.case_path, slow.case_path);
  EXPECT_TRUE(fast.truth.empty());
  // The full-size example: its table comes with --observations (made on a GPU).
  const std::string full = std::string(WETDEM_SOURCE_DIR) + "/assets/diagnosis/pp2_l5/";
  const DiagnosisSpec f = parse_diagnosis_file(full + "diagnose.toml");
  EXPECT_TRUE(f.observations.empty());
  EXPECT_EQ(f.effects.size(), 6u);
  for (const char* twin : {"twin_absorption.toml", "twin_null.toml"})
    EXPECT_EQ(parse_twin_file(full + twin).condition_toml.at(0).size(), 4u) << twin;
  DiagnoseOptions o;
  o.out = (fs::temp_directory_path() / ("wetdem-diag-notable-" + std::to_string(::getpid()))).string();
  EXPECT_NE(expect_diagnose_error([&] { run_diagnosis(f, o); }).find("--observations"), std::string::npos);
  EXPECT_FALSE(fs::exists(o.out));
}

TEST(DiagnoseFiles, BadDiagnosisFilesNameTheKey) {
  DiagnoseDir d;
  const std::string obs =
      d.write("obs.csv", "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n");
  const std::string head = "case = \"" + kDiagnoseMicroCase + "\"\nobservations = \"obs.csv\"\n";
  auto err = [&](const std::string& body) {
    const std::string f = d.write("d.toml", head + body);
    return expect_diagnose_error([&] { parse_diagnosis_file(f); });
  };
  EXPECT_NE(err("effects = [\"gravity\"]\n").find("unknown effect 'gravity'"), std::string::npos);
  EXPECT_NE(err("colour = 3\n").find("colour: unknown key"), std::string::npos);
  EXPECT_NE(err("replicates = 0\n").find("replicates"), std::string::npos);
  // Escalation must add seeds: at or below `replicates` it would run the same diagnosis twice.
  EXPECT_NE(err("replicates = 2\nescalate_replicates = 2\n")
                .find("escalate_replicates: 2 is not more than replicates (2)"),
            std::string::npos);
  EXPECT_NE(err("escalate_replicates = -1\n").find("escalate_replicates: an integer in [0, 100]"),
            std::string::npos);
  EXPECT_NE(err("escalate_when = \"sometimes\"\n").find("escalate_when: \"undecided\" (the default"),
            std::string::npos);
  EXPECT_NE(err("escalate_when = 1\n").find("escalate_when: "), std::string::npos);
  EXPECT_FALSE(parse_diagnosis_file(d.write("d.toml", head)).escalate_only_decidable) << "the default";
  EXPECT_TRUE(parse_diagnosis_file(d.write("d.toml", head + "escalate_when = \"decidable\"\n"))
                  .escalate_only_decidable);
  // The probes share the baseline's first seeds: no more of them than the replicates.
  EXPECT_NE(err("replicates = 2\nprobe_seeds = 3\n").find("probe_seeds: an integer in [1, replicates = 2]"),
            std::string::npos);
  EXPECT_NE(err("probe_seeds = 0\n").find("probe_seeds"), std::string::npos);
  d.write("obs2.csv",
          "liquid.content,observable,value,sigma\n\"0 %\",aor_deg_mean,30,1\n\"5 %\",aor_deg_mean,31,1\n");
  DiagnosisSpec ps =
      parse_diagnosis_file(d.write("p.toml", "case = \"" + kDiagnoseMicroCase +
                                                 "\"\nobservations = \"obs2.csv\"\nreplicates = 3\n"
                                                 "probe_seeds = 2\n"));
  EXPECT_EQ(ps.probe_seeds, 2);
  // A --replicates below the file's probe_seeds (commands.cpp sets d.replicates): refused before any output.
  ps.replicates = 1;
  DiagnoseOptions po;
  po.out = (fs::temp_directory_path() / ("wetdem-diag-probe-seeds-" + std::to_string(::getpid()))).string();
  const std::string pe = expect_diagnose_error([&] { run_diagnosis(ps, po); });
  EXPECT_NE(pe.find("probe_seeds: 2 is not in [1, replicates = 1]"), std::string::npos) << pe;
  EXPECT_FALSE(fs::exists(po.out));
  EXPECT_NE(err("second_effect = 1\n").find("second_effect: true or false"), std::string::npos);
  EXPECT_NE(err("reach_conditions = -1\n").find("reach_conditions: an integer in [0, 20]"),
            std::string::npos);
  EXPECT_NE(err("reach_steps = 11\n").find("reach_steps: an integer in [0, 10]"), std::string::npos);
  EXPECT_NE(err("limit_steps = -1\n").find("limit_steps: an integer in [0, 10]"), std::string::npos);
  EXPECT_NE(err("next_refit = 11\n").find("next_refit: an integer in [0, 10]"), std::string::npos);
  EXPECT_NE(err("effects = [\"cohesion\"]\n[probes]\ncohesion = [0.1, 0.01]\n").find("ascending"),
            std::string::npos);
  EXPECT_NE(err("effects = [\"cohesion\"]\n[probes]\nviscous = [0.1]\n").find("not one of the effects"),
            std::string::npos);
  EXPECT_NE(
      err("effects = [\"cohesion\", \"spread\", \"cohesion\"]\n").find("effects: cohesion is listed twice"),
      std::string::npos);
  const std::string f =
      d.write("d2.toml", "case = \"" + kDiagnoseMicroCase + "\"\nobservations = \"missing.csv\"\n");
  EXPECT_NE(expect_diagnose_error([&] { parse_diagnosis_file(f); }).find("observations: no such file"),
            std::string::npos);
  // A table given on the command line replaces the file's, which then need not exist; a missing one is named.
  const std::string table = d.write("table.csv", "liquid.content,observable,value,sigma\n");
  EXPECT_EQ(parse_diagnosis_file(f, table).observations, fs::absolute(table).lexically_normal().string());
  EXPECT_NE(expect_diagnose_error([&] {
              parse_diagnosis_file(f, (d.p / "none.csv").string());
            }).find("--observations: no such file"),
            std::string::npos);
}

// Re-fitted parameters (refit.h): every value is resolved through the case schema when the file is read, so a
// wrong key, a value out of its range or a clash with a candidate's own key is refused before anything runs.
TEST(DiagnoseFiles, RefitIsCheckedAgainstTheCaseBeforeAnyRun) {
  DiagnoseDir d;
  d.write(
      "obs.csv",
      "liquid.content,observable,value,sigma\n\"5 %\",f_wet_mean,0.8,0.02\n\"10 %\",f_wet_mean,0.9,0.02\n");
  const std::string head = "case = \"" + kDiagnoseMicroCase +
                           "\"\nobservations = \"obs.csv\"\neffects = [\"spread\", \"cohesion\"]\n";
  auto parse = [&](const std::string& body) { return parse_diagnosis_file(d.write("d.toml", head + body)); };
  auto err = [&](const std::string& body) { return expect_diagnose_error([&] { parse(body); }); };

  // A good one: the calibrated value (1 % in the case) is setting 0 and is not repeated when listed.
  const DiagnosisSpec ok = parse(
      "refit = [\"liquid.v_max\"]\n[refit_values]\n\"liquid.v_max\" = "
      "[\"0.5 %\", \"1 %\", 0.02]\n");
  ASSERT_EQ(ok.refit.size(), 1u);
  EXPECT_EQ(ok.refit[0].key, "liquid.v_max");
  EXPECT_DOUBLE_EQ(ok.refit[0].calibrated_si, 0.01);
  ASSERT_EQ(ok.refit[0].values.size(), 2u);
  EXPECT_DOUBLE_EQ(ok.refit[0].values[0].si, 0.005);
  EXPECT_EQ(ok.refit[0].values[0].written, "0.5 %");
  EXPECT_DOUBLE_EQ(ok.refit[0].values[1].si, 0.02);
  const std::vector<RefitSetting> one = refit_settings(ok.refit);
  ASSERT_EQ(one.size(), 3u);
  EXPECT_TRUE(one[0].overrides.empty());
  EXPECT_EQ(one[0].label, "calibrated");
  EXPECT_DOUBLE_EQ(one[0].si.at("liquid.v_max"), 0.01);
  EXPECT_EQ(one[1].overrides, (std::vector<std::string>{"liquid.v_max=\"0.5 %\""}));
  EXPECT_EQ(one[2].label, "liquid.v_max=0.02");
  // Two keys: the Cartesian product of [calibrated] + values, the calibrated model first.
  const DiagnosisSpec two = parse(
      "refit = [\"liquid.v_max\", \"friction.mu_r\"]\n[refit_values]\n\"liquid.v_max\" = [\"2 %\"]\n"
      "\"friction.mu_r\" = [0.1, 0.5]\n");
  const std::vector<RefitSetting> grid = refit_settings(two.refit);
  ASSERT_EQ(grid.size(), 6u);
  EXPECT_EQ(grid[1].label, "friction.mu_r=0.1");
  EXPECT_EQ(grid[5].label, "liquid.v_max=2 %, friction.mu_r=0.5");
  EXPECT_TRUE(refit_settings({}).size() == 1 && refit_settings({})[0].overrides.empty());

  const std::string refit = "refit = [\"liquid.v_max\"]\n";
  EXPECT_NE(err("refit = [\"liquid.vmax\"]\n[refit_values]\n\"liquid.vmax\" = [0.02]\n").find("liquid.vmax"),
            std::string::npos);
  EXPECT_NE(err(refit + "[refit_values]\n\"liquid.v_max\" = []\n").find("non-empty array"),
            std::string::npos);
  EXPECT_NE(err(refit).find("[refit_values]"), std::string::npos);
  const std::string range = err(refit + "[refit_values]\n\"liquid.v_max\" = [\"150 %\"]\n");
  EXPECT_NE(range.find("liquid.v_max"), std::string::npos) << range;
  EXPECT_NE(range.find("[0, 1]"), std::string::npos) << range;
  EXPECT_NE(range.find("d.toml"), std::string::npos) << range;
  EXPECT_NE(err(refit + "[refit_values]\n\"liquid.v_max\" = [\"1 %\"]\n").find("no value other than"),
            std::string::npos);
  EXPECT_NE(err(refit + "[refit_values]\n\"liquid.v_max\" = [0.02, \"2 %\"]\n").find("the same value"),
            std::string::npos);
  EXPECT_NE(err(refit + "[refit_values]\n\"liquid.v_max\" = [0.02]\n\"liquid.v_min\" = [0.1]\n")
                .find("\"liquid.v_min\": not named in refit"),
            std::string::npos);
  EXPECT_NE(err("refit = [\"liquid.wetted_fraction\"]\n[refit_values]\n\"liquid.wetted_fraction\" = [0.5]\n")
                .find("candidate effect 'spread'"),
            std::string::npos);
  EXPECT_NE(err("refit = [\"liquid.films\"]\n[refit_values]\n\"liquid.films\" = [\"mean_volume\"]\n")
                .find("not a numeric case key"),
            std::string::npos);
  EXPECT_NE(err("refit = [\"friction.mu_r\"]\n[refit_values]\n\"friction.mu_r\" = [0.01, 0.02, 0.03, 0.04, "
                "0.05, 0.06, 0.07, 0.08, 0.09, 0.1, 0.11, 0.12, 0.13, 0.14, 0.15, 0.16]\n")
                .find("at most 16"),
            std::string::npos);

  // A refit key that is also a condition of the table is measured, not fitted: refused before any run.
  const std::string f = d.write("c.toml", head +
                                              "refit = [\"liquid.content\"]\n[refit_values]\n"
                                              "\"liquid.content\" = [\"3 %\"]\n");
  DiagnoseOptions o = quiet_options((d.p / "out").string());
  EXPECT_NE(expect_diagnose_error([&] { run_diagnosis(parse_diagnosis_file(f), o); }).find("is a condition"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(d.p / "out" / "store" / "runs")) << "nothing may run on bad input";
}

TEST(DiagnoseFiles, BadObservationTablesAreRefusedBeforeAnyRun) {
  DiagnoseDir d;
  auto diagnose_with = [&](const std::string& csv) {
    d.write("obs.csv", csv);
    const std::string f =
        d.write("d.toml", "case = \"" + kDiagnoseMicroCase + "\"\nobservations = \"obs.csv\"\n");
    DiagnoseOptions o = quiet_options((d.p / "out").string());
    const std::string err = expect_diagnose_error([&] { run_diagnosis(parse_diagnosis_file(f), o); });
    o.check = true;  // diagnose --check refuses it with the same words
    EXPECT_EQ(expect_diagnose_error([&] { run_diagnosis(parse_diagnosis_file(f), o); }), err);
    return err;
  };
  // One condition: no held-out check possible.
  EXPECT_NE(diagnose_with("liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
                          "\"5 %\",f_wet_mean,0.5,0.1\n")
                .find("at least two"),
            std::string::npos);
  // Unknown observable, named with its line.
  EXPECT_NE(diagnose_with("liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
                          "\"10 %\",colour,3,1\n")
                .find("line 3: unknown observable 'colour'"),
            std::string::npos);
  // A condition no case can express: named where the user wrote it, the table's rows at that condition, with
  // the case's reason (not the study's internal point number).
  const std::string bad_key = diagnose_with(
      "liquid.contnt,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
      "\"5 %\",f_wet_mean,0.5,0.1\n\"10 %\",aor_deg_mean,31,1\n");
  EXPECT_NE(bad_key.find("obs.csv: lines 2-3 (liquid.contnt=5 %): liquid.contnt: unknown key"),
            std::string::npos)
      << bad_key;
  EXPECT_EQ(bad_key.find("point 0"), std::string::npos) << bad_key;
  // A condition value out of its range, on one row of several conditions.
  const std::string bad_value = diagnose_with(
      "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n\"110 %\",aor_deg_mean,31,1\n");
  EXPECT_NE(bad_value.find("obs.csv: line 3 (liquid.content=110 %): liquid.content: must be in [0, 1]"),
            std::string::npos)
      << bad_value;
  // An observable the model cannot produce: the plate AoR of a periodic slice.
  EXPECT_NE(diagnose_with("liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
                          "\"10 %\",aor_plate_deg,31,1\n")
                .find("line 3: the model cannot produce aor_plate_deg"),
            std::string::npos);
  // An observable that carries no information at any condition (every value missing or sigma infinite).
  EXPECT_NE(
      diagnose_with("liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
                    "\"10 %\",aor_deg_mean,31,1\n\"5 %\",f_wet_mean,NA,0.1\n\"10 %\",f_wet_mean,0.5,inf\n")
          .find("f_wet_mean carries no information at any condition (lines 4, 5"),
      std::string::npos);
  // The whole table: nothing measured leaves fewer than two conditions.
  EXPECT_NE(diagnose_with("liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,,1\n"
                          "\"10 %\",aor_deg_mean,31,inf\n")
                .find("carries no information"),
            std::string::npos);
  // A [set] key the table varies would be replaced by each condition's value.
  {
    d.write("obs.csv",
            "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n\"10 %\",aor_deg_mean,31,1\n");
    const std::string f =
        d.write("ds.toml", "case = \"" + kDiagnoseMicroCase +
                               "\"\nobservations = \"obs.csv\"\n[set]\n\"liquid.content\" = \"5 %\"\n");
    DiagnoseOptions o = quiet_options((d.p / "out").string());
    EXPECT_NE(expect_diagnose_error([&] {
                run_diagnosis(parse_diagnosis_file(f), o);
              }).find("[set] liquid.content: a condition of the observation table"),
              std::string::npos);
  }
  // One cell given twice, and one condition written two ways that are equal in SI.
  const std::string twice = diagnose_with(
      "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n\"10 %\",aor_deg_mean,31,1\n"
      "\"5 %\",aor_deg_mean,32,1\n");
  EXPECT_NE(twice.find("lines 2 and 4 both give aor_deg_mean at liquid.content=5 %"), std::string::npos)
      << twice;
  const std::string two_ways = diagnose_with(
      "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n0.05,f_wet_mean,0.5,0.1\n"
      "\"10 %\",aor_deg_mean,31,1\n");
  EXPECT_NE(two_ways.find("line 2 (liquid.content=5 %) and line 3 (liquid.content=0.05) are the same "
                          "condition in SI units"),
            std::string::npos)
      << two_ways;
  // A value outside the observable's possible range by more than its noise could put it (5 sigma); a value
  // just outside, within its error, is a measurement (a washing assay recovering 101 %).
  EXPECT_NE(
      diagnose_with("liquid.content,observable,value,sigma\n\"0 %\",f_wet_mean,-0.11,0.02\n"
                    "\"10 %\",f_wet_mean,0.5,0.02\n")
          .find("line 2: f_wet_mean = -0.11 is outside its possible range [0, 1] (-) by more than 5 sigma"),
      std::string::npos);
  EXPECT_EQ(read_table(d.write("near.csv",
                               "liquid.content,observable,value,sigma\n\"0 %\",liquid_free_fraction,"
                               "1.02,0.02\n\"10 %\",f_wet_mean,-0.05,0.02\n"))
                .cells.size(),
            2u);
  EXPECT_FALSE(fs::exists(d.p / "out" / "store" / "runs")) << "nothing may run on bad input";
  // A good table with --check: the counts, and nothing written (not even the store's run aliases).
  {
    d.write("obs.csv",
            "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n"
            "\"5 %\",f_wet_mean,0.5,0.1\n\"10 %\",aor_deg_mean,31,1\n");
    const std::string f =
        d.write("dc.toml", "case = \"" + kDiagnoseMicroCase +
                               "\"\nobservations = \"obs.csv\"\neffects = [\"cohesion\", \"spread\"]\n");
    DiagnoseOptions o;
    o.out = (d.p / "checked").string();
    o.quiet = true;
    o.check = true;
    const nlohmann::json j = run_diagnosis(parse_diagnosis_file(f), o);
    EXPECT_TRUE(j.value("checked", false));
    EXPECT_EQ(j.value("conditions", 0), 2);
    EXPECT_EQ(j.value("cells", 0), 3);
    EXPECT_EQ(j["candidates"], nlohmann::json::array({"cohesion", "spread"}));
    EXPECT_FALSE(fs::exists(d.p / "checked")) << "a check writes nothing";
  }
}

TEST(DiagnoseFiles, ProbesOutsideThePhysicalRangeAreRefused) {
  DiagnoseDir d;
  const auto err = [&](const std::string& body) {
    return expect_diagnose_error(
        [&] { parse_diagnosis_file(d.write("d.toml", "case = \"" + kDiagnoseMicroCase + "\"\n" + body)); });
  };
  EXPECT_NE(
      err("[probes]\ncohesion = [0.01, 0.3]\n").find("[probes] cohesion: 0.3 is outside the physical range"),
      std::string::npos);
  EXPECT_NE(err("[probes]\nspread = [0.5, 0.95]\n").find("0.95 is outside the physical range 0.01-0.9"),
            std::string::npos);
  EXPECT_NE(err("[shapes]\nabsorption = [0.001, 1]\n").find("[shapes] absorption: 0.001 is outside"),
            std::string::npos);
  EXPECT_NE(err("[shapes]\ncohesion = [1, 2]\n").find("no second parameter"), std::string::npos);
  EXPECT_NE(err("max_cost = 0.5\n").find("max_cost"), std::string::npos);
  EXPECT_NE(err("max_froude = 1.5\n").find("max_froude: a number in (0, 1]"), std::string::npos);
  EXPECT_NE(err("max_froude = 0\n").find("max_froude"), std::string::npos);
  EXPECT_NE(err("[verdict]\ntable_level = 1\n").find("verdict.table_level: in [0, 1)"), std::string::npos);
  EXPECT_NE(err("[verdict]\nheld_out = \"aic\"\n")
                .find("verdict.held_out: \"chi2\" or \"log_density\", not \"aic\""),
            std::string::npos);
  EXPECT_NE(err("[verdict]\ntie_noise = -1\n").find("verdict.tie_noise: a number >= 0"), std::string::npos);
  EXPECT_NE(err("[verdict]\ntie_draws = 1\n").find("verdict.tie_draws: an integer in 2-1000, not 1"),
            std::string::npos);
  const DiagnosisSpec ok = parse_diagnosis_file(d.write(
      "d.toml",
      "case = \"" + kDiagnoseMicroCase +
          "\"\n[shapes]\nabsorption = [1, 10]\n[verdict]\ntie_delta = 3\ntable_level = 0\ntie_noise = 0\n"));
  EXPECT_EQ(ok.shapes.at("absorption"), (std::vector<double>{1, 10}));
  EXPECT_EQ(ok.max_froude, 0.5) << "the default";
  EXPECT_EQ(ok.rule.tie_delta, 3.0);
  EXPECT_EQ(ok.rule.tie_noise, 0.0) << "0 turns the held-out noise margin off";
  EXPECT_EQ(ok.rule.tie_draws, VerdictRule{}.tie_draws);
  EXPECT_EQ(ok.rule.table_level, 0.0) << "0 turns the table test off";
  for (const EffectSpec& e : effect_catalogue())
    for (double s : e.probes) EXPECT_TRUE(s >= e.phys_lo && s <= e.phys_hi) << e.name << " " << s;
}

TEST(DiagnoseFiles, EveryEffectMapsStrengthsToCaseKeys) {
  for (const EffectSpec& e : effect_catalogue()) {
    ASSERT_FALSE(e.probes.empty()) << e.name;
    for (double s : e.probes) EXPECT_FALSE(e.overrides(s, ModelFacts{0.5236}).empty()) << e.name;
    EXPECT_THROW(e.overrides(0.0, ModelFacts{0.5236}), std::invalid_argument) << e.name;
  }
  EXPECT_EQ(effect_spec("evaporation").overrides(0.1, ModelFacts{0.5})[0],
            "liquid.evaporation_time=\"10 s\"");
  EXPECT_EQ(effect_spec("hysteresis").overrides(10.0, ModelFacts{30.0 * 3.14159265358979323846 / 180})[0],
            "liquid.theta_receding=\"20 deg\"");
  EXPECT_THROW(effect_spec("magic"), std::invalid_argument);
  ModelFacts m;
  m.scaling = 5.0;
  m.has_plates = true;
  m.plates_mu_s = 0.3;
  m.plates_mu_r = 0.9;
  EXPECT_EQ(effect_spec("scale").overrides(0.2, m), (std::vector<std::string>{"scaling=4"}));
  EXPECT_EQ(effect_spec("plates").overrides(0.2, m),
            (std::vector<std::string>{"walls.plates.mu_s=0.5", "walls.plates.mu_r=1"}));
  EXPECT_EQ(effect_spec("plates").not_applicable(m), "");
  m.has_plates = false;
  EXPECT_NE(effect_spec("plates").not_applicable(m).find("periodic slice"), std::string::npos);
}

TEST(DiagnoseFiles, AnEffectThatCannotActIsRefusedBeforeAnyRun) {
  DiagnoseDir d;
  d.write("obs.csv",
          "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n\"10 %\",aor_deg_mean,31,1\n");
  const std::string f = d.write("d.toml", "case = \"" + kDiagnoseMicroCase +
                                              "\"\nobservations = \"obs.csv\"\neffects = [\"plates\"]\n");
  DiagnoseOptions o = quiet_options((d.p / "out").string());
  EXPECT_NE(expect_diagnose_error([&] {
              run_diagnosis(parse_diagnosis_file(f), o);
            }).find("'plates' cannot act here"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(d.p / "out" / "store" / "runs")) << "nothing may run on bad input";
}

// [assays]: measurements a laboratory could add for the next experiment. Each names an observable a
// laboratory can measure, with the sd of one measurement; one the table already has, or one the model cannot
// produce, is refused before any run.
TEST(DiagnoseFiles, AssaysAreLabMeasurementsTheTableLacks) {
  DiagnoseDir d;
  const auto err = [&](const std::string& body) {
    return expect_diagnose_error(
        [&] { parse_diagnosis_file(d.write("d.toml", "case = \"" + kDiagnoseMicroCase + "\"\n" + body)); });
  };
  EXPECT_NE(err("[assays]\nmoisture = 0.01\n").find("[assays] moisture: not an observable"),
            std::string::npos);
  EXPECT_NE(
      err("[assays]\nf_wet_mean = 0.01\n").find("[assays] f_wet_mean: f_wet_mean is a simulation quantity"),
      std::string::npos);
  EXPECT_NE(err("[assays]\nliquid_free_fraction = -0.01\n")
                .find("[assays] liquid_free_fraction: the sd of one measurement, a positive number"),
            std::string::npos);
  EXPECT_NE(err("[assays]\nliquid_free_fraction = \"2 %\"\n").find("a positive number"), std::string::npos);
  EXPECT_NE(err("assays = 0.02\n").find("[assays]: a table of observable = measurement sd"),
            std::string::npos);
  const DiagnosisSpec ok = parse_diagnosis_file(
      d.write("d.toml", "case = \"" + kDiagnoseMicroCase + "\"\n[assays]\nliquid_free_fraction = 0.02\n"));
  EXPECT_EQ(ok.assays.at("liquid_free_fraction"), 0.02);

  // Against the table and the model (the procedure, before any run).
  d.write("obs.csv",
          "liquid.content,observable,value,sigma\n\"5 %\",aor_deg_mean,30,1\n\"10 %\",aor_deg_mean,31,1\n"
          "\"5 %\",liquid_free_fraction,0.5,0.02\n\"10 %\",liquid_free_fraction,0.6,0.02\n");
  DiagnoseOptions o = quiet_options((d.p / "out").string());
  const auto run_err = [&](const std::string& assays) {
    const std::string f = d.write(
        "d.toml", "case = \"" + kDiagnoseMicroCase + "\"\nobservations = \"obs.csv\"\n[assays]\n" + assays);
    return expect_diagnose_error([&] { run_diagnosis(parse_diagnosis_file(f), o); });
  };
  // An assay the table measures now (a report asked for it, the laboratory added its rows and runs the file
  // again) is one of the table's observables: dropped from the assays with a note, not refused.
  {
    const Procedure p(parse_diagnosis_file(d.write("d.toml", "case = \"" + kDiagnoseMicroCase +
                                                                 "\"\nobservations = \"obs.csv\"\n[assays]\n"
                                                                 "liquid_free_fraction = 0.02\n")),
                      o);
    EXPECT_TRUE(p.d.assays.empty()) << "the table's rows and σ, not the file's";
    EXPECT_EQ(p.assays_in_table, std::vector<std::string>{"liquid_free_fraction"});
    EXPECT_TRUE(p.notes.empty()) << "not a run that could not be made";
  }
  EXPECT_NE(run_err("aor_centre_deg = 1\n").find("[assays] aor_centre_deg: the model cannot produce it"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(d.p / "out" / "store" / "runs")) << "nothing may run on bad input";
}
