// The benchmark's arithmetic (host/bench/traffic.h) against hand-worked values, and the device-memory
// bookkeeping it reads (System::device_memory, vk::Context::device_bytes) against the buffers a System
// really holds; the resource estimate (host/app/run/resources.h) uses the same bytes per particle and entry.
#ifdef WETDEM_HAVE_BENCH
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "app/drum/scenarios.h"
#include "app/run/resources.h"
#include "bench/traffic.h"
#include "support/gpu.h"
#include "wetdem/system.h"

namespace wetdem {
namespace {

TEST(BenchTraffic, RebuildIntervalIsStepsPerRebuild) {
  EXPECT_DOUBLE_EQ(*bench::rebuild_interval(1000, 40), 25.0);
  EXPECT_DOUBLE_EQ(*bench::rebuild_interval(7, 2), 3.5);
  EXPECT_FALSE(bench::rebuild_interval(1000, 0).has_value());  // no rebuild in the window: no interval
}

TEST(BenchTraffic, BytesPerStepByHand) {
  const bench::ElementBytes b{284, 60, 56, 64};
  // every step: 2 x 1000 x 284 + 2 x 20000 x (56 + 64) = 568,000 + 4,800,000
  // per rebuild: 2 x 1000 x (284 + 60) + 2 x 20000 x 56 = 688,000 + 2,240,000
  const bench::Traffic t = bench::step_traffic(b, 1000, 20000, 20.0);
  EXPECT_DOUBLE_EQ(t.every_step, 5368000.0);
  EXPECT_DOUBLE_EQ(t.per_rebuild, 2928000.0);
  EXPECT_DOUBLE_EQ(t.per_step, 5368000.0 + 2928000.0 / 20.0);
  EXPECT_DOUBLE_EQ(t.per_particle_step, (5368000.0 + 146400.0) / 1000.0);
  // No rebuild: the rebuild term is dropped, not divided by zero.
  EXPECT_DOUBLE_EQ(bench::step_traffic(b, 1000, 20000, std::nullopt).per_step, 5368000.0);
  // Two particle sets + scratch, and per entry two entry sets + scratch: 2 x 284 + 60 + 20 x (112 + 64).
  EXPECT_DOUBLE_EQ(bench::bytes_per_particle(b, 20.0), 628.0 + 3520.0);
}

TEST(BenchTraffic, BandwidthByDeviceName) {
  EXPECT_DOUBLE_EQ(bench::default_bandwidth("NVIDIA H100 80GB HBM3").gbs, 3350.0);
  EXPECT_DOUBLE_EQ(bench::default_bandwidth("NVIDIA H100 PCIe").gbs, 2000.0);
  EXPECT_DOUBLE_EQ(bench::default_bandwidth("NVIDIA H200").gbs, 4800.0);
  EXPECT_DOUBLE_EQ(bench::default_bandwidth("llvmpipe (LLVM 15.0.6, 256 bits)").gbs, 20.0);
  EXPECT_DOUBLE_EQ(bench::default_bandwidth("Some Unknown GPU").gbs, 0.0);
}

class BenchMemory : public test::GpuTest {};

// The byte counts the resource estimate multiplies by are the System's real buffer sizes, and the context's
// count of live device bytes covers the System and returns to where it was when the System is gone.
TEST_F(BenchMemory, DeviceMemoryMatchesBuffersAndEstimate) {
  Scenario sc = tumbling_wet_slice(400, 3);
  const double n = double(sc.state.p.size());
  const uint64_t before = test::gpu().device_bytes();
  {
    System sys(test::gpu(), sc.prm, sc.state.p.size());
    sys.upload(sc.state);
    sys.step(20);
    const DeviceMemory m = sys.device_memory();
    ASSERT_GT(m.entry_capacity, 0u);
    EXPECT_GE(m.entry_capacity, 2 * sys.counters().entries) << "each set holds the list";
    const double per_particle = double(m.particle_sets + m.particle_scratch) / n;
    EXPECT_DOUBLE_EQ(per_particle, app::device_bytes_per_particle(sc.prm.drum.periodic_z) -
                                       app::kDeviceCellBytesPerParticle - app::kSortScratchBytes);
    // By hand from buffer_set.h: 144 B per particle + 44 B per wall record, 2 sets, 64 B scratch.
    EXPECT_DOUBLE_EQ(app::device_bytes_per_particle(true), 2.0 * (144 + 44) + 64 + 8 + 64);
    EXPECT_DOUBLE_EQ(app::device_bytes_per_particle(false), 2.0 * (144 + 3 * 44) + 64 + 8 + 64);
    EXPECT_DOUBLE_EQ(double(m.entry_sets), double(m.entry_capacity) * app::kEntrySetBytes);
    // The scratch is sized for the larger set (it only grows): between the mean and the sum of the
    // capacities.
    EXPECT_EQ(m.entry_scratch % uint64_t(app::kEntryScratchBytes), 0u);
    EXPECT_GE(double(m.entry_scratch), 0.5 * double(m.entry_capacity) * app::kEntryScratchBytes);
    EXPECT_LE(double(m.entry_scratch), double(m.entry_capacity) * app::kEntryScratchBytes);
    EXPECT_DOUBLE_EQ(app::kDeviceBytesPerEntry, 128.0);  // 2 x 48 + 32, by hand from buffer_set.h
    // The grid holds at most max(8 n, 2^16) cells of two uint32 (system.cpp hashes a larger one).
    EXPECT_LE(double(m.grid), 8.0 * std::max(8.0 * n, 65536.0));
    const uint64_t live = test::gpu().device_bytes() - before;
    EXPECT_GE(live, m.total()) << "the context counts every buffer of the System";
    EXPECT_LT(double(live), 2.0 * double(m.total())) << "sort and scan scratch are small beside the state";
  }
  EXPECT_EQ(test::gpu().device_bytes(), before) << "every buffer released is uncounted";
}

}  // namespace
}  // namespace wetdem
#endif
