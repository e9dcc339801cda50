#include "app/run/session.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "app/drum/aor.h"
#include "app/observe/camera.h"
#include "wetdem/observables.h"
#include "wetdem/timestep.h"

namespace wetdem::app {

namespace {

SimParams phase_params(const SimParams& prm, bool rotating) {
  SimParams p = prm;
  if (!rotating) p.drum.omega = 0.0;  // settle with the drum at rest
  return p;
}

}  // namespace

DrumSession::DrumSession(vk::Context& ctx, const Prepared& prep, LogFn log)
    : ctx_(ctx), prep_(prep), log_(std::move(log)), sch_(Schedule::of(prep.c, prep.derived.dt)) {
  so_.steps_per_submit = prep.c.run.steps_per_submit;
  liquid_start_ = prep.state.total_liquid();
  make_system(sch_.rotating(0));
  sys_->upload(prep.state);
  // physics.md §6 at start: the bridges this case can form.
  if (auto w = capillary_timestep_warning(prep.prm, prep.state)) {
    log_("WARNING: " + *w);
    dt_warned_ = true;
  }
  // Candidate effect `viscous`: explicit stability of the lubrication damper (README "Candidate effects").
  if (auto w = viscous_timestep_warning(prep.prm, prep.state)) log_("WARNING: " + *w);
}

DrumSession::DrumSession(vk::Context& ctx, const Prepared& prep, const Checkpoint& ck, LogFn log)
    : ctx_(ctx), prep_(prep), log_(std::move(log)), sch_(Schedule::of(prep.c, prep.derived.dt)) {
  so_.steps_per_submit = prep.c.run.steps_per_submit;
  step_ = ck.host.at("step").get<uint64_t>();
  samples_ = samples_from_json(ck.host.at("samples"));
  liquid_start_ = ck.host.at("liquid_start").get<int64_t>();
  resumed_host_ = ck.host;
  make_system(sch_.rotating(step_));
  sys_->restore(ck.system);
}

void DrumSession::make_system(bool rotating) {
  sys_ = std::make_unique<System>(ctx_, phase_params(prep_.prm, rotating), prep_.state.p.size(), so_);
}

void DrumSession::advance(uint64_t to) {
  if (to <= step_) return;
  if (to > sch_.next_stop(step_)) throw std::logic_error("DrumSession::advance past the next scheduled stop");
  sys_->step(to - step_);
  step_ = to;
  if (step_ == sch_.n_settle && sch_.n_settle > 0) {
    // Rotation starts: the drum's speed is set in place (the state stays on the device untouched; done
    // identically in a resumed run, whose checkpoint is written after it, and in an ensemble).
    sys_->set_run_params(0, phase_params(prep_.prm, true));
    log_(fmt::format("settled at t = {:.4g} s: drum starts turning at {:.4g} rad/s", time(),
                     prep_.prm.drum.omega));
  }
}

SystemState DrumSession::state() {
  SystemState st = sys_->download();
  st.time = time();
  st.step = step_;
  return st;
}

const Sample& DrumSession::sample() {
  const SystemState st = sys_->download();
  const Observables o = compute_observables(st, sys_->params());
  // physics.md §6: warn (once) when dt is too large for the stiffest bridge present.
  if (!dt_warned_)
    if (auto w = capillary_timestep_warning_present(sys_->params(), st)) {
      log_("WARNING: " + *w);
      dt_warned_ = true;
    }
  const SystemCounters k = sys_->counters();
  if (!std::isfinite(o.kinetic_energy))
    throw std::runtime_error(
        fmt::format("kinetic energy is not finite at step {}: the run blew up (dt too large?)", step_));
  if (k.lost_bridges > 0)
    throw std::runtime_error(
        fmt::format("{} liquid bridges were lost with pairs leaving the neighbour list", k.lost_bridges));
  if (k.escaped > 0)
    throw std::runtime_error(fmt::format("{} particles escaped the drum by step {}", k.escaped, step_));
  const AorSample a = dynamic_aor(std::vector<glm::dvec3>{o.com}, {}, prep_.prm.drum.radius);
  Sample x;
  x.step = step_;
  x.time = time();
  x.aor_signed_deg = a.signed_deg;
  x.com_x = o.com.x;
  x.com_y = o.com.y;
  x.flagged = a.flagged;
  x.contacts = o.contacts;
  x.bridges = o.bridges;
  x.f_wet = o.f_wet;
  x.kinetic_energy = o.kinetic_energy;
  x.camera = observe::observe_camera(st, prep_.prm, liquid_start_);      // diagnosis.md §2
  x.liquid_films = o.liquid_films, x.liquid_bridges = o.liquid_bridges;  // liquid accounting
  x.liquid_pores = o.liquid_pores, x.liquid_evaporated = o.liquid_evaporated;
  x.liquid_unit_m3 = prep_.prm.liquid_unit_m3;
  samples_.push_back(x);
  return samples_.back();
}

Checkpoint DrumSession::checkpoint(const nlohmann::json& extra) const {
  Checkpoint k;
  k.system = sys_->snapshot();
  k.host = extra;
  k.host["step"] = step_;
  k.host["time_s"] = time();
  k.host["samples"] = samples_to_json(samples_);
  k.host["liquid_start"] = liquid_start_;
  k.host["radii_hash"] = prep_.radii_hash;
  k.host["device"] = sys_->device_name();
  k.host["seed"] = prep_.c.run.seed;
  k.host["case"] = case_to_json(prep_.c);
  return k;
}

}  // namespace wetdem::app
