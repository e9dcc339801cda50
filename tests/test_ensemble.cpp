// Ensembles (docs/ensembles.md): independent runs stepped together in one System, each bitwise equal to the
// same run done alone, and kept apart (runs never touch, even when their particles overlap in space).
#include <gtest/gtest.h>

#include "support/gpu.h"
#include "support/state_diff.h"
#include "support/twin.h"
#include "wetdem/system.h"

namespace wetdem::test {

class Ensemble : public GpuTest {};

namespace {

SimParams wet(double v_max, double mu_s, double omega) {
  SimParams prm = twin_drum_params(0.012, 0.012, 0.5e-3, false);
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.1;
  prm.liq_pp.theta = 0.5;
  prm.liq_pp.v_max = int64_t(v_max);
  prm.liquid_unit_m3 = 1e-20;
  prm.pp.mu_s = mu_s;
  prm.drum.omega = omega;
  return prm;
}

}  // namespace

TEST_F(Ensemble, EachRunIsBitwiseTheRunDoneAlone) {
  // Three runs that differ in bridges (V_max), friction, drum speed, wetness, size and packing; runs 0 and 2
  // start from the same packing, so they overlap in space and would collide if the runs could see each other.
  // Half-way, run 1's drum changes speed (set_run_params), as a drum run's settle -> rotate switch does.
  std::vector<SimParams> prm = {wet(1 << 28, 0.5, 6.0), wet(1 << 26, 0.3, 0.0), wet(1 << 28, 0.5, 3.0)};
  prm[2].liq_pp.enabled = false;
  prm[1].skin = 0.6e-3;  // the ensemble rebuilds on the thinnest skin; alone, each on its own
  std::vector<SystemState> s = {random_drum_packing(prm[0], 400, 0.5e-3, 0.8e-3, 31, 0.2),
                                random_drum_packing(prm[1], 330, 0.5e-3, 0.8e-3, 32, 0.2),
                                random_drum_packing(prm[2], 400, 0.5e-3, 0.8e-3, 31, 0.2)};
  for (auto& f : s[0].p.film) f = 1 << 27;
  for (auto& f : s[1].p.film) f = 1 << 26;
  SimParams turning = prm[1];
  turning.drum.omega = 5.0;

  std::vector<SystemState> alone;
  for (size_t r = 0; r < prm.size(); ++r) {
    System sys(gpu(), prm[r], s[r].p.size());
    sys.upload(s[r]);
    sys.step(150);
    if (r == 1) sys.set_run_params(0, turning);
    sys.step(150);
    alone.push_back(sys.download());
  }
  System ens(gpu(), prm, {s[0].p.size(), s[1].p.size(), s[2].p.size()});
  EXPECT_EQ(ens.runs(), 3u);
  ens.upload_runs(s);
  ens.step(150);
  ens.set_run_params(1, turning);
  ens.step(150);
  const std::vector<SystemState> together = ens.download_runs();
  ASSERT_EQ(together.size(), 3u);
  for (size_t r = 0; r < prm.size(); ++r) {
    EXPECT_EQ(first_difference(alone[r], together[r]), "") << "run " << r;
    EXPECT_EQ(together[r].total_liquid(), s[r].total_liquid()) << "run " << r;
  }
  EXPECT_GT(ens.counters().rebuilds, 3u);
  EXPECT_FALSE(alone[0].pairs.empty());
  // The runs did differ: wet and dry from one packing part ways.
  EXPECT_NE(first_difference(alone[0], alone[2]), "");
}

TEST_F(Ensemble, RunsThatCannotShareTheGridAreRefusedByName) {
  SimParams a = wet(1 << 28, 0.5, 6.0), b = a;
  b.drum.radius = 0.014;
  try {
    System ens(gpu(), {a, b}, {100, 100});
    ens.upload_runs({random_drum_packing(a, 100, 0.5e-3, 0.8e-3, 1, 0.2),
                     random_drum_packing(b, 100, 0.5e-3, 0.8e-3, 2, 0.2)});
    FAIL() << "an ensemble of two drum sizes was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("drum.radius"), std::string::npos) << e.what();
  }
  b = a;
  b.dt *= 0.5;
  EXPECT_THROW(
      {
        System ens(gpu(), {a, b}, {100, 100});
        ens.upload_runs({random_drum_packing(a, 100, 0.5e-3, 0.8e-3, 1, 0.2),
                         random_drum_packing(b, 100, 0.5e-3, 0.8e-3, 2, 0.2)});
      },
      std::invalid_argument);
}

}  // namespace wetdem::test
