// physics.md §7.8 on the GPU: an agitated wet packing of 1,000 particles in a turning drum, with more than
// one formation and one rupture per step on average, keeps Σ films + Σ bridges exactly (integers), checked
// every 100 steps. CI runs 2,000 steps; `wetdem_bench --soak 1000000` runs the full count.
#include <gtest/gtest.h>

#include "app/drum/scenarios.h"
#include "support/gpu.h"
#include "wetdem/system.h"

namespace wetdem::test {

class LiquidSoak : public GpuTest {};

TEST_F(LiquidSoak, TumblingWetPackingConservesLiquidExactly) {
  Scenario sc = tumbling_wet_slice(1000, 3);
  ASSERT_EQ(sc.state.p.size(), 1000u);
  System sys(gpu(), sc.prm, sc.state.p.size());
  sys.upload(sc.state);
  const int64_t total = sc.state.total_liquid();
  uint64_t formations = 0, ruptures = 0;
  const int chunks = 20, per_chunk = 100;
  for (int c = 0; c < chunks; ++c) {
    sys.step(per_chunk);
    SystemState s = sys.download();
    ASSERT_EQ(s.total_liquid(), total) << "after " << (c + 1) * per_chunk << " steps";
    EventCounts e = sys.read_events();
    formations += e.formations;
    ruptures += e.ruptures;
  }
  Observables o = sys.observables();
  std::printf(
      "soak: 1000 particles, %d steps, %llu formations, %llu ruptures, %llu bridges now, liquid exact\n",
      chunks * per_chunk, (unsigned long long)formations, (unsigned long long)ruptures,
      (unsigned long long)o.bridges);
  EXPECT_GT(formations, uint64_t(chunks * per_chunk)) << "fewer than one formation per step";
  EXPECT_GT(ruptures, uint64_t(chunks * per_chunk)) << "fewer than one rupture per step";
  EXPECT_EQ(sys.counters().lost_bridges, 0u);
}

}  // namespace wetdem::test
