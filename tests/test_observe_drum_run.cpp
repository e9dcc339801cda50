// The camera observables in a micro drum run (closed drum with end plates, so the plate and centre slab
// angles exist): every one is in summary.json with a finite blocked standard error (the AoR drift, whose
// window is too short here, with the reason it is not reported), timeseries.csv has a
// column for each, and the frames carry the cluster of every particle. A few seconds on lavapipe
// (tests/support/small_case.h with its slice closed by rotating plates).
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/observe/camera.h"
#include "app/output/vtk_writer.h"
#include "app/run/run.h"
#include "support/gpu.h"
#include "support/small_case.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

class ObserveDrumRun : public GpuTest {};

TEST_F(ObserveDrumRun, ClosedDrumReportsEveryCameraObservableWithAnError) {
  const fs::path base = fs::temp_directory_path() / ("wetdem_test_observe_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base);
  // The small case's slice, closed by rotating end plates 18 mm apart.
  std::string text = kSmall;
  const auto swap = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  swap("periodic_slice = true", "periodic_slice = false");
  swap("slice_thickness = \"18 mm\"", "length = \"18 mm\"");
  std::ofstream(base / "small.toml") << text;
  app::RunOptions o;
  o.case_path = (base / "small.toml").string();
  o.out_dir = (base / "run").string();
  o.quiet = true;
  o.context = &gpu();
  // A shorter run than the small case's: 0.5 s of rotation, 16 samples in the window 0.2-0.5 s.
  o.overrides = {"output.formats=[\"vtk\"]", "output.checkpoint_interval=0", "run.duration=\"0.5 s\"",
                 "run.steady_state_start=\"0.2 s\"", "run.sample_interval=\"0.02 s\""};
  const app::RunResult r = app::run_case(o);
  ASSERT_TRUE(r.completed);
  const nlohmann::json& s = r.summary;

  for (const observe::CameraField& f : observe::kCameraFields) {
    const std::string name = f.name, sem = name + "_sem";
    ASSERT_TRUE(s.contains(name) && s[name].is_number()) << name << " = " << s.value(name, nlohmann::json());
    ASSERT_TRUE(s.contains(sem) && s[sem].is_number()) << sem;
    EXPECT_TRUE(std::isfinite(s[name].get<double>())) << name;
    EXPECT_GE(s[sem].get<double>(), 0.0) << sem;
  }
  // The drift per revolution needs a window of >= 1 revolution (app/output/window_rules.h): 0.3 s at 30 rpm
  // is 0.15 of one, so the keys are there, null, with the reason (test_window_rules.cpp has the long window).
  for (const char* k : {"aor_drift_deg_per_rev", "aor_drift_deg_per_rev_sem"})
    ASSERT_TRUE(s.contains(k) && s[k].is_null()) << k << " = " << s.value(k, nlohmann::json());
  EXPECT_NE(s["aor_drift_reason"].get<std::string>().find("0.15 revolutions"), std::string::npos)
      << s["aor_drift_reason"];

  // Plausibility on this bed (wet, V_min = 0, 30 rpm, plates turning with the drum: the whole bed is bridged
  // into one or a few agglomerates and is carried up far): the slab angles are centre-of-mass angles like
  // aor_deg, bridges make clusters of more than one particle, no liquid has left films and bridges.
  const double aor = s["aor_deg_mean"].get<double>();
  EXPECT_NEAR(s["aor_plate_deg"].get<double>(), aor, 15.0);
  EXPECT_NEAR(s["aor_centre_deg"].get<double>(), aor, 15.0);
  EXPECT_GT(s["agglomerate_size_mean"].get<double>(), 1.0);
  EXPECT_GT(s["drum_to_agglomerate_ratio"].get<double>(), 0.0);
  EXPECT_LT(s["drum_to_agglomerate_ratio"].get<double>(), 60e-3 / 4e-3);  // at most D / one mean particle
  EXPECT_EQ(s["liquid_free_fraction"].get<double>(), 1.0);                // liquid is conserved exactly
  EXPECT_EQ(s["liquid_free_fraction_sem"].get<double>(), 0.0);
  EXPECT_GE(s["flowing_layer_depth_m"].get<double>(), 0.0);

  // timeseries.csv: one column per observable, each filled in some sample of the window; sample by sample
  // the fitted surface follows the centre-of-mass angle (median difference below 10°; the two differ when
  // the bed is lifted as a block, so the means may not).
  std::ifstream ts(base / "run" / "timeseries.csv");
  std::string header, line;
  std::getline(ts, header);
  std::vector<std::string> names;
  {
    std::stringstream hs(header);
    for (std::string cell; std::getline(hs, cell, ',');) names.push_back(cell);
  }
  std::vector<size_t> filled(names.size(), 0);
  std::vector<double> diff;
  const size_t i_aor = 1,
               i_surface = size_t(std::find(names.begin(), names.end(), "aor_surface_deg") - names.begin());
  while (std::getline(ts, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    cells.resize(names.size());
    if (std::stod(cells[0]) < 0.25 + 0.2) continue;
    for (size_t i = 0; i < names.size(); ++i) filled[i] += !cells[i].empty();
    if (!cells[i_aor].empty() && !cells[i_surface].empty())
      diff.push_back(std::fabs(std::stod(cells[i_surface]) - std::stod(cells[i_aor])));
  }
  for (const observe::CameraField& f : observe::kCameraFields) {
    const size_t i = size_t(std::find(names.begin(), names.end(), f.name) - names.begin());
    ASSERT_LT(i, names.size()) << f.name;
    EXPECT_GT(filled[i], 0u) << f.name;
  }
  ASSERT_GE(diff.size(), 8u);
  std::nth_element(diff.begin(), diff.begin() + long(diff.size() / 2), diff.end());
  EXPECT_LT(diff[diff.size() / 2], 10.0);

  // The last frame colours agglomerates: cluster label and size per particle.
  const auto frames = read_pvd((base / "run" / "frames" / "frames.pvd").string());
  ASSERT_FALSE(frames.empty());
  const VtpData d = read_vtp((base / "run" / "frames" / frames.back().second).string());
  ASSERT_TRUE(d.point_data.count("cluster"));
  ASSERT_TRUE(d.point_data.count("cluster_size"));
  double largest = 0;
  for (double c : d.point_data.at("cluster_size")) largest = std::max(largest, c);
  EXPECT_GT(largest, 1.0);
  fs::remove_all(base);
}

}  // namespace
}  // namespace wetdem::test

#endif  // WETDEM_HAVE_APP
