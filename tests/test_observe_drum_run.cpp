// The camera observables in a micro drum run (closed drum with end plates, so the plate and centre slab
// angles exist): every one is in summary.json with a finite blocked standard error, timeseries.csv has a
// column for each, and the frames carry the cluster of every particle. A few seconds on lavapipe
// (tests/support/small_case.h with its slice closed by rotating plates).
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>
#include <unistd.h>

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
  o.overrides = {"output.formats=[\"vtk\"]", "output.checkpoint_interval=0"};
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
  for (const char* k : {"aor_drift_deg_per_rev", "aor_drift_deg_per_rev_sem"})
    ASSERT_TRUE(s.contains(k) && s[k].is_number()) << k;
  EXPECT_GT(s["aor_drift_deg_per_rev_sem"].get<double>(), 0.0);

  // Plausibility on this bed (wet, V_min = 0, rolling at 30 rpm): the surface and slab angles are AoR-like,
  // bridges make clusters of more than one particle, and no liquid has left films and bridges.
  const double aor = s["aor_deg_mean"].get<double>();
  EXPECT_NEAR(s["aor_surface_deg"].get<double>(), aor, 15.0);
  EXPECT_NEAR(s["aor_plate_deg"].get<double>(), aor, 15.0);
  EXPECT_NEAR(s["aor_centre_deg"].get<double>(), aor, 15.0);
  EXPECT_GT(s["agglomerate_size_mean"].get<double>(), 1.0);
  EXPECT_GT(s["drum_to_agglomerate_ratio"].get<double>(), 0.0);
  EXPECT_LT(s["drum_to_agglomerate_ratio"].get<double>(), 60e-3 / 4e-3);  // at most D / one mean particle
  EXPECT_EQ(s["liquid_free_fraction"].get<double>(), 1.0);                // liquid is conserved exactly
  EXPECT_EQ(s["liquid_free_fraction_sem"].get<double>(), 0.0);
  EXPECT_GE(s["flowing_layer_depth_m"].get<double>(), 0.0);

  // timeseries.csv: one column per observable, filled in the rotating part.
  std::ifstream ts(base / "run" / "timeseries.csv");
  std::string header, line, last;
  std::getline(ts, header);
  for (const observe::CameraField& f : observe::kCameraFields)
    EXPECT_NE(header.find(f.name), std::string::npos) << f.name;
  while (std::getline(ts, line)) last = line;
  EXPECT_EQ(last.find(",,"), std::string::npos) << last;  // the last sample has every value

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
