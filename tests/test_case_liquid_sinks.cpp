// Case keys of the liquid effects of diagnosis.md §3 (`absorption`, `evaporation`, `spread`): parsing,
// errors that name the key, the resolved echo, SimParams, and the spread films (exact total and wetted
// fraction, reproducible for a seed).
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>

#include "app/case/case.h"

namespace wetdem::app {
namespace {

std::string shipped(const std::string& name) {
  return std::string(WETDEM_SOURCE_DIR) + "/assets/" + name;
}

std::string sink_error_key(const std::vector<std::string>& sets) {
  try {
    parse_case_file(shipped("pp2_l5.toml"), sets);
  } catch (const CaseError& e) {
    return e.key();
  }
  return "(no error)";
}

TEST(CaseLiquidSinks, KeysParseEchoAndReachSimParams) {
  const Case d = parse_case_file(shipped("pp2_l5.toml"));
  EXPECT_EQ(d.absorption.capacity, 0.0);
  EXPECT_EQ(d.absorption.rate, 0.0);
  EXPECT_EQ(d.liquid.evaporation_time, 0.0);
  EXPECT_EQ(d.liquid.wetted_fraction, 1.0);
  const SimParams p0 = make_sim_params(d, {1e-3, 1.2e-3});
  EXPECT_FALSE(p0.sinks.absorbs());
  EXPECT_FALSE(p0.sinks.evaporates());

  const Case c = parse_case_file(shipped("pp2_l5.toml"),
                                 {"absorption.capacity=\"12 %\"", "absorption.rate=0.5",
                                  "liquid.evaporation_time=\"2 min\"", "liquid.wetted_fraction=0.4"});
  EXPECT_DOUBLE_EQ(c.absorption.capacity, 0.12);
  EXPECT_DOUBLE_EQ(c.absorption.rate, 0.5);
  EXPECT_DOUBLE_EQ(c.liquid.evaporation_time, 120.0);
  EXPECT_DOUBLE_EQ(c.liquid.wetted_fraction, 0.4);
  const SimParams p = make_sim_params(c, {1e-3, 1.2e-3});
  EXPECT_DOUBLE_EQ(p.sinks.pore_capacity, 0.12);
  EXPECT_DOUBLE_EQ(p.sinks.absorption_rate, 0.5);
  EXPECT_DOUBLE_EQ(p.sinks.evaporation_time, 120.0);
  // The resolved echo holds every key and parses back to the same case.
  const std::string toml = case_to_toml(c);
  EXPECT_NE(toml.find("evaporation_time_s"), std::string::npos) << toml;
  EXPECT_NE(toml.find("wetted_fraction"), std::string::npos);
  EXPECT_NE(toml.find("[absorption]"), std::string::npos);
  EXPECT_EQ(case_to_json(parse_case_string(toml)), case_to_json(c));

  const Case inst = parse_case_file(shipped("pp2_l5.toml"),
                                    {"absorption.capacity=0.1", "absorption.rate=\"instantaneous\""});
  EXPECT_TRUE(std::isinf(inst.absorption.rate));
  EXPECT_NE(case_to_toml(inst).find("instantaneous"), std::string::npos);
  EXPECT_EQ(case_to_json(parse_case_string(case_to_toml(inst))), case_to_json(inst));
}

// Time-step check: k dt > 0.1 resolves the decay with fewer than ~10 steps: noted at start (never unstable).
TEST(CaseLiquidSinks, FastAbsorptionIsNotedAtStart) {
  auto noted = [](const std::string& rate) {
    const Case c =
        parse_case_file(shipped("pp2_l5.toml"), {"absorption.capacity=0.1", "absorption.rate=" + rate});
    Derived d;
    make_sim_params(c, {1e-3, 1.2e-3}, &d);
    for (const std::string& n : d.notes)
      if (n.find("absorption.rate x dt") != std::string::npos) return true;
    return false;
  };
  EXPECT_FALSE(noted("1"));
  EXPECT_TRUE(noted("1e6"));
  EXPECT_FALSE(noted("\"instantaneous\""));
}

TEST(CaseLiquidSinks, BadValuesNameTheKey) {
  EXPECT_EQ(sink_error_key({"absorption.capacity=0.5"}), "absorption.capacity");
  EXPECT_EQ(sink_error_key({"absorption.rate=-1"}), "absorption.rate");
  EXPECT_EQ(sink_error_key({"absorption.rate=0.001"}), "absorption.rate");
  EXPECT_EQ(sink_error_key({"absorption.rate=\"fast\""}), "absorption.rate");
  EXPECT_EQ(sink_error_key({"absorption.pores=1"}), "absorption.pores");  // unknown key
  EXPECT_EQ(sink_error_key({"liquid.evaporation_time=\"0.5 s\""}), "liquid.evaporation_time");
  EXPECT_EQ(sink_error_key({"liquid.evaporation_time=\"2 h\""}), "liquid.evaporation_time");
  EXPECT_EQ(sink_error_key({"liquid.wetted_fraction=0.05"}), "liquid.wetted_fraction");
  EXPECT_EQ(sink_error_key({"liquid.wetted_fraction=1.2"}), "liquid.wetted_fraction");
}

// spread: round(f N) particles hold all the liquid, in proportion to their own volume; the total equals the
// uniform case exactly; the same seed gives the same particles, another seed others.
TEST(CaseLiquidSinks, SpreadFilmsExactAndReproducible) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.4e-3, 1.2e-3);
  std::vector<double> radii(2001);
  for (double& r : radii) r = u(rng);
  const Case uni = parse_case_file(shipped("pp2_l5.toml"));
  const SimParams p = make_sim_params(uni, radii);
  const std::vector<int64_t> f1 = initial_films(uni, radii, p.liquid_unit_m3);
  const int64_t total = std::accumulate(f1.begin(), f1.end(), int64_t(0));
  for (double f : {0.1, 0.37, 0.9}) {
    const Case c = parse_case_file(shipped("pp2_l5.toml"), {"liquid.wetted_fraction=" + std::to_string(f)});
    const std::vector<int64_t> fs = initial_films(c, radii, p.liquid_unit_m3);
    EXPECT_EQ(std::accumulate(fs.begin(), fs.end(), int64_t(0)), total) << "f = " << f;
    const size_t wet = size_t(std::count_if(fs.begin(), fs.end(), [](int64_t v) { return v > 0; }));
    EXPECT_EQ(wet, size_t(std::llround(f * double(radii.size())))) << "f = " << f;
    // Films in proportion to own volume: V_f,k / r_k^3 is the same for every wetted particle (to 1 unit).
    double lo = 1e300, hi = 0;
    for (size_t k = 0; k < fs.size(); ++k) {
      if (fs[k] == 0) continue;
      const double r3 = radii[k] * radii[k] * radii[k];
      lo = std::min(lo, (double(fs[k]) - 1.0) / r3);
      hi = std::max(hi, (double(fs[k]) + 1.0) / r3);
    }
    EXPECT_LT((hi - lo) / hi, 1e-6) << "f = " << f;
    EXPECT_EQ(initial_films(c, radii, p.liquid_unit_m3), fs) << "same seed, same films";
    Case other = parse_case_file(shipped("pp2_l5.toml"),
                                 {"liquid.wetted_fraction=" + std::to_string(f), "run.seed=99"});
    EXPECT_NE(initial_films(other, radii, p.liquid_unit_m3), fs) << "another seed, other particles";
  }
  // f = 1 is the uniform films themselves.
  const Case one = parse_case_file(shipped("pp2_l5.toml"), {"liquid.wetted_fraction=1"});
  EXPECT_EQ(initial_films(one, radii, p.liquid_unit_m3), f1);
}

}  // namespace
}  // namespace wetdem::app

#endif
