// From a case to SimParams (physics.md §1, §4, §6), and the shipped case files.
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/case/case.h"
#include "app/drum/psd.h"
#include "support/numbers.h"

namespace wetdem::app {
namespace {

namespace fs = std::filesystem;
constexpr double kTwo40 = 1099511627776.0;

std::string asset(const std::string& name) {
  return std::string(WETDEM_SOURCE_DIR) + "/assets/" + name;
}

TEST(CaseParams, RayleighTimeOfPhysicsSection7) {
  // §7.6: r = 1 mm, rho = 2500, E = 1e7 Pa, nu = 0.3: t_R = 8.654e-5 s. Stiffness not reduced here.
  std::ifstream in(asset("pp2_l5.toml"));
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  text.replace(text.find("G = \"400 MPa\""), 13, "nu = 0.3");
  const Case c = parse_case_string(
      text, {"material.E=\"10 MPa\"", "material.density=\"2500 kg/m3\"", "material.stiffness_reduction=1"});
  Derived d;
  make_sim_params(c, {1e-3, 2e-3}, &d);
  EXPECT_NEAR(d.t_rayleigh, 8.654e-5, 5e-9);
  EXPECT_DOUBLE_EQ(d.dt, 0.2 * d.t_rayleigh);
  EXPECT_DOUBLE_EQ(d.skin, 3e-4);  // 0.3 r_min
}

TEST(CaseParams, ModuliScalingAndLiquidUnits) {
  const Case c = parse_case_file(asset("pp2_l5.toml"));
  const std::vector<double> radii = {1.3e-3, 2.0e-3, 3.3e-3};
  Derived d;
  const SimParams p = make_sim_params(c, radii, &d);
  const double nu = 1325.0 / 800.0 - 1.0;
  EXPECT_NEAR(d.nu, nu, 1e-15);
  EXPECT_NEAR(p.pp.E_star, 1.325e9 / (2.0 * (1.0 - nu * nu)) / 1000.0, 1e-6);  // §1, reduced by 10^3
  EXPECT_NEAR(p.pp.G_star, 4.0e8 / (2.0 * (2.0 - nu)) / 1000.0, 1e-6);
  EXPECT_DOUBLE_EQ(p.pw[kWallCylinder].E_star, p.pp.E_star);
  EXPECT_DOUBLE_EQ(p.pp.mu_s, 0.8);
  EXPECT_DOUBLE_EQ(p.pp.mu_r, 0.3);
  EXPECT_DOUBLE_EQ(p.pp.restitution, 0.5);
  EXPECT_NEAR(p.liq_pp.gamma, 5.0 * 0.0217, 1e-15);  // §4: gamma scaled by l
  EXPECT_NEAR(p.liq_pp.theta, kPi / 6.0, 1e-15);
  double vbar = 0;
  for (double r : radii) vbar += 4.0 / 3.0 * kPi * r * r * r;
  vbar /= 3.0;
  EXPECT_NEAR(p.liquid_unit_m3, vbar / kTwo40, 1e-30);
  EXPECT_EQ(p.liq_pp.v_min, std::llround(0.10 * kTwo40));
  EXPECT_EQ(p.liq_pp.v_max, std::llround(0.01 * kTwo40));
  EXPECT_TRUE(p.liq_pp.enabled);
  for (uint32_t w = 0; w < kNumWalls; ++w) EXPECT_FALSE(p.liq_pw[w].enabled);
  EXPECT_DOUBLE_EQ(p.drum.radius, 0.07);
  EXPECT_DOUBLE_EQ(p.drum.length, 0.18);
  EXPECT_NEAR(p.drum.omega, 5.0 * 2.0 * kPi / 60.0, 1e-15);
  EXPECT_FALSE(p.drum.periodic_z);
  EXPECT_TRUE(p.drum.plate_lo.present && p.drum.plate_lo.rotates);
  // dt = 0.2 t_R(r_min) with the reduced G and nu = 0.656 (§6).
  const double tr = kPi * 1.3e-3 * std::sqrt(900.0 / 4.0e5) / (0.1631 * nu + 0.8766);
  EXPECT_NEAR(p.dt, 0.2 * tr, 1e-15);

  // Films: phi_L x own volume, in units; their sum is phi_L N 2^40 up to rounding.
  const std::vector<int64_t> f = initial_films(c, radii, p.liquid_unit_m3);
  int64_t sum = 0;
  for (int64_t v : f) sum += v;
  EXPECT_NEAR(double(sum), 0.10 * 3.0 * kTwo40, 2.0);
  EXPECT_GT(f[2], f[0]);
  const Case m = parse_case_file(asset("pp2_l5.toml"), {"liquid.films=mean_volume"});
  const std::vector<int64_t> fm = initial_films(m, radii, p.liquid_unit_m3);
  EXPECT_EQ(fm[0], std::llround(0.10 * kTwo40));
  EXPECT_EQ(fm[0], fm[2]);
}

TEST(CaseParams, DryCaseAndPeriodicSlice) {
  const Case c = parse_case_file(asset("demo.toml"), {"liquid.content=0"});
  const SimParams p = make_sim_params(c, {1.5e-3, 2e-3});
  EXPECT_FALSE(p.liq_pp.enabled);
  EXPECT_EQ(p.bridge_range_pp(), 0.0);
  EXPECT_TRUE(p.drum.periodic_z);
  EXPECT_DOUBLE_EQ(p.drum.length, 0.018);
  EXPECT_FALSE(p.drum.plate_lo.present);
  EXPECT_EQ(initial_films(c, {1.5e-3, 2e-3}, p.liquid_unit_m3), std::vector<int64_t>(2, 0));
}

TEST(Assets, AllShippedCasesParseAndValidate) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(std::string(WETDEM_SOURCE_DIR) + "/assets")) {
    if (e.path().extension() != ".toml") continue;
    SCOPED_TRACE(e.path().string());
    const Case c = parse_case_file(e.path().string());
    EXPECT_FALSE(c.name.empty());
    EXPECT_EQ(c.name, e.path().stem().string());  // name = file name: run folders are named after it
    EXPECT_DOUBLE_EQ(c.material.density, 900.0);  // logged assumption (drum.md)
    // The echo of every asset parses back to the same case.
    EXPECT_EQ(case_to_json(c), case_to_json(parse_case_string(case_to_toml(c))));
    ++n;
  }
  EXPECT_GE(n, 5u);
}

// Particle count of a case at its fill, from the PSD's mean volume (as the fill computes it).
double expected_particles(const Case& c) {
  const Psd psd(c.psd);
  const double v = kPi * 0.25 * c.drum.diameter * c.drum.diameter * c.drum.sim_length();
  return c.drum.fill * v * c.drum.bed_solid_fraction / psd.mean_volume();
}

TEST(Assets, FillGivesThePaperParticleCounts) {
  // drum.md: 101,200 particles for PP2 at l = 3; rough sizes PP2 l = 5 ~ 22k, PP1 l = 5 ~ 60-75k.
  EXPECT_NEAR(expected_particles(parse_case_file(asset("pp2_l3.toml"))), 101200.0, 100.0);
  EXPECT_NEAR(expected_particles(parse_case_file(asset("pp2_l5.toml"))), 22000.0, 1000.0);
  const double pp1 = expected_particles(parse_case_file(asset("pp1_l5.toml")));
  EXPECT_GT(pp1, 60000.0);
  EXPECT_LT(pp1, 75000.0);
  // The demo stays small (a few thousand particles: minutes on lavapipe).
  const double demo = expected_particles(parse_case_file(asset("demo.toml")));
  EXPECT_GT(demo, 1000.0);
  EXPECT_LT(demo, 5000.0);
}

TEST(Assets, PaperCasesUseTheCalibratedLiquidSets) {
  const Case pp2 = parse_case_file(asset("pp2_l5.toml"));
  EXPECT_DOUBLE_EQ(pp2.liquid.v_min, 0.10);  // drum.md finding 4
  EXPECT_DOUBLE_EQ(pp2.liquid.v_max, 0.01);
  EXPECT_DOUBLE_EQ(parse_case_file(asset("pp2_l3.toml")).mu_r, 0.4);  // Table 3 at l = 3
  const Case pp1 = parse_case_file(asset("pp1_l5.toml"));
  EXPECT_DOUBLE_EQ(pp1.liquid.v_min, 0.0);
  EXPECT_DOUBLE_EQ(pp1.liquid.v_max, 0.01);
  EXPECT_DOUBLE_EQ(pp1.psd.table.front().diameter, 304.0e-6);
  const Case demo = parse_case_file(asset("demo.toml"));
  EXPECT_TRUE(demo.drum.periodic_slice);
  EXPECT_EQ(demo.liquid.v_min, 0.0);  // bridges form at once
  EXPECT_TRUE(demo.liquid.on());
}

}  // namespace
}  // namespace wetdem::app

#endif  // WETDEM_HAVE_APP
