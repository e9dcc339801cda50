// The sinks' per-particle buffers (pore, evaporated, pore capacity) travel with the GPU state: a snapshot
// restored into a fresh system continues bitwise (checkpoints), and download/upload keeps pores and
// evaporated counters exactly (ARCHITECTURE.md "Liquid sinks").
#include <gtest/gtest.h>

#include <cmath>

#include "support/gpu.h"
#include "support/twin.h"
#include "wetdem/system.h"

namespace wetdem::test {
namespace {

class SinksState : public GpuTest {};

SimParams sink_params() {
  SimParams prm = twin_drum_params(0.012, 0.012, 0.9e-3, false);
  prm.liquid_unit_m3 = 4.0 / 3.0 * 3.14159265358979 * std::pow(0.95e-3, 3) * std::ldexp(1.0, -40);
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.1;
  prm.liq_pp.theta = 0.5;
  prm.liq_pp.v_max = int64_t(std::ldexp(1.0, 40) * 2e-4);
  prm.sinks.pore_capacity = 6e-4;
  prm.sinks.absorption_rate = 300.0;
  prm.sinks.evaporation_time = 0.02;
  return prm;
}

TEST_F(SinksState, SnapshotRestoreAndDownloadUploadCarryPoresAndEvaporated) {
  const SimParams prm = sink_params();
  SystemState s = random_drum_packing(prm, 300, 0.9e-3, 1.0e-3, 5, 0.1);
  for (size_t k = 0; k < s.p.size(); ++k) s.p.film[k] = int64_t(std::ldexp(1.0, 40) * 1e-3);
  const int64_t total0 = s.total_liquid();
  System a(gpu(), prm, s.p.size());
  a.upload(s);
  a.step(150);
  const std::vector<uint8_t> snap = a.snapshot();
  a.step(150);
  const SystemState sa = a.download();
  System b(gpu(), prm, s.p.size());
  b.restore(snap);
  b.step(150);
  const SystemState sb = b.download();
  EXPECT_EQ(sb.p.x, sa.p.x);
  EXPECT_EQ(sb.p.film, sa.p.film);
  EXPECT_EQ(sb.p.pore, sa.p.pore);
  EXPECT_EQ(sb.p.evaporated, sa.p.evaporated);
  EXPECT_EQ(sa.total_liquid(), total0);
  const LiquidBudget lb = sa.liquid_budget();
  EXPECT_GT(lb.pores, 0);
  EXPECT_GT(lb.evaporated, 0);
  // download -> upload -> download: the integer stores come back unchanged.
  System c(gpu(), prm, s.p.size());
  c.upload(sa);
  const SystemState sc = c.download();
  EXPECT_EQ(sc.p.pore, sa.p.pore);
  EXPECT_EQ(sc.p.evaporated, sa.p.evaporated);
  EXPECT_EQ(sc.total_liquid(), total0);
}

}  // namespace
}  // namespace wetdem::test
