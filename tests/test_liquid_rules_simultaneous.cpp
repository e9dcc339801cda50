// §5 "Simultaneous events": the two-phase rule of wetdem against the MercuryDPM-style sequential rule, both
// in the CPU reference. They agree whenever no two events share a particle; the two cases where they differ
// are documented with the expected values of each rule. Also the integer split of ARCHITECTURE.md "Liquid".
#include <gtest/gtest.h>

#include <random>

#include "reference/liquid_events.h"
#include "reference/reference.h"
#include "reference/scenario.h"
#include "support/liquid_pair.h"

namespace wetdem::test {
namespace {

SimParams pair_params(double d_c = 1.0, int64_t v_min = 0) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(v_min, kVmax, d_c);
  return prm;
}

PairRecord bridge_record(uint32_t i, uint32_t j, int64_t v) {
  PairRecord r;
  r.id_i = std::min(i, j);
  r.id_j = std::max(i, j);
  r.bridge = v;
  r.flags = v > 0 ? uint32_t(kFlagWasInContact) : 0u;
  return r;
}

struct StepOutcome {
  SystemState st;
  EventCounts ev;
};

StepOutcome one_step_by_rule(const SimParams& prm, const SystemState& s, bool sequential) {
  ref::ReferenceSystem sys(prm);
  sys.set_sequential_events(sequential);
  sys.set_state(s);
  sys.step();
  return {sys.state(), sys.read_events()};
}

TEST(SplitProportional, IntegerFormula) {
  // Equal shares: exact halves.
  EXPECT_EQ(ref::split_proportional(300'000'000, 300'000'000, 300'000'000, 300'000'000, 300'000'000),
            150'000'000);
  // 3:1 of 2e8: q = 49152/65536 = 0.75 exactly.
  EXPECT_EQ(ref::split_proportional(200'000'000, 300'000'000, 100'000'000, 300'000'000, 100'000'000),
            150'000'000);
  // By hand for 1:2 of 1000: q = floor(65536/3) = 21845, part = (1000 * 21845) >> 16 = 333.
  EXPECT_EQ(ref::split_proportional(1000, 1, 2, 1000, 1000), 333);
  // One side empty: everything from the other.
  EXPECT_EQ(ref::split_proportional(12345, 7, 0, 12345, 0), 12345);
  EXPECT_EQ(ref::split_proportional(12345, 0, 7, 0, 12345), 0);
  // Clamps: the floor would leave b giving more than it can (b_cap), and a never gives more than a_cap.
  EXPECT_EQ(ref::split_proportional(10, 1, 2, 10, 6), 4);  // floor 3, but b can only give 6
  EXPECT_EQ(ref::split_proportional(10, 2, 1, 5, 10), 5);  // 6 would pass a_cap = 5
  // Large volumes (films near 2^40 units) do not overflow.
  const int64_t big = int64_t(1) << 41;
  const int64_t part = ref::split_proportional(big, big, big / 3, big, big);
  EXPECT_NEAR(double(part), 0.75 * double(big), 1e-4 * double(big));
  EXPECT_EQ(ref::split_proportional(0, 5, 5, 5, 5), 0);
}

// Random configurations of isolated events, one per cluster, clusters 2 cm apart (no interaction):
//   0 particle-particle rupture A-B, with surviving bridges B-C and A-D (random volumes, some near the cap);
//   1 formation A-B at first touch (random films, random V_min), A also bridged to C (touching, no event);
//   2 wall rupture of P (plate bridge beyond S_c), P bridged to Q;
//   3 wall formation of P on the plate, P bridged to Q.
// Both rules must give the same state, to the unit, and the same event counts.
TEST(SimultaneousEvents, TwoPhaseEqualsSequentialOnIsolatedEvents) {
  std::mt19937_64 rng(12345);
  auto uni = [&](int64_t lo, int64_t hi) { return std::uniform_int_distribution<int64_t>(lo, hi)(rng); };
  uint64_t total_events = 0;
  for (int config = 0; config < 25; ++config) {
    const double d_c = std::array<double, 3>{1.0, 0.8, 0.37}[config % 3];
    SimParams prm = pair_params(d_c, uni(0, 300'000'000));
    prm.drum.radius = 1.0;
    prm.drum.length = 0.2;
    prm.drum.plate_lo.present = true;
    prm.drum.plate_lo.rotates = false;
    prm.liq_pw[kWallPlateLo] =
        water(uni(0, 300'000'000), kVmax, std::array<double, 3>{0.9, 1.0, 0.5}[config % 3]);
    const double z_plate = -0.5 * prm.drum.length;
    // Rupturing bridges sit between their S_c and the interaction range, as they would in a run.
    const double range_pp = prm.bridge_range_pp(), range_w = prm.bridge_range_pw(kWallPlateLo);
    const int clusters = 8;
    SystemState s = empty_state(4 * clusters);
    for (int c = 0; c < clusters; ++c) {
      const uint32_t a = 4 * c, bb = a + 1, cc = a + 2, dd = a + 3;
      const int type = int(uni(0, 3));
      const double xc = 0.02 * c - 0.08;
      // Ids are shuffled within the cluster so that lower/higher id roles vary.
      std::array<uint32_t, 4> id{a, bb, cc, dd};
      std::shuffle(id.begin(), id.end(), rng);
      const glm::dvec3 base(xc, 0.0, type >= 2 ? z_plate + kR : 0.0);
      for (uint32_t k = 0; k < 4; ++k) s.p.film[id[k]] = uni(0, 600'000'000);
      if (type == 0) {
        const int64_t vab = uni(2, kVmax);
        const double sc = rupture_distance(prm.liq_pp.theta, double(vab) * prm.liquid_unit_m3);
        put_sphere(s, id[0], base, kR, kRho);
        put_sphere(s, id[1], beside(base, glm::dvec3(1, 0, 0), 0.5 * (sc + range_pp)), kR, kRho);
        put_sphere(s, id[2], beside(s.p.x[id[1]], glm::dvec3(1, 1, 0), 1e-6), kR, kRho);
        put_sphere(s, id[3], beside(base, glm::dvec3(-1, 1, 0), 0.0), kR, kRho);
        s.pairs.push_back(bridge_record(id[0], id[1], vab));
        s.pairs.push_back(bridge_record(id[1], id[2], uni(1, kVmax)));
        s.pairs.push_back(bridge_record(id[0], id[3], uni(kVmax / 2, kVmax)));
      } else if (type == 1) {
        put_sphere(s, id[0], base, kR, kRho);
        put_sphere(s, id[1], beside(base, glm::dvec3(1, 0, 0), -1e-7), kR, kRho);  // overlap: a sure touch
        put_sphere(s, id[2], beside(base, glm::dvec3(-1, 0.2, 0), 0.0), kR, kRho);
        put_sphere(s, id[3], base + glm::dvec3(0.0, 0.005, 0.0), kR, kRho);  // alone
        s.pairs.push_back(bridge_record(id[0], id[2], uni(1, kVmax)));
      } else {
        const bool rupture = type == 2;
        const int64_t vw = uni(2, kVmax);
        const double sc = rupture_distance(prm.liq_pw[kWallPlateLo].theta, double(vw) * prm.liquid_unit_m3);
        const glm::dvec3 xp = base + glm::dvec3(0.0, 0.0, rupture ? 0.5 * (sc + range_w) : -1e-7);
        put_sphere(s, id[0], xp, kR, kRho);
        put_sphere(s, id[1], beside(xp, glm::dvec3(1, 0, 1), 1e-6), kR, kRho);  // above the plate
        put_sphere(s, id[2], base + glm::dvec3(0.0, 0.005, 0.01), kR, kRho);    // alone
        put_sphere(s, id[3], base + glm::dvec3(0.0, -0.005, 0.01), kR, kRho);   // alone
        s.pairs.push_back(bridge_record(id[0], id[1], uni(1, kVmax)));
        if (rupture) {
          s.p.wall[id[0] * kNumWalls + kWallPlateLo].bridge = vw;
          s.p.wall[id[0] * kNumWalls + kWallPlateLo].flags = kFlagWasInContact;
        }
      }
    }
    const StepOutcome two = one_step_by_rule(prm, s, false);
    const StepOutcome seq = one_step_by_rule(prm, s, true);
    ASSERT_EQ(two.st.total_liquid(), s.total_liquid());
    ASSERT_EQ(seq.st.total_liquid(), s.total_liquid());
    EXPECT_EQ(two.ev.formations, seq.ev.formations) << "config " << config;
    EXPECT_EQ(two.ev.ruptures, seq.ev.ruptures) << "config " << config;
    total_events += two.ev.formations + two.ev.ruptures;
    EXPECT_EQ(two.st.p.film, seq.st.p.film) << "config " << config;
    ASSERT_EQ(two.st.pairs.size(), seq.st.pairs.size()) << "config " << config;
    for (size_t k = 0; k < two.st.pairs.size(); ++k) {
      EXPECT_EQ(two.st.pairs[k].id_i, seq.st.pairs[k].id_i);
      EXPECT_EQ(two.st.pairs[k].id_j, seq.st.pairs[k].id_j);
      EXPECT_EQ(two.st.pairs[k].bridge, seq.st.pairs[k].bridge) << "config " << config << " pair " << k;
      EXPECT_EQ(two.st.pairs[k].flags, seq.st.pairs[k].flags);
    }
    for (size_t k = 0; k < two.st.p.wall.size(); ++k) {
      EXPECT_EQ(two.st.p.wall[k].bridge, seq.st.p.wall[k].bridge) << "config " << config << " wall " << k;
      EXPECT_EQ(two.st.p.wall[k].flags, seq.st.p.wall[k].flags);
    }
  }
  EXPECT_GT(total_events, 150u);  // 200 clusters: most of them do have their event
  std::cout << "isolated-event configurations: " << total_events << " events compared\n";
}

// Difference 1: A (id 0) touches B (id 1) and C (id 2) for the first time in the same step; films
// A = 600000001, B = 1e8, C = 2e8, no cap reached.
//  two-phase: A offers floor(V_f,A / 2) = 3e8 to each; AB = 3e8 + 1e8, AC = 3e8 + 2e8; A keeps the odd unit.
//  sequential: AB forms first from the full films (7e8 + 1), then AC finds A dry and takes only C's 2e8.
TEST(SimultaneousEvents, ParticleTouchingTwoNewPartners) {
  const SimParams prm = pair_params();
  SystemState s = empty_state(3);
  const glm::dvec3 xa(0.0);
  put_sphere(s, 0, xa, kR, kRho);
  put_sphere(s, 1, beside(xa, glm::dvec3(-1, 0, 0), 0.0), kR, kRho);
  put_sphere(s, 2, beside(xa, glm::dvec3(1, 0, 0), 0.0), kR, kRho);
  s.p.film = {600'000'001, 100'000'000, 200'000'000};
  const StepOutcome two = one_step_by_rule(prm, s, false);
  EXPECT_EQ(bridge_of(two.st, 0, 1), 400'000'000);
  EXPECT_EQ(bridge_of(two.st, 0, 2), 500'000'000);
  EXPECT_EQ(two.st.p.film, (std::vector<int64_t>{1, 0, 0}));
  EXPECT_EQ(two.ev.formations, 2u);
  const StepOutcome seq = one_step_by_rule(prm, s, true);
  EXPECT_EQ(bridge_of(seq.st, 0, 1), 700'000'001);
  EXPECT_EQ(bridge_of(seq.st, 0, 2), 200'000'000);
  EXPECT_EQ(seq.st.p.film, (std::vector<int64_t>{0, 0, 0}));
  EXPECT_EQ(seq.ev.formations, 2u);
}

// Difference 2: chain A-B-C-D (ids 0-3); A-B and C-D (6e8 each) rupture in the same step, B-C (7e8) survives,
// V_max = 1e9, d_c = 1. B receives 3e8 (higher id of AB), C receives 3e8 (lower id of CD).
//  two-phase: B-C takes both shares, 1.3e9, and returns the 3e8 overflow in proportion to the shares (1:1):
//             films A = 3e8, B = 1.5e8, C = 1.5e8, D = 3e8.
//  sequential: AB first fills B-C exactly to V_max; then C's whole share overflows into C's film:
//             films A = 3e8, B = 0, C = 3e8, D = 3e8.
TEST(SimultaneousEvents, BridgeFedFromBothEnds) {
  const SimParams prm = pair_params();
  SystemState s = empty_state(4);
  const glm::dvec3 xb(0.0);
  put_sphere(s, 1, xb, kR, kRho);
  put_sphere(s, 2, beside(xb, glm::dvec3(1, 0, 0), 1e-6), kR, kRho);
  put_sphere(s, 0, beside(xb, glm::dvec3(-1, 0, 0), 1.1e-4), kR, kRho);  // S_c(6e8) = 99 um < 110 um < 117 um
  put_sphere(s, 3, beside(s.p.x[2], glm::dvec3(1, 0, 0), 1.1e-4), kR, kRho);
  s.pairs = {bridge_record(0, 1, 600'000'000), bridge_record(1, 2, 700'000'000),
             bridge_record(2, 3, 600'000'000)};
  const StepOutcome two = one_step_by_rule(prm, s, false);
  EXPECT_EQ(two.ev.ruptures, 2u);
  EXPECT_EQ(bridge_of(two.st, 1, 2), kVmax);
  EXPECT_EQ(two.st.p.film, (std::vector<int64_t>{300'000'000, 150'000'000, 150'000'000, 300'000'000}));
  const StepOutcome seq = one_step_by_rule(prm, s, true);
  EXPECT_EQ(seq.ev.ruptures, 2u);
  EXPECT_EQ(bridge_of(seq.st, 1, 2), kVmax);
  EXPECT_EQ(seq.st.p.film, (std::vector<int64_t>{300'000'000, 0, 300'000'000, 300'000'000}));
  EXPECT_EQ(two.st.total_liquid(), s.total_liquid());
  EXPECT_EQ(seq.st.total_liquid(), s.total_liquid());
}

}  // namespace
}  // namespace wetdem::test
