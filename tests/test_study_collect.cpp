// collect and calibrate on fake run stores: summary.json files written by the test, so the statistics and the
// calibration are checked against values computed by hand, without running anything.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "study/calibrate.h"
#include "study/collect.h"
#include "study/store.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;
using study::StudyError;

// Plans a study in DIR and writes a summary.json for every run with the observables f(run).
template <class F>
study::StudyIndex fake_store(const std::string& dir, const std::string& text, F f) {
  const auto s = study::parse_study_file(write_text(dir + "/s.toml", text));
  const auto runs = study::expand(s);
  const study::StudyIndex ix = study::write_plan(dir + "/st", s, runs);
  for (const auto& r : runs) {
    fs::create_directories(dir + "/st/runs/" + r.hash);
    std::ofstream(dir + "/st/runs/" + r.hash + "/summary.json") << f(r).dump();
  }
  return ix;
}

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string l; std::getline(in, l);) rows.push_back(study::split_csv(l));
  return rows;
}

TEST(StudyCollect, StatisticsOverReplicates) {
  const study::Stats s = study::stats_of({1.0, 2.0, 6.0});
  EXPECT_EQ(s.n, 3u);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_NEAR(s.sd, std::sqrt(7.0), 1e-12);  // ((4 + 1 + 9) / 2)
  EXPECT_NEAR(s.se, std::sqrt(7.0 / 3.0), 1e-12);
  EXPECT_TRUE(std::isnan(study::stats_of({5.0}).sd));

  const std::string d = study_temp("collect");
  // aor = 10 * content(%) + seed: replicates 1, 2, 3 give mean 10 c + 2, sd 1, se 1/sqrt(3).
  fake_store(
      d, "base = \"" + micro_case() + "\"\nreplicates = 3\n[axes]\n\"liquid.content\" = [\"0 %\", \"5 %\"]\n",
      [](const study::PlannedRun& r) {
        nlohmann::json j;
        j["aor_deg_mean"] = 1000.0 * r.resolved.liquid.content + double(r.seed);
        j["f_wet_mean"] = r.seed == 2 ? nlohmann::json(nullptr) : nlohmann::json(0.5 * double(r.seed));
        j["device"] = "fake";
        return j;
      });
  study::CollectOptions o;
  o.figures = false;
  study::collect(d + "/st", o);
  const auto runs = read_csv(d + "/st/runs.csv");
  ASSERT_EQ(runs.size(), 7u);  // header + 6 runs
  const auto pts = read_csv(d + "/st/points.csv");
  ASSERT_EQ(pts.size(), 3u);
  const auto col = [&](const std::string& name) {
    for (size_t i = 0; i < pts[0].size(); ++i)
      if (pts[0][i] == name) return i;
    ADD_FAILURE() << "no column " << name;
    return size_t(0);
  };
  EXPECT_EQ(pts[2][col("liquid.content")], "5 %");
  EXPECT_NEAR(std::stod(pts[2][col("liquid.content [SI]")]), 0.05, 1e-15);
  EXPECT_NEAR(std::stod(pts[2][col("aor_deg_mean_mean")]), 52.0, 1e-9);
  EXPECT_NEAR(std::stod(pts[2][col("aor_deg_mean_sd")]), 1.0, 1e-9);
  EXPECT_NEAR(std::stod(pts[2][col("aor_deg_mean_se")]), 1.0 / std::sqrt(3.0), 1e-8);
  EXPECT_EQ(pts[2][col("n")], "3");
  // A null (flagged) value is left out: f_wet over seeds 1 and 3 = 0.5, 1.5.
  EXPECT_EQ(pts[1][col("f_wet_mean_n")], "2");
  EXPECT_NEAR(std::stod(pts[1][col("f_wet_mean_mean")]), 1.0, 1e-12);
  EXPECT_NEAR(std::stod(pts[1][col("f_wet_mean_se")]), 0.5, 1e-9);  // sd sqrt(0.5), / sqrt(2)
  EXPECT_TRUE(fs::exists(d + "/st/report.md"));
}

// A smooth "true" response: AoR rises with liquid content, most for V_max near 1.5 %.
double truth(double content, double vmax) {
  const double l = std::log10(vmax / 0.015);
  return 25.0 + 200.0 * content * std::exp(-l * l / 0.5);
}

std::string calib_study(const std::string& obs) {
  return "base = \"" + micro_case() +
         "\"\nreplicates = 2\n"
         // V_max = 8 % needs a slice thicker than the micro case's 18 mm (twice the neighbour reach).
         "[set]\n\"drum.slice_thickness\" = \"24 mm\"\n"
         "[axes]\n\"liquid.content\" = [\"5 %\", \"10 %\"]\n"
         "\"liquid.v_max\" = [\"0.25 %\", \"0.5 %\", \"1 %\", \"2 %\", \"4 %\", \"8 %\"]\n"
         "[observations]\nfile = \"" +
         obs + "\"\nfit = [\"liquid.v_max\"]\n";
}

TEST(StudyCalibrate, RecoversAKnownOptimum) {
  const std::string d = study_temp("calib");
  // The "measurements": the truth at V_max = 1.5 % (between grid values) plus noise of sigma 0.3 deg, at
  // four liquid contents; the simulated replicates scatter by +-0.2 deg around the truth.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::string obs = "liquid.content,observable,value,sigma,n,note\n";
  for (double c : {5.0, 10.0})
    obs += std::to_string(int(c)) + " %,aor_deg_mean," + std::to_string(truth(c / 100, 0.015) + noise(rng)) +
           ",0.3,3,synthetic\n";
  write_text(d + "/obs.csv", obs);
  fake_store(d, calib_study(d + "/obs.csv"), [](const study::PlannedRun& r) {
    nlohmann::json j;
    j["aor_deg_mean"] =
        truth(r.resolved.liquid.content, r.resolved.liquid.v_max) + (r.seed == 1 ? 0.2 : -0.2);
    return j;
  });
  const study::Calibration c = study::calibrate(d + "/st");
  ASSERT_EQ(c.points.size(), 6u);
  // The best grid point is one of the two neighbours of 1.5 %; the emulator finds 1.5 % within its interval.
  const double best = c.points[size_t(c.best)].x_si[0];
  EXPECT_TRUE(best == 0.01 || best == 0.02) << best;
  EXPECT_NEAR(c.optimum[0], 0.015, 0.002);
  EXPECT_LE(c.interval_lo[0], 0.015);
  EXPECT_GE(c.interval_hi[0], 0.015);
  EXPECT_LT(c.interval_lo[0], c.optimum[0]);
  EXPECT_GT(c.interval_hi[0], c.optimum[0]);
  EXPECT_LT(c.interval_hi[0] / c.interval_lo[0], 1.5);  // informative, not the whole axis
  EXPECT_FALSE(c.interval_open_lo[0] || c.interval_open_hi[0]);
  // chi2 of the best grid point by hand: SE of two replicates +-0.2 is 0.2.
  double chi2 = 0;
  for (const auto& o : c.obs) {
    const double content = o.conditions_si[0];
    const double r = o.value - truth(content, best);
    chi2 += r * r / (0.3 * 0.3 + 0.2 * 0.2);
  }
  EXPECT_NEAR(c.points[size_t(c.best)].chi2, chi2, 1e-9 * chi2);
  const std::string md = study::write_calibration(d + "/st", c);
  EXPECT_NE(md.find("(best)"), std::string::npos);
  // Refinement proposals land near the optimum, away from the sampled values.
  study::CalibrateOptions co;
  co.propose = 2;
  const study::Calibration p = study::calibrate(d + "/st", co);
  ASSERT_EQ(p.proposals.size(), 2u);
  EXPECT_GT(p.proposals[0][0], 0.01);
  EXPECT_LT(p.proposals[0][0], 0.02);
}

TEST(StudyCalibrate, ObservationTableErrorsNameTheRow) {
  const std::string d = study_temp("obs");
  write_text(d + "/ok.csv", "liquid.content,observable,value,sigma\n5 %,aor_deg_mean,30,1\n");
  fake_store(d, calib_study(d + "/ok.csv"), [](const study::PlannedRun&) {
    return nlohmann::json{{"aor_deg_mean", 30.0}};
  });
  const auto expect_row = [&](const std::string& table, const std::string& what) {
    write_text(d + "/bad.csv", table);
    study::CalibrateOptions o;
    o.observations = d + "/bad.csv";
    try {
      study::calibrate(d + "/st", o);
      ADD_FAILURE() << "accepted: " << table;
    } catch (const StudyError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("line 3"), std::string::npos) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
    }
  };
  const std::string head = "liquid.content,observable,value,sigma\n5 %,aor_deg_mean,30,1\n";
  expect_row(head + "10 %,aor_deg_mean,31,0\n", "sigma must be positive");
  expect_row(head + "10 %,aor_deg_mean,31,-1\n", "sigma must be positive");
  expect_row(head + "10 %,aor_deg_mean,31,\n", "sigma");
  expect_row(head + "10 %,aor_deg_mean,thirty,1\n", "value");
  expect_row(head + "10 %,aor_deg_mean,31\n", "fields");
  expect_row(head + "10 %,aor_max,31,1\n", "unknown observable");
  expect_row(head + "7 %,aor_deg_mean,31,1\n", "no run of the study has the conditions");
  expect_row(head + "7 lightyears,aor_deg_mean,31,1\n", "liquid.content");
  EXPECT_NO_THROW(study::calibrate(d + "/st"));
}

}  // namespace
}  // namespace wetdem::test
