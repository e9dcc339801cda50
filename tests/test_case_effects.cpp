// Case keys of the candidate force effects (docs/model.md "Candidate effects"): units, validation naming the
// key, defaults, the resolved echo, and what reaches SimParams (w scaled by l, S_min default, theta_r).
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "app/case/case.h"
#include "app/case/units.h"
#include "support/numbers.h"
#include "support/small_case.h"

namespace wetdem::app {
namespace {

Case parse(const std::vector<std::string>& sets) {
  return parse_case_string(test::kSmall, sets, "small.toml");
}

std::string effect_error_key(const std::vector<std::string>& sets) {
  try {
    parse(sets);
  } catch (const CaseError& e) {
    return e.key();
  }
  return "(accepted)";
}

TEST(CaseEffects, UnitsOfViscosityAndSurfaceEnergy) {
  EXPECT_DOUBLE_EQ(parse_quantity("2 mPa s", Dim::Viscosity), 2e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("0.5 Pa*s", Dim::Viscosity), 0.5);
  EXPECT_DOUBLE_EQ(parse_quantity("2 cP", Dim::Viscosity), 2e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("50 mJ/m2", Dim::SurfaceEnergy), 0.05);
  EXPECT_DOUBLE_EQ(parse_quantity("0.01 J/m^2", Dim::SurfaceEnergy), 0.01);
  EXPECT_THROW(parse_quantity("2 Pa", Dim::Viscosity), std::invalid_argument);
  EXPECT_THROW(parse_quantity("0.05", Dim::SurfaceEnergy), std::invalid_argument);
}

TEST(CaseEffects, DefaultsAreOffAndEchoed) {
  const Case c = parse({});
  EXPECT_EQ(c.liquid.viscosity, 0.0);
  EXPECT_FALSE(c.liquid.lubrication_cutoff.has_value());
  EXPECT_FALSE(c.liquid.theta_receding.has_value());
  EXPECT_EQ(c.cohesion.surface_energy, 0.0);
  const std::string echo = case_to_toml(c);
  EXPECT_NE(echo.find("viscosity_Pa_s = 0.0"), std::string::npos) << echo;
  EXPECT_NE(echo.find("theta_receding_rad = " + fmt::format("{}", c.liquid.theta)), std::string::npos)
      << echo;
  EXPECT_NE(echo.find("[cohesion]\nsurface_energy_J_per_m2 = 0.0"), std::string::npos) << echo;
  EXPECT_EQ(case_to_json(parse_case_string(echo, {}, "echo")), case_to_json(c));
  // SimParams: all off; theta_r = theta.
  const SimParams p = make_sim_params(c, std::vector<double>(10, 1e-3));
  EXPECT_EQ(p.liq_pp.viscosity, 0.0);
  EXPECT_EQ(p.liq_pp.theta_r(), p.liq_pp.theta);
  EXPECT_EQ(p.pp.surface_energy, 0.0);
}

TEST(CaseEffects, KeysResolveScaleAndEchoBack) {
  const Case c = parse({"liquid.viscosity=\"2 mPa s\"", "liquid.lubrication_cutoff=\"10 um\"",
                        "liquid.theta_receding=\"10 deg\"", "cohesion.surface_energy=\"20 mJ/m2\""});
  EXPECT_DOUBLE_EQ(c.liquid.viscosity, 2e-3);
  EXPECT_DOUBLE_EQ(*c.liquid.lubrication_cutoff, 10e-6);
  EXPECT_DOUBLE_EQ(*c.liquid.theta_receding, 10.0 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(c.cohesion.surface_energy, 0.02);
  const std::string echo = case_to_toml(c);
  for (const char* k :
       {"viscosity_Pa_s = 0.002", "lubrication_cutoff_m = 1e-05", "surface_energy_J_per_m2 = 0.02"})
    EXPECT_NE(echo.find(k), std::string::npos) << k << "\n" << echo;
  EXPECT_EQ(case_to_json(parse_case_string(echo, {}, "echo")), case_to_json(c));
  Derived d;
  const SimParams p = make_sim_params(c, std::vector<double>(10, 1e-3), &d);
  EXPECT_DOUBLE_EQ(p.pp.surface_energy, 5 * 0.02);  // scaling = 5: w_scaled = l w, like gamma
  for (const auto& w : p.pw) EXPECT_DOUBLE_EQ(w.surface_energy, 5 * 0.02);
  EXPECT_DOUBLE_EQ(p.liq_pp.viscosity, 2e-3);
  EXPECT_DOUBLE_EQ(p.liq_pp.lubrication_cutoff, 10e-6);
  EXPECT_DOUBLE_EQ(p.liq_pp.theta_r(), 10.0 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(derived_to_json(d)["surface_energy_scaled_J_per_m2"].get<double>(), 0.1);
  EXPECT_GT(d.dt_viscous_limit, d.dt);  // 2 mPa s is far from the explicit limit
  // Suffixed keys are the same quantities.
  const Case s = parse({"liquid.viscosity_mPa_s=2", "cohesion.surface_energy_J_per_m2=0.02"});
  EXPECT_DOUBLE_EQ(s.liquid.viscosity, 2e-3);
  EXPECT_DOUBLE_EQ(s.cohesion.surface_energy, 0.02);
}

TEST(CaseEffects, CutoffDefaultsToOnePercentOfTheMeanRadiusAndDtIsChecked) {
  const Case c = parse({"liquid.viscosity=\"1 Pa s\""});
  Derived d;
  make_sim_params(c, std::vector<double>(10, 2e-3), &d);
  EXPECT_NEAR(d.lubrication_cutoff, 2e-5, 1e-15);
  EXPECT_GT(d.dt_viscous_limit, 0.0);
  // 100 Pa s with a 0.1 um cut-off: the damping is far too stiff for the Rayleigh dt. The default dt is
  // lowered to the damper's limit (as the Rayleigh fraction limits it), and the log says why.
  const Case hard = parse({"liquid.viscosity=\"100 Pa s\"", "liquid.lubrication_cutoff=\"0.1 um\""});
  Derived soft;
  make_sim_params(parse({}), std::vector<double>(10, 2e-3), &soft);
  const SimParams p = make_sim_params(hard, std::vector<double>(10, 2e-3), &d);
  EXPECT_LT(d.dt_viscous_limit, soft.dt);
  EXPECT_DOUBLE_EQ(d.dt, d.dt_viscous_limit);
  EXPECT_DOUBLE_EQ(p.dt, d.dt);
  EXPECT_NE(d.dt_reason.find("viscous limit"), std::string::npos) << d.dt_reason;
  bool noted = false;
  for (const std::string& n : d.notes) noted = noted || n.find("dt lowered") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_EQ(case_viscous_dt_limit(hard, 2e-3, d.mean_solid_volume), d.dt_viscous_limit);
  // An explicit run.dt is the user's: kept, with a note that it is unstable.
  const Case given =
      parse({"liquid.viscosity=\"100 Pa s\"", "liquid.lubrication_cutoff=\"0.1 um\"", "run.dt=\"1 us\""});
  make_sim_params(given, std::vector<double>(10, 2e-3), &d);
  EXPECT_DOUBLE_EQ(d.dt, 1e-6);
  EXPECT_LT(d.dt_viscous_limit, d.dt);
  EXPECT_EQ(d.dt_reason, "run.dt");
  noted = false;
  for (const std::string& n : d.notes)
    noted = noted || n.find("exceeds the viscous limit") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(CaseEffects, BadValuesNameTheirKey) {
  EXPECT_EQ(effect_error_key({"liquid.viscosity=\"-1 Pa s\""}), "liquid.viscosity");
  EXPECT_EQ(effect_error_key({"liquid.viscosity=\"2 Pa\""}), "liquid.viscosity");
  EXPECT_EQ(effect_error_key({"liquid.viscosity=\"500 Pa s\""}), "liquid.viscosity");
  EXPECT_EQ(effect_error_key({"liquid.lubrication_cutoff=0"}), "liquid.lubrication_cutoff");
  EXPECT_EQ(effect_error_key({"liquid.lubrication_cutoff=\"5 mm\""}), "liquid.lubrication_cutoff");
  EXPECT_EQ(effect_error_key({"liquid.theta_receding=\"95 deg\""}), "liquid.theta_receding");
  EXPECT_EQ(effect_error_key({"cohesion.surface_energy=\"-1 mJ/m2\""}), "cohesion.surface_energy");
  EXPECT_EQ(effect_error_key({"cohesion.surface_energy=\"2 J/m2\""}), "cohesion.surface_energy");
  EXPECT_EQ(effect_error_key({"cohesion.adhesion=1"}), "cohesion.adhesion");
}

}  // namespace
}  // namespace wetdem::app

#endif
