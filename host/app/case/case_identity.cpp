// physics_identity (case.h): the parameters that cannot act in a case, reset to their defaults.
#include "app/case/case.h"

namespace wetdem::app {

Case physics_identity(const Case& c) {
  Case id = c;
  if (!c.liquid.on()) {
    // No film, no bridge: lubrication, the receding angle, evaporation, the wetted fraction's draw (its own
    // RNG stream, spread_films) and pore absorption have no liquid to act on. The dry time step does not see
    // them either (case_viscous_dt_limit is 0 without liquid).
    const LiquidSpec none;
    id.liquid.viscosity = none.viscosity;
    id.liquid.lubrication_cutoff = none.lubrication_cutoff;
    id.liquid.theta_receding = none.theta_receding;
    id.liquid.evaporation_time = none.evaporation_time;
    id.liquid.wetted_fraction = none.wetted_fraction;
    id.absorption = AbsorptionSpec{};
  }
  // Words, not physics (the only ones case_to_json echoes).
  id.name.clear();
  id.description.clear();
  return id;
}

}  // namespace wetdem::app
