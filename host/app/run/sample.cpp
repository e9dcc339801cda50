#include "app/run/sample.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "app/drum/aor.h"
#include "app/observe/camera.h"
#include "app/observe/interface.h"
#include "wetdem/observables.h"
#include "wetdem/timestep.h"

namespace wetdem::app {

namespace {

// The sample from the reductions `o` and a state `st` holding at least positions, velocities, radii, masses
// and the bridged pairs (the slim state of System::sample_runs, or a whole one).
Sample make_sample(const Observables& o, const SystemState& st, const SampleContext& x, bool& dt_warned,
                   const std::function<void(const std::string&)>& log) {
  const Prepared& prep = *x.prep;
  // physics.md §6: warn (once) when dt is too large for the stiffest bridge present.
  if (!dt_warned)
    if (auto w = capillary_timestep_warning_present(*x.prm, st)) {
      log("WARNING: " + *w);
      dt_warned = true;
    }
  const SystemCounters& k = x.counters;
  if (!std::isfinite(o.kinetic_energy))
    throw std::runtime_error(
        fmt::format("kinetic energy is not finite at step {}: the run blew up (dt too large?)", x.step));
  if (k.lost_bridges > 0)
    throw std::runtime_error(
        fmt::format("{} liquid bridges were lost with pairs leaving the neighbour list", k.lost_bridges));
  if (k.escaped > 0)
    throw std::runtime_error(fmt::format("{} particles escaped the drum by step {}", k.escaped, x.step));
  const AorSample a = dynamic_aor(std::vector<glm::dvec3>{o.com}, {}, prep.prm.drum.radius);
  Sample s;
  s.step = x.step;
  s.time = x.time;
  s.aor_signed_deg = a.signed_deg;
  s.com_x = o.com.x;
  s.com_y = o.com.y;
  s.flagged = a.flagged;
  s.contacts = o.contacts;
  s.bridges = o.bridges;
  s.f_wet = o.f_wet;
  s.kinetic_energy = o.kinetic_energy;
  // diagnosis.md §2; the free liquid (films + bridges) from the reductions
  s.camera = observe::observe_camera(st, prep.prm, x.liquid_start, o.liquid_films + o.liquid_bridges);
  s.interface = observe::interface_profile(st, prep.prm.drum.radius, prep.prm.drum.length);
  s.liquid_films = o.liquid_films, s.liquid_bridges = o.liquid_bridges;  // liquid accounting
  s.liquid_pores = o.liquid_pores, s.liquid_evaporated = o.liquid_evaporated;
  s.liquid_unit_m3 = prep.prm.liquid_unit_m3;
  return s;
}

}  // namespace

Sample take_sample(const RunSample& rs, const SampleContext& x, bool& dt_warned,
                   const std::function<void(const std::string&)>& log) {
  return make_sample(rs.obs, rs.bed, x, dt_warned, log);
}

Sample take_sample(const SystemState& st, const SampleContext& x, bool& dt_warned,
                   const std::function<void(const std::string&)>& log) {
  return make_sample(compute_observables(st, *x.prm), st, x, dt_warned, log);
}

}  // namespace wetdem::app
