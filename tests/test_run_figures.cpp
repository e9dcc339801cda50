// A run's figures (issue 21, app/run/figures.h): with figures on, the run draws figures/aor.png and
// figures/bed.png through scripts/plot_run.py and lists them in summary.json; the data the bed figure draws
// (the last frame and its fitted surface) is beside them. A plotting failure (here: no such python) leaves a
// complete run whose summary lists no figure and says why. A few seconds on lavapipe plus matplotlib.
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/run/run.h"
#include "support/gpu.h"
#include "support/small_case.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

class RunFigures : public GpuTest {};

fs::path fresh_dir(const std::string& what) {
  const fs::path d =
      fs::temp_directory_path() / ("wetdem_test_figures_" + what + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

app::RunOptions short_run(const fs::path& base) {
  std::ofstream(base / "small.toml") << kSmall;
  app::RunOptions o;
  o.case_path = (base / "small.toml").string();
  o.out_dir = (base / "run").string();
  o.quiet = true;
  o.context = &gpu();
  o.figures = true;
  o.overrides = {"output.checkpoint_interval=0", "run.duration=\"0.3 s\"",
                 "run.steady_state_start=\"0.1 s\""};
  return o;
}

bool is_png(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  char magic[8] = {};
  f.read(magic, 8);
  return f && std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

TEST_F(RunFigures, SummaryListsTheTwoFigures) {
  const fs::path base = fresh_dir("ok");
  const app::RunResult r = app::run_case(short_run(base));
  ASSERT_TRUE(r.completed);
  const nlohmann::json& s = r.summary;
  ASSERT_EQ(s["figures"], nlohmann::json({"figures/aor.png", "figures/bed.png"})) << s["figures_error"];
  EXPECT_EQ(s["figures_error"], "");
  for (const auto& f : s["figures"]) EXPECT_TRUE(is_png(base / "run" / f.get<std::string>())) << f;
  // What the bed figure drew: every particle of the last frame, the liquid scale, the fitted surface.
  std::ifstream in(base / "run" / "figures" / "plot_data.json");
  const nlohmann::json d = nlohmann::json::parse(in);
  EXPECT_EQ(d["frame"]["x_m"].size(), s["particles"].get<size_t>());
  EXPECT_EQ(d["frame"]["liquid_m3"].size(), s["particles"].get<size_t>());
  EXPECT_GT(d["frame"]["liquid_color_max_m3"].get<double>(), 0.0);
  EXPECT_TRUE(d["surface"].contains("valid"));
  EXPECT_EQ(d["summary"]["aor_deg_mean"], s["aor_deg_mean"]);
  // summary.json on disk says the same (written after the figures).
  std::ifstream sj(base / "run" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(sj)["figures"], s["figures"]);
  fs::remove_all(base);
}

TEST_F(RunFigures, AFailingPlotDoesNotFailTheRun) {
  const fs::path base = fresh_dir("nopython");
  app::RunOptions o = short_run(base);
  o.python = (base / "no-such-python3").string();
  const app::RunResult r = app::run_case(o);
  ASSERT_TRUE(r.completed);
  EXPECT_TRUE(fs::exists(base / "run" / "summary.json"));
  EXPECT_FALSE(fs::exists(base / "run" / "FAILED.txt"));
  EXPECT_TRUE(r.summary["figures"].empty());
  const std::string why = r.summary["figures_error"].get<std::string>();
  EXPECT_NE(why.find("failed"), std::string::npos) << why;
  EXPECT_NE(why.find("no-such-python3"), std::string::npos) << why;
  std::ifstream log(base / "run" / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("WARNING: figures:"), std::string::npos);
  fs::remove_all(base);
}

TEST_F(RunFigures, OffByDefaultForLibraryRuns) {
  const fs::path base = fresh_dir("off");
  app::RunOptions o = short_run(base);
  o.figures = false;  // what studies and diagnoses run with
  const app::RunResult r = app::run_case(o);
  ASSERT_TRUE(r.completed);
  EXPECT_FALSE(r.summary.contains("figures"));
  EXPECT_FALSE(fs::exists(base / "run" / "figures"));
  fs::remove_all(base);
}

}  // namespace
}  // namespace wetdem::test

#endif  // WETDEM_HAVE_APP
