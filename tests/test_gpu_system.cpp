// GPU-system properties that have no reference counterpart: the neighbour list against brute force, history
// across forced rebuilds and reorders, bitwise determinism, and buffer growth on overflow.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <tuple>

#include <fmt/format.h>

#include "support/gpu.h"
#include "support/state_diff.h"
#include "support/twin.h"
#include "wetdem/system.h"

namespace wetdem::test {

class GpuSystem : public GpuTest {};

namespace {

// The wet drum of the determinism tests: pair bridges on, films set by each test.
SimParams wet_drum_params(bool periodic = false) {
  SimParams prm = twin_drum_params(0.012, 0.012, 0.5e-3, periodic);
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.1;
  prm.liq_pp.theta = 0.5;
  prm.liq_pp.v_max = 1 << 28;
  prm.liquid_unit_m3 = 1e-20;
  return prm;
}

// Pairs whose surface gap is below S_c,max + skin, by brute force in double precision.
std::vector<std::pair<uint32_t, uint32_t>> brute_force_pairs(const SystemState& s, const SimParams& prm,
                                                             double slack, size_t& borderline) {
  const double cut = prm.bridge_range_pp() + prm.skin;
  std::vector<std::pair<uint32_t, uint32_t>> out;
  borderline = 0;
  for (uint32_t i = 0; i < s.p.size(); ++i)
    for (uint32_t j = i + 1; j < s.p.size(); ++j) {
      glm::dvec3 d = s.p.x[i] - s.p.x[j];
      if (prm.drum.periodic_z) d.z -= prm.drum.length * std::round(d.z / prm.drum.length);
      double gap = glm::length(d) - s.p.radius[i] - s.p.radius[j];
      if (std::abs(gap - cut) < slack) borderline++;
      if (gap < cut) out.emplace_back(i, j);
    }
  return out;
}

}  // namespace

TEST_F(GpuSystem, NeighbourListEqualsBruteForce) {
  for (bool periodic : {false, true}) {
    SimParams prm = twin_drum_params(0.012, 0.012, 0.5e-3, periodic);
    prm.liq_pp.enabled = true;  // a bridge range widens the cutoff beyond contact
    prm.liq_pp.theta = 0.5;
    prm.liq_pp.v_max = 1 << 20;
    prm.liquid_unit_m3 = 1e-16;
    SystemState s = random_drum_packing(prm, 1500, 0.5e-3, 0.8e-3, 3, 0.3);
    System sys(gpu(), prm, s.p.size());
    sys.upload(s);
    for (int round = 0; round < 3; ++round) {
      SystemState g = sys.download();
      size_t borderline = 0;
      auto expect = brute_force_pairs(g, prm, 1e-9, borderline);
      ASSERT_EQ(borderline, 0u) << "a pair sits within float rounding of the cutoff: change the seed";
      EXPECT_EQ(sys.neighbour_pairs(), expect) << "periodic " << periodic << " round " << round;
      EXPECT_GT(expect.size(), g.p.size());
      sys.force_rebuild();
      sys.step(50);
    }
  }
}

TEST_F(GpuSystem, SlidingPairKeepsItsSpringAcrossForcedRebuildAndReorder) {
  SimParams prm = twin_drum_params(0.02, 0.02, 1e-3, false);
  prm.gravity = glm::dvec3(0.0, 0.0, -9.81);  // presses particle 0 onto particle 1, 1 onto the lower plate
  prm.pp.mu_r = 0.0;
  // Particle 1 sits in a lower cell than particle 0, so the first cell sort swaps them.
  SystemState s;
  s.p.resize(2);
  set_sphere(s.p, 1, {0.0, 0.0, -0.01 + 1e-3}, 1e-3, 900);
  set_sphere(s.p, 0, {0.0, 0.0, -0.01 + 3e-3 - 1e-6}, 1e-3, 900);
  s.p.v[0] = {0.01, 0.0, 0.0};  // tangential sliding
  auto run = [&](bool rebuild_every_step) {
    System sys(gpu(), prm, 2);
    sys.upload(s);
    std::vector<glm::dvec3> springs;
    for (int k = 0; k < 40; ++k) {
      if (rebuild_every_step) sys.force_rebuild();
      sys.step(1);
      SystemState g = sys.download();
      springs.push_back(g.pairs.empty() ? glm::dvec3(0.0) : g.pairs[0].spring_t);
    }
    EXPECT_GE(sys.counters().rebuilds, rebuild_every_step ? 40u : 0u);
    return springs;
  };
  auto plain = run(false), rebuilt = run(true);
  ASSERT_GT(glm::length(plain.back()), 0.0);
  for (size_t k = 0; k < plain.size(); ++k) EXPECT_EQ(plain[k], rebuilt[k]) << "step " << k;
}

TEST_F(GpuSystem, SameRunTwiceIsBitwiseIdentical) {
  SimParams prm = wet_drum_params();
  SystemState s = random_drum_packing(prm, 1200, 0.5e-3, 0.8e-3, 5, 0.2);
  for (auto& f : s.p.film) f = 1 << 27;
  auto run = [&] {
    System sys(gpu(), prm, s.p.size());
    sys.upload(s);
    sys.step(1000);
    EXPECT_GT(sys.counters().rebuilds, 2u);
    return sys.download();
  };
  SystemState a = run(), b = run();
  EXPECT_TRUE(bitwise_equal(a, b));
  EXPECT_EQ(a.total_liquid(), s.total_liquid());
}

TEST_F(GpuSystem, ContactBufferGrowsOnOverflowAndLosesNothing) {
  SimParams prm = twin_drum_params(0.012, 0.012, 0.5e-3, false);
  // One entry per particle: the list overflows at its first build, the buffers grow and the step is
  // finished; the result must be bitwise that of a run that never overflowed.
  SystemState s = random_drum_packing(prm, 800, 0.5e-3, 0.8e-3, 9, 0.2);
  auto run = [&](uint32_t per_particle) {
    SystemOptions o;
    o.initial_entries_per_particle = per_particle;
    System sys(gpu(), prm, s.p.size(), o);
    sys.upload(s);
    sys.step(600);
    auto c = sys.counters();
    return std::make_pair(sys.download(), c.regrows);
  };
  auto [small, regrows_small] = run(1);
  auto [big, regrows_big] = run(64);
  EXPECT_GT(regrows_small, 0u);
  EXPECT_EQ(regrows_big, 0u);
  EXPECT_TRUE(bitwise_equal(small, big)) << "growing the buffers changed the result";
}

TEST_F(GpuSystem, SplitRebuildsAreBitwiseTheGatedChain) {
  // The rebuild chain submitted on its own when a step halts for it must give bitwise the state of the chain
  // recorded, gated, into every step: wet pairs, rebuilds, a list that overflows and grows, and batches of
  // any length (one step at a time, or many).
  SimParams prm = wet_drum_params();
  prm.skin = 0.6e-3;  // rebuilds ~8 steps apart
  SystemState s = random_drum_packing(prm, 500, 0.5e-3, 0.8e-3, 11, 0.02);
  for (auto& f : s.p.film) f = 1 << 27;
  auto run = [&](bool split, uint32_t per_particle, bool one_at_a_time) {
    SystemOptions o;
    o.split_rebuilds = split;
    o.split_min_interval = 1.0;  // split at any rebuild interval (the default waits for 8 steps)
    o.initial_entries_per_particle = per_particle;
    System sys(gpu(), prm, s.p.size(), o);
    sys.upload(s);
    if (one_at_a_time)
      for (int k = 0; k < 100; ++k) sys.step(1);
    else
      sys.step(100);
    sys.step(250);
    return std::make_pair(sys.download(), sys.counters());
  };
  const auto [gated, cg] = run(false, 16, false);
  EXPECT_GT(cg.rebuilds, 3u);
  for (bool one : {false, true}) {
    for (uint32_t per : {16u, 1u}) {
      const auto [split, cs] = run(true, per, one);
      EXPECT_TRUE(bitwise_equal(gated, split)) << "entries/particle " << per << ", one at a time " << one;
      // A rebuild on a batch's last step builds at x^n (the next kick-drift starts the next batch), one on
      // any other step at x^(n+1) (folded into its gather): batch lengths move the schedule a little, never
      // the result.
      EXPECT_NEAR(double(cs.rebuilds), double(cg.rebuilds), 0.1 * double(cg.rebuilds) + 2.0) << per << one;
      EXPECT_GT(cs.split_rebuilds, cs.rebuilds / 2) << "split batches did not halt for most rebuilds";
      EXPECT_EQ(cg.split_rebuilds, 0u);
      EXPECT_EQ(cs.regrows > 0, per == 1u);
    }
  }
}

TEST_F(GpuSystem, RestoredSnapshotStepsBitwiseAsTheContinuedRun) {
  // The System-level half of a resumed run (DrumRun.ResumeReachesTheBitwiseSameFinalState adds the run
  // phases): a snapshot taken mid-run, restored into a new System, must step to bitwise the state of the run
  // that went on, through rebuilds and bridge events. (On the H100 the drum-level resume was not bitwise,
  // docs/benchmark.md "On a GPU"; this test separates the System from the run phases there.)
  SimParams prm = wet_drum_params();
  SystemState s = random_drum_packing(prm, 600, 0.5e-3, 0.8e-3, 13, 0.2);
  for (auto& f : s.p.film) f = 1 << 27;
  System first(gpu(), prm, s.p.size());
  first.upload(s);
  first.step(150);
  const std::vector<uint8_t> snap = first.snapshot();
  const uint64_t r0 = first.counters().rebuilds;
  first.step(250);
  EXPECT_GT(first.counters().rebuilds, r0 + 2);
  const SystemState a = first.download();

  System second(gpu(), prm, s.p.size());
  second.restore(snap);
  second.step(250);
  const SystemState b = second.download();
  EXPECT_TRUE(bitwise_equal(a, b)) << "a restored snapshot stepped differently from the run that went on";
  EXPECT_EQ(a.total_liquid(), s.total_liquid());
  EXPECT_EQ(b.total_liquid(), s.total_liquid());
}

TEST_F(GpuSystem, StepsWriteTheirScratchBeforeReadingIt) {
  // Scratch (the set being built, pair results, liquid and rebuild scratch) is not in a snapshot: a restored
  // System has it zeroed where the run that went on holds the last step's values. Filled with a pattern, it
  // must change nothing, or a resumed run drifts from the uninterrupted one (a late divergence on the H100).
  SimParams prm = wet_drum_params();
  prm.drum.omega = 6.0;
  SystemState s = random_drum_packing(prm, 600, 0.5e-3, 0.8e-3, 17, 0.2);
  for (auto& f : s.p.film) f = 1 << 27;
  System first(gpu(), prm, s.p.size());
  first.upload(s);
  first.step(120);
  const std::vector<uint8_t> snap = first.snapshot();
  for (uint32_t word : {0u, 1u, 0x00800001u}) {
    System a(gpu(), prm, s.p.size()), b(gpu(), prm, s.p.size());
    a.restore(snap);
    b.restore(snap);
    b.fill_scratch(word);
    for (int k = 0; k < 30; ++k) {
      a.step(10);
      b.step(10);
      if (k % 3 == 0) b.fill_scratch(word);
      ASSERT_EQ(first_difference(a.download(), b.download()), "")
          << "scratch filled with " << word << ": first difference by step " << 120 + 10 * (k + 1);
    }
    EXPECT_GT(a.counters().rebuilds, 3u);
  }
}

TEST_F(GpuSystem, RunIsBitwiseIndependentOfTheRebuildSchedule) {
  // Segments are ordered by the partners' stable ids (nbr_fill.comp), so the sums of a step do not depend on
  // when the list was built: a thin and a thick skin, rebuilds forced every 7 steps, split or gated chains
  // all give bitwise the same wet rotating run, with different rebuild counts. Ensembles rely on it: their
  // runs share one rebuild schedule, and each must stay bitwise the run done alone.
  SimParams prm = wet_drum_params();
  prm.drum.omega = 6.0;
  SystemState s = random_drum_packing(prm, 500, 0.5e-3, 0.8e-3, 23, 0.2);
  for (auto& f : s.p.film) f = 1 << 27;
  auto run = [&](double skin, bool split, bool force) {
    SimParams q = prm;
    q.skin = skin;
    SystemOptions o;
    o.split_rebuilds = split;
    o.split_min_interval = 1.0;
    System sys(gpu(), q, s.p.size(), o);
    sys.upload(s);
    for (int k = 0; k < 40; ++k) {
      if (force) sys.force_rebuild();
      sys.step(7);
    }
    return std::make_pair(sys.download(), sys.counters().rebuilds);
  };
  const auto [ref, r_ref] = run(0.3e-3, false, false);
  EXPECT_GT(r_ref, 4u);
  for (auto [skin, split, force] :
       {std::tuple{0.8e-3, false, false}, std::tuple{0.3e-3, true, true}, std::tuple{1.2e-3, true, false}}) {
    const auto [x, r] = run(skin, split, force);
    EXPECT_NE(r, r_ref) << "skin " << skin << ": the schedule did not change";
    EXPECT_EQ(first_difference(ref, x), "") << "skin " << skin << ", split " << split << ", forced " << force;
  }
  EXPECT_GT(ref.pairs.size(), 100u);
  EXPECT_EQ(ref.total_liquid(), s.total_liquid());
}

}  // namespace wetdem::test

namespace wetdem::test {

TEST_F(GpuSystem, SkinTestInTheDrumFrameMissesNoPair) {
  // The skin test measures each displacement from the reference turned with the drum and rebuilds when the
  // two largest add up to the skin (step_control.glsl). Every pair must be listed before it touches: each
  // rule must give bitwise the run whose list is rebuilt before every step, in a closed drum and in a
  // periodic slice (turned references, wrapped z). The worst case for the rule: pairs on head-on courses,
  // just outside the list when it is built (gap = reach + 1.01 skin), each particle moving at the same speed
  // relative to a fast drum (20 rad/s) that carries them, or to the drum at rest, some across the periodic
  // boundary. A rule that
  // counts an approach short by a tenth lets them touch unlisted (checked). Then a loose lattice turning with
  // the drum, touching and bridged, which barely moves relative to it: the drum frame must save most rebuilds
  // there.
  for (bool periodic : {false, true})
    for (auto [head_on, omega] : {std::pair{true, 20.0}, std::pair{true, 0.0}, std::pair{false, 20.0}}) {
      SimParams prm = wet_drum_params(periodic);
      prm.drum.omega = omega;
      prm.skin = 0.3e-3;
      SystemState s;
      if (head_on) {
        prm.gravity = glm::dvec3(0.0);
        prm.liquid_unit_m3 = 1e-24;  // bridges of ~10 um reach: a new pair's slack is the skin alone
        std::mt19937_64 rng(37);
        std::uniform_real_distribution<double> uni(-1.0, 1.0);
        const double r = 0.5e-3, gap = prm.bridge_range_pp() + 1.01 * prm.skin, v = 0.15;
        std::vector<glm::dvec3> centres;
        for (double x = -8e-3; x <= 8e-3; x += 4e-3)
          for (double y = -8e-3; y <= 8e-3; y += 4e-3)
            for (double z : {-3e-3, 3e-3})
              if (std::hypot(x, y) < 9e-3) centres.push_back({x, y, z});
        s.p.resize(2 * centres.size());
        for (size_t c = 0; c < centres.size(); ++c) {
          glm::dvec3 dir(uni(rng), uni(rng), uni(rng));
          if (periodic && c % 4 == 0) {  // across the periodic boundary, along z
            dir = glm::dvec3(0.1 * uni(rng), 0.1 * uni(rng), 1.0);
            centres[c].z = 0.5 * prm.drum.length;
          }
          dir = glm::normalize(dir);
          for (int side : {-1, 1}) {
            const size_t k = 2 * c + (side > 0);
            glm::dvec3 x = centres[c] + double(side) * (r + 0.5 * gap) * dir;
            if (periodic) x.z -= prm.drum.length * std::round(x.z / prm.drum.length);
            set_sphere(s.p, k, x, r, 900.0);
            s.p.v[k] = -double(side) * v * dir + prm.drum.omega * glm::dvec3(-x.y, x.x, 0.0);
          }
        }
      } else {
        s = random_drum_packing(prm, 500, 0.6e-3, 0.6e-3, 31, 0.0);
        for (size_t k = 0; k < s.p.size(); ++k) {
          set_sphere(s.p, k, s.p.x[k], 0.597e-3, 900.0);  // touching: 6 um overlaps
          s.p.v[k] = prm.drum.omega * glm::dvec3(-s.p.x[k].y, s.p.x[k].x, 0.0);
          s.p.w[k] = glm::dvec3(0.0, 0.0, prm.drum.omega);
        }
      }
      for (auto& f : s.p.film) f = 1 << 27;
      const int steps = 240;
      uint64_t formations = 0;  // bridges formed, one per first contact (of the last run)
      auto run = [&](bool drum_frame, bool top_two, bool every_step) {
        SystemOptions o;
        o.skin_drum_frame = drum_frame;
        o.skin_top_two = top_two;
        System sys(gpu(), prm, s.p.size(), o);
        sys.upload(s);
        for (int k = 0; k < steps; k += every_step ? 1 : 40) {
          if (every_step) sys.force_rebuild();
          sys.step(every_step ? 1 : 40);
        }
        formations = sys.read_events().formations;
        return std::make_pair(sys.download(), sys.counters().rebuilds);
      };
      const std::string where = fmt::format("periodic {}, head-on {}, omega {}", periodic, head_on, omega);
      const auto [ref, r_ref] = run(false, false, true);
      const uint64_t ref_formations = formations;
      const auto [classic, r_classic] = run(false, false, false);
      const auto [frame, r_frame] = run(true, false, false);
      const auto [both, r_both] = run(true, true, false);
      EXPECT_EQ(first_difference(ref, classic), "") << "classic rule, " << where;
      EXPECT_EQ(first_difference(ref, frame), "") << "drum frame, " << where;
      EXPECT_EQ(first_difference(ref, both), "") << "drum frame and the two largest, " << where;
      EXPECT_GE(r_classic, 1u) << where;
      EXPECT_LE(r_both, r_frame) << where;
      if (head_on) {  // every pair came into contact: a bridge formed
        EXPECT_GE(ref_formations, s.p.size() / 2) << where;
      } else {
        EXPECT_LT(2 * r_frame, r_classic) << where << ": the drum frame saved few rebuilds";
        EXPECT_GT(ref.pairs.size(), 100u) << where;
      }
      EXPECT_EQ(ref.total_liquid(), s.total_liquid()) << where;
      RecordProperty(fmt::format("rebuilds_{}_{}_{}", periodic ? "periodic" : "closed",
                                 head_on ? "head_on" : "lattice", omega),
                     fmt::format("{} classic, {} drum frame, {} with the two largest (of {} steps)",
                                 r_classic, r_frame, r_both, steps));
    }
}

TEST_F(GpuSystem, FusedStepIsBitwiseTheStepPassByPass) {
  // The fused step (kick-drift folded into the gather, liquid pass 4a there, the films changed by 4b/4d with
  // integer atomics, the liquid passes behind a gate, the rebuild decision in a last workgroup) must give
  // bitwise the state and events of the step recorded pass by pass, whatever the batch lengths (a submit's
  // last step does not fold its kick-drift; a halted split step leaves it done for the next submit): a wet
  // closed drum turning, with wall bridges, and the liquid sinks on.
  SimParams prm = wet_drum_params();
  prm.drum.omega = 6.0;
  prm.skin = 0.4e-3;
  for (LiquidParams& l : prm.liq_pw) l = prm.liq_pp;
  SystemState s = random_drum_packing(prm, 500, 0.5e-3, 0.8e-3, 29, 0.2);
  for (auto& f : s.p.film) f = 1 << 27;
  for (bool sinks : {false, true}) {
    SimParams q = prm;
    if (sinks) {
      q.sinks.evaporation_time = 0.05;
      q.sinks.absorption_rate = 20.0;
      q.sinks.pore_capacity = 0.01;
    }
    auto run = [&](bool fused, bool gate, bool split, uint32_t per_submit, bool one_at_a_time) {
      SystemOptions o;
      o.fused_step = fused;
      o.liquid_gate = gate;
      o.split_rebuilds = split;
      o.split_min_interval = 1.0;
      o.steps_per_submit = per_submit;
      System sys(gpu(), q, s.p.size(), o);
      sys.upload(s);
      if (one_at_a_time)
        for (int k = 0; k < 60; ++k) sys.step(1);
      sys.step(one_at_a_time ? 180 : 240);
      EventCounts ev = sys.read_events();
      return std::make_tuple(sys.download(), ev, sys.counters());
    };
    const auto [ref, ev_ref, c_ref] = run(false, false, false, 200, false);
    EXPECT_GT(c_ref.rebuilds, 4u);
    EXPECT_GT(ev_ref.formations, 10u);
    EXPECT_GT(ev_ref.ruptures, 10u);
    EXPECT_EQ(ref.total_liquid(), s.total_liquid());
    for (auto [gate, split, per, one] :
         {std::tuple{true, true, 200u, false}, std::tuple{true, false, 200u, false},
          std::tuple{false, true, 7u, false}, std::tuple{true, true, 3u, true},
          std::tuple{true, false, 1u, true}}) {
      const auto [x, ev, c] = run(true, gate, split, per, one);
      EXPECT_EQ(first_difference(ref, x), "")
          << "sinks " << sinks << ", gate " << gate << ", split " << split << ", per submit " << per;
      EXPECT_EQ(ev.formations, ev_ref.formations);
      EXPECT_EQ(ev.ruptures, ev_ref.ruptures);
      EXPECT_EQ(c.steps, c_ref.steps);
      EXPECT_LT(c.dispatches_per_step, c_ref.dispatches_per_step);
      if (gate && !sinks) {
        EXPECT_LT(c.liquid_steps, c.steps) << "the liquid gate never closed";
      } else {
        EXPECT_EQ(c.liquid_steps, c.steps);
      }
    }
  }
}

}  // namespace wetdem::test
