// Formation at t = 0 (physics.md §5, issue 12 point 2): a state uploaded with touching pairs that carry film
// liquid forms their bridges at the first event check, as MercuryDPM's initialiseSolve does, instead of
// waiting for the pair to separate and touch again. Whole steps on every backend.
#include <gtest/gtest.h>

#include "reference/liquid_events.h"
#include "reference/scenario.h"
#include "support/backend.h"
#include "support/liquid_pair.h"

namespace wetdem::test {
namespace {

class LiquidInitial : public ::testing::TestWithParam<std::string> {};

// Chain A-B-C (ids 0, 1, 2) along x, at rest, no gravity. A and B overlap by 1 um at upload, B-C has a gap of
// 50 um. Films: A 3e8, B 1e8, C 2e8 units. Right after upload (before any step): bridge A-B = min(4e8, V_max)
// drawn 3:1 from the films (B has one forming pair, so it offers its whole film), no bridge B-C, C's film
// untouched, liquid exact. Then it holds over 20 steps without a second formation.
TEST_P(LiquidInitial, TouchingPairAtUploadBridgesAtOnce) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, kVmax);
  SystemState s = empty_state(3);
  put_sphere(s, 0, glm::dvec3(-2.0 * kR + 1e-6, 0.0, 0.0), kR, kRho);
  put_sphere(s, 1, glm::dvec3(0.0), kR, kRho);
  put_sphere(s, 2, glm::dvec3(2.0 * kR + 5e-5, 0.0, 0.0), kR, kRho);
  const int64_t fa = 300'000'000, fb = 100'000'000, fc = 200'000'000;
  s.p.film = {fa, fb, fc};
  auto b = make_backend(GetParam(), prm, 3);
  b->set_state(s);
  const SystemState st = b->state();
  const int64_t vb = fa + fb;
  ASSERT_EQ(bridge_of(st, 0, 1), vb) << "the pair touching at upload must bridge at once";
  EXPECT_EQ(flags_of(st, 0, 1), uint32_t(kFlagWasInContact));
  const int64_t from_a = ref::split_proportional(vb, fa, fb, fa, fb);
  EXPECT_EQ(st.p.film[0], fa - from_a);
  EXPECT_EQ(st.p.film[1], fb - (vb - from_a));
  EXPECT_EQ(bridge_of(st, 1, 2), 0);
  EXPECT_EQ(st.p.film[2], fc);
  EXPECT_EQ(liquid_sum(st), fa + fb + fc);
  EXPECT_EQ(b->read_events().formations, 1u);
  b->step(20);
  const SystemState s2 = b->state();
  EXPECT_EQ(bridge_of(s2, 0, 1), vb);
  EXPECT_EQ(bridge_of(s2, 1, 2), 0);
  EXPECT_EQ(liquid_sum(s2), fa + fb + fc);
  EXPECT_EQ(b->read_events().formations, 0u);
}

// A state taken from a run and uploaded again (a touching pair whose touch formed no bridge keeps its flag)
// forms nothing at upload: the check is the end-of-step rule, not a second chance.
TEST_P(LiquidInitial, FlaggedTouchingPairDoesNotFormAgain) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, kVmax);
  SystemState s = empty_state(2);
  put_sphere(s, 0, glm::dvec3(-kR + 5e-7, 0.0, 0.0), kR, kRho);
  put_sphere(s, 1, glm::dvec3(kR - 5e-7, 0.0, 0.0), kR, kRho);
  s.p.film = {300'000'000, 100'000'000};
  PairRecord r;
  r.id_i = 0;
  r.id_j = 1;
  r.flags = kFlagWasInContact;
  s.pairs.push_back(r);
  auto b = make_backend(GetParam(), prm, 2);
  b->set_state(s);
  const SystemState st = b->state();
  EXPECT_EQ(bridge_of(st, 0, 1), 0);
  EXPECT_EQ(st.p.film[0], 300'000'000);
  EXPECT_EQ(b->read_events().formations, 0u);
}

INSTANTIATE_TEST_SUITE_P(Backends, LiquidInitial, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
