#include "app/run/session.h"

#include "app/run/sample.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "app/drum/aor.h"
#include "app/observe/camera.h"
#include "wetdem/observables.h"
#include "wetdem/timestep.h"

namespace wetdem::app {

SimParams phase_params(const SimParams& prm, bool rotating) {
  SimParams p = prm;
  if (!rotating) p.drum.omega = 0.0;  // settle with the drum at rest
  return p;
}

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
  // Candidate effect `viscous`: explicit stability of the lubrication damper (docs/model.md "Candidate
  // effects").
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
  SampleContext x;
  x.prep = &prep_;
  x.prm = &sys_->params();
  x.step = step_;
  x.time = time();
  x.liquid_start = liquid_start_;
  x.counters = sys_->counters();
  samples_.push_back(take_sample(sys_->sample_runs()[0], x, dt_warned_, log_));
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
