// physics.md §6: Rayleigh time and the capillary time-step guard.
#include <gtest/gtest.h>

#include <cmath>

#include "wetdem/timestep.h"

namespace wetdem {

TEST(TimeStep, CapillaryLimitByHand) {
  // m* = 1e-6 kg, R_h = 1e-3 m, f0 = 1e-3 N, V = 1e-12 m^3: k_c = 1.05e-3 * sqrt(1e9) = 33.2 N/m.
  const double k_c = 1.05e-3 * std::sqrt(1e-3 / 1e-12);
  EXPECT_NEAR(capillary_dt_limit(1e-6, 1e-3, 1e-3, 1e-12), 0.1 * 3.14159265358979 * std::sqrt(1e-6 / k_c),
              1e-15);
}

TEST(TimeStep, WarnsOnlyWhenTheStepIsTooLargeForTheStiffestBridge) {
  SimParams prm;
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.072;
  prm.liq_pp.theta = 0.3;
  prm.liq_pp.v_min = 0;
  prm.liq_pp.v_max = 1000000000;  // 1e-12 m^3
  SystemState s;
  s.p.resize(2);
  set_sphere(s.p, 0, {0, 0, 0}, 1e-3, 2500);
  set_sphere(s.p, 1, {0, 2e-3, 0}, 1e-3, 2500);
  s.p.film = {500000000, 500000000};
  const double m = s.p.mass[0];
  const double f0 = 2 * 3.14159265358979 * 1e-3 * 0.072 * std::cos(0.3);
  // The smallest bridge these films can form is one film (5e8 units): a partner whose film an earlier bridge
  // spent adds nothing.
  EXPECT_EQ(smallest_formable_bridge(prm.liq_pp, s.p.film), 500000000);
  const double lim = capillary_dt_limit(0.5 * m, 1e-3, f0, 5e-13);
  prm.dt = 0.9 * lim;
  EXPECT_FALSE(capillary_timestep_warning(prm, s).has_value());
  prm.dt = 1.1 * lim;
  auto w = capillary_timestep_warning(prm, s);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("capillary"), std::string::npos);
  // An existing, smaller bridge is stiffer: it lowers the limit.
  prm.dt = 0.9 * lim;
  PairRecord r;
  r.id_i = 0;
  r.id_j = 1;
  r.bridge = 1000;  // 1e-18 m^3
  s.pairs.push_back(r);
  EXPECT_TRUE(capillary_timestep_warning(prm, s).has_value());
  prm.liq_pp.enabled = false;
  EXPECT_FALSE(capillary_timestep_warning(prm, s).has_value());
}

// Candidate effect `viscous`: c = dF_v/dv_n at S_min by hand and the explicit limit dt < 2 m*/(4 c).
// eta = 0.1 Pa s, R* = 0.5 mm, S_min = 1e-5 m, V = 1e-12 m^3: x = V/(pi R* S^2) = 6.3662, 1 - 1/sqrt(1 + x) =
// 0.631551, c = 6 pi 0.1 (0.5e-3)^2 / 1e-5 * 0.631551^2 = 1.8795e-2 kg/s.
TEST(TimeStep, ViscousLimitByHandAndWarning) {
  const double b = 1.0 - 1.0 / std::sqrt(1.0 + 1e-12 / (3.14159265358979 * 0.5e-3 * 1e-10));
  EXPECT_NEAR(b, 0.631551, 1e-6);
  EXPECT_NEAR(6.0 * 3.14159265358979 * 0.1 * 0.25e-6 / 1e-5 * b * b, 1.8795e-2, 1e-6);
  const double c = 6.0 * 3.14159265358979 * 0.1 * 0.25e-6 / 1e-5 * b * b;
  EXPECT_NEAR(viscous_damping_coefficient(0.1, 1e-5, 0.5e-3, 1e-12), c, 1e-12 * c);
  EXPECT_NEAR(viscous_dt_limit(5e-6, 0.5e-3, 0.1, 1e-5, 1e-12), 2.0 * 5e-6 / (4.0 * c), 1e-12);

  SimParams prm;
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.072;
  prm.liq_pp.v_max = 1000000000;  // 1e-12 m^3
  prm.liq_pp.viscosity = 0.1;
  prm.liq_pp.lubrication_cutoff = 1e-5;
  SystemState s;
  s.p.resize(2);
  set_sphere(s.p, 0, {0, 0, 0}, 1e-3, 2500);
  set_sphere(s.p, 1, {0, 3e-3, 0}, 1.5e-3, 2500);
  const double lim = viscous_dt_limit(0.5 * s.p.mass[0], 0.5e-3, 0.1, 1e-5, 1e-12);
  prm.dt = 0.9 * lim;
  EXPECT_FALSE(viscous_timestep_warning(prm, s).has_value());
  // At the limit (where a default dt is lowered to) is fine; just past it is not.
  prm.dt = lim;
  EXPECT_FALSE(viscous_timestep_warning(prm, s).has_value());
  prm.dt = lim * (1.0 + 1e-6);
  EXPECT_TRUE(viscous_timestep_warning(prm, s).has_value());
  prm.dt = 1.1 * lim;
  auto w = viscous_timestep_warning(prm, s);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("viscous"), std::string::npos);
  // Wall bridges (R* = r, m* = m; x = V/(pi r S^2) is halved) lower the limit to 0.764 of the pairs' one.
  prm.dt = 0.8 * lim;
  EXPECT_FALSE(viscous_timestep_warning(prm, s).has_value());
  prm.liq_pw[0] = prm.liq_pp;
  EXPECT_TRUE(viscous_timestep_warning(prm, s).has_value());
  prm.liq_pp.viscosity = prm.liq_pw[0].viscosity = 0.0;
  EXPECT_FALSE(viscous_timestep_warning(prm, s).has_value());
}

}  // namespace wetdem
