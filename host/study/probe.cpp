#include "study/probe.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "app/run/ensemble.h"
#include "app/run/resources.h"
#include "app/run/run.h"
#include "vk/context.h"

namespace wetdem::study {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Particles (estimated from the PSD as `wetdem check` does), steps and samples of a run.
struct Size {
  double particles = 0, steps = 0, samples = 0;
};
Size size_of_run(const app::Case& c) {
  const app::ResourceEstimate e = app::estimate_resources(c);
  Size s;
  s.particles = e.particles;
  s.steps = e.steps;
  s.samples = std::floor((c.run.settle + c.run.duration) / c.run.sample_interval) + 1.0;
  return s;
}

}  // namespace

ProbeResult probe(const std::vector<PlannedRun>& runs, size_t batch, uint64_t steps,
                  const std::string& device) {
  if (runs.empty()) throw StudyError("probe: no runs to measure");
  const size_t k = std::min(std::max<size_t>(1, batch), runs.size());
  ProbeResult r;
  vk::ContextOptions co;
  co.device = device;
  co.quiet = true;
  vk::Context ctx(co);
  r.device = ctx.info().name;
  std::vector<std::unique_ptr<app::Prepared>> preps;
  std::vector<const app::Prepared*> view;
  const auto t_setup = Clock::now();
  for (size_t i = 0; i < k; ++i) {
    preps.push_back(std::make_unique<app::Prepared>(app::prepare_run(runs[i].resolved)));
    view.push_back(preps.back().get());
    r.particles += preps.back()->state.p.size();
  }
  r.setup_s_per_run = since(t_setup) / double(k);
  r.runs = k;
  app::DrumEnsemble ens(ctx, view, [](size_t, const std::string&) {});
  const app::Schedule& sch = ens.schedule();
  auto step_to = [&](uint64_t to) {
    while (ens.step() < to && !ens.done()) ens.advance(std::min(to, sch.next_stop(ens.step())));
  };
  step_to(std::min<uint64_t>(sch.total, 20));  // pipelines, first list build: not timed
  ens.sample();
  const uint64_t from = ens.step();
  const auto t_steps = Clock::now();
  step_to(std::min<uint64_t>(sch.total, from + steps));
  const double wall = since(t_steps);
  r.steps = ens.step() - from;
  if (r.steps == 0) throw StudyError("probe: the runs are shorter than the warm-up");
  r.step_s = wall / double(r.steps);
  const auto t_sample = Clock::now();
  const int reps = 3;
  for (int i = 0; i < reps; ++i) ens.sample();
  r.sample_s = since(t_sample) / reps;
  r.particle_steps_per_s = double(r.particles) / r.step_s;
  return r;
}

Estimate estimate(const std::vector<PlannedRun>& runs, size_t batch, const ProbeResult& p) {
  Estimate e;
  const size_t k = std::max<size_t>(1, batch);
  const double step_per_particle = p.step_s / double(std::max<size_t>(1, p.particles));
  const double sample_per_particle = p.sample_s / double(std::max<size_t>(1, p.particles));
  for (size_t b = 0; b < runs.size(); b += k) {
    double particles = 0, steps = 0, samples = 0;
    for (size_t i = b; i < std::min(runs.size(), b + k); ++i) {
      const Size s = size_of_run(runs[i].resolved);
      particles += s.particles;
      steps = std::max(steps, s.steps);  // a batch's runs share the schedule
      samples = std::max(samples, s.samples);
      e.particle_steps += s.particles * s.steps;
      e.setup_s += p.setup_s_per_run;
      ++e.runs;
    }
    const double st = steps * particles * step_per_particle, sa = samples * particles * sample_per_particle;
    e.step_s += st;
    e.sample_s += sa;
    e.batch_s.push_back(p.setup_s_per_run * double(std::min(runs.size(), b + k) - b) + st + sa);
    ++e.batches;
  }
  return e;
}

MeasuredRate measured_rate(const std::vector<nlohmann::json>& summaries, const std::string& device) {
  MeasuredRate m;
  double sum = 0;
  for (const nlohmann::json& j : summaries) {
    if ((!device.empty() && j.value("device", std::string()) != device) || !j.contains("wall_split_s"))
      continue;
    const double stepping = j["wall_split_s"].value("stepping", 0.0);
    const double k = j.contains("ensemble") ? j["ensemble"].value("runs", 1.0) : 1.0;
    const double n = j.value("particles", 0.0);
    const double stepped = j.value("steps", 0.0) - j.value("resumed_from_step", 0.0);
    if (!(stepping > 0) || !(n > 0) || !(stepped > 0) || !(k >= 1)) continue;
    sum += stepping / (k * n * stepped);
    const size_t kk = size_t(k);
    m.batch_min = m.runs ? std::min(m.batch_min, kk) : kk;
    m.batch_max = std::max(m.batch_max, kk);
    ++m.runs;
  }
  if (m.runs) m.particle_steps_per_s = double(m.runs) / sum;
  return m;
}

ProbeResult at_rate(ProbeResult p, double particle_steps_per_s) {
  if (particle_steps_per_s > 0) {
    p.particle_steps_per_s = particle_steps_per_s;
    p.step_s = double(p.particles) / particle_steps_per_s;
  }
  return p;
}

nlohmann::json to_json(const MeasuredRate& m) {
  return {{"runs", m.runs},
          {"particle_steps_per_s", m.particle_steps_per_s},
          {"batch_min", m.batch_min},
          {"batch_max", m.batch_max}};
}

nlohmann::json to_json(const ProbeResult& p) {
  return {{"runs", p.runs},
          {"particles", p.particles},
          {"steps", p.steps},
          {"setup_s_per_run", p.setup_s_per_run},
          {"step_s", p.step_s},
          {"sample_s", p.sample_s},
          {"particle_steps_per_s", p.particle_steps_per_s},
          {"device", p.device}};
}

nlohmann::json to_json(const Estimate& e) {
  return {{"batches", e.batches},   {"runs", e.runs},      {"particle_steps", e.particle_steps},
          {"setup_s", e.setup_s},   {"step_s", e.step_s},  {"sample_s", e.sample_s},
          {"total_s", e.total_s()}, {"batch_s", e.batch_s}};
}

}  // namespace wetdem::study
