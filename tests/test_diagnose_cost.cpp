// The cost guard (Procedure::cost, max_cost) counts a variant's particle-steps against the baseline's at the
// same condition. A table with one long row (a 12 s run beside 3 s ones, as a reach's measurement adds) must
// not count every variant's long run against the short baseline: that capped every probe's strength.
// Planning only; nothing runs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "diagnose/driver.h"
#include "diagnose/files.h"
#include "diagnose/procedure.h"

namespace {

namespace fs = std::filesystem;
using wetdem::diagnose::DiagnoseOptions;
using wetdem::diagnose::parse_diagnosis_file;
using wetdem::diagnose::Procedure;

struct CostDir {
  fs::path p = fs::temp_directory_path() / ("wetdem-cost-" + std::to_string(::getpid()));
  CostDir() {
    fs::remove_all(p);
    fs::create_directories(p);
  }
  ~CostDir() { fs::remove_all(p); }
};

TEST(DiagnoseCost, ALongRowCostsItsOwnBaselineNotTheFirstRowsOne) {
  CostDir dir;
  // Two conditions of the micro model: the shipped 0.3 s window, and a 4x longer one.
  std::ofstream(dir.p / "obs.csv") << "liquid.content,run.duration,observable,value,sigma,n,note\n"
                                      "\"5 %\",\"0.3 s\",aor_deg_mean,30,1,2,short\n"
                                      "\"5 %\",\"1.2 s\",aor_deg_mean,30,1,2,long\n";
  std::ofstream(dir.p / "d.toml") << "name = \"cost\"\ncase = \"" << WETDEM_SOURCE_DIR
                                  << "/assets/diagnosis/micro/model.toml\"\nobservations = \"obs.csv\"\n"
                                     "effects = [\"viscous\"]\nreplicates = 2\n\n[probes]\n"
                                     "viscous = [0.003, 0.01, 0.1]\n";
  DiagnoseOptions o;
  o.out = (dir.p / "out").string();
  o.store = (dir.p / "store").string();
  o.quiet = true;
  const Procedure p(parse_diagnosis_file((dir.p / "d.toml").string()), o);
  ASSERT_EQ(p.tab.conditions.size(), 2u);
  // The table keeps its conditions in the order of their first row: the short one first, as in the flowing
  // table that showed the fault.
  const auto& shortc = p.tab.conditions[0];
  const auto& longc = p.tab.conditions[1];
  const double base_short = p.book.particle_steps(shortc, p.variant("", 0));
  const double base_long = p.book.particle_steps(longc, p.variant("", 0));
  ASSERT_GT(base_long, 2.0 * base_short) << "the long row is not longer (settle 0.2 s + run)";

  // The baseline itself costs one baseline run at every row (the first row's unit made it cost 2.8).
  EXPECT_NEAR(p.cost(p.variant("", 0)), 1.0, 1e-9);
  // Strong lubrication lowers the time step (the damper's limit): its cost is that ratio, the same at either
  // row, not the long row's run over the short row's baseline.
  const auto visc = p.variant("viscous", 0.1);
  const double at_short = p.book.particle_steps(shortc, visc) / base_short;
  const double at_long = p.book.particle_steps(longc, visc) / base_long;
  ASSERT_GT(at_short, 1.0) << "the damper did not lower the time step: the test shows nothing";
  EXPECT_NEAR(p.cost(visc), std::max(at_short, at_long), 1e-9);
  EXPECT_LT(p.cost(visc), 1.01 * at_short);
}

}  // namespace
