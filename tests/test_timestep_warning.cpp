// The capillary time-step warning (physics.md §6, issue 12 point 3) on the demo case: at the start it judges
// the smallest bridge the formation rule can make from the case's films, V_min and V_max (not one liquid
// unit); during the run it judges the bridges present, so films spent by formations do not raise it.
#include <gtest/gtest.h>

#include <string>

#include "app/case/case.h"
#include "app/drum/psd.h"
#include "wetdem/timestep.h"

namespace wetdem {
namespace {

std::string demo_path() {
  return std::string(WETDEM_SOURCE_DIR) + "/assets/demo.toml";
}

// Three particles of the demo's PSD (the smallest, a middle one, the largest) with the case's films.
struct DemoLike {
  SimParams prm;
  app::Derived d;
  SystemState s;
};

DemoLike demo_like(const std::vector<std::string>& sets = {}) {
  const app::Case c = app::parse_case_file(demo_path(), sets);
  const Psd psd(c.psd);
  const std::vector<double> radii = {0.5 * psd.d_min(), 0.25 * (psd.d_min() + psd.d_max()),
                                     0.5 * psd.d_max()};
  DemoLike o;
  o.prm = app::make_sim_params(c, radii, &o.d);
  o.s.p.resize(3);
  for (size_t k = 0; k < 3; ++k)
    set_sphere(o.s.p, k, glm::dvec3(0.02 * double(k), 0.0, 0.0), radii[k], c.material.density);
  o.s.p.film = app::initial_films(c, radii, o.prm.liquid_unit_m3);
  return o;
}

TEST(CapillaryWarning, DemoDoesNotWarnAtStartNorAfterFilmsAreSpent) {
  DemoLike o = demo_like();
  ASSERT_TRUE(o.prm.liq_pp.enabled);
  ASSERT_EQ(o.prm.liq_pp.v_min, 0);
  EXPECT_EQ(smallest_formable_bridge(o.prm.liq_pp, o.s.p.film), o.s.p.film[0]);
  EXPECT_FALSE(capillary_timestep_warning(o.prm, o.s).has_value()) << *capillary_timestep_warning(o.prm, o.s);
  for (const std::string& n : o.d.notes) EXPECT_EQ(n.find("capillary"), std::string::npos) << n;
  EXPECT_GT(o.d.dt_capillary_limit, o.d.dt);
  // Mid-run: particles 0 and 1 spent their films on a bridge 0-1; 2 keeps its film. The old check took the
  // smallest film (0) and warned for a bridge of one liquid unit, which this state cannot form.
  PairRecord r;
  r.id_i = 0;
  r.id_j = 1;
  r.bridge = o.s.p.film[0] + o.s.p.film[1];
  r.flags = kFlagWasInContact;
  o.s.pairs.push_back(r);
  o.s.p.film[0] = o.s.p.film[1] = 0;
  EXPECT_FALSE(capillary_timestep_warning_present(o.prm, o.s).has_value());
  // A bridge that is truly too stiff for dt (a thousandth of the smallest film) is reported while present.
  o.s.pairs[0].bridge = r.bridge / 1000000;
  const auto w = capillary_timestep_warning_present(o.prm, o.s);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("bridge 0-1"), std::string::npos) << *w;
  EXPECT_NE(w->find("run.dt_rayleigh_fraction"), std::string::npos) << *w;
}

TEST(CapillaryWarning, TrulyUnsafeCaseStillWarnsAtStart) {
  // V_max = 1e-6 V-bar_S caps every bridge far below the films: k_c is ~30x stiffer, the limit drops below
  // dt.
  const DemoLike o = demo_like({"liquid.v_max=1e-6"});
  EXPECT_EQ(smallest_formable_bridge(o.prm.liq_pp, o.s.p.film), o.prm.liq_pp.v_max);
  const auto w = capillary_timestep_warning(o.prm, o.s);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("smallest bridge the films can form"), std::string::npos) << *w;
  EXPECT_NE(w->find("run.dt_rayleigh_fraction"), std::string::npos) << *w;
  EXPECT_LT(o.d.dt_capillary_limit, o.d.dt);
  bool noted = false;
  for (const std::string& n : o.d.notes) noted |= n.find("capillary") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(CapillaryWarning, NoFormableBridgeBelowThreshold) {
  LiquidParams l;
  l.enabled = true;
  l.v_min = 100;
  l.v_max = 1000;
  EXPECT_EQ(smallest_formable_bridge(l, {40, 50, 45}), 0);    // 50 + 45 <= V_min: nothing forms
  EXPECT_EQ(smallest_formable_bridge(l, {40, 50, 70}), 101);  // 50 + 70 > V_min: at least V_min + 1
  EXPECT_EQ(smallest_formable_bridge(l, {400, 500, 0}), 400);
  EXPECT_EQ(smallest_formable_bridge(l, {4000, 5000}), 1000);  // capped at V_max
}

}  // namespace
}  // namespace wetdem
