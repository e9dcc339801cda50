#include "bench/steady.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "app/run/session.h"
#include "vk/context.h"
#include "wetdem/version.h"

namespace fs = std::filesystem;

namespace wetdem::bench {

std::string steady_key(const app::Case& c, const std::string& device) {
  nlohmann::json k;
  k["case"] = app::case_to_json(c);
  k["code_version"] = code_version();
  k["device"] = device;
  const std::string s = k.dump();
  return app::bytes_hash(s.data(), s.size());
}

Steady reach_steady(vk::Context& ctx, app::Case c, const SteadyOptions& opt, const Log& log) {
  Steady r;
  r.settle_s = opt.settle_s >= 0 ? opt.settle_s : c.run.settle;
  r.rotate_s = opt.rotate_s >= 0 ? opt.rotate_s : c.run.steady_state_start;
  // The run's schedule ends where timing starts: settle, then rotate_s of rotation.
  c.run.settle = r.settle_s;
  c.run.duration = r.rotate_s;
  r.prep = std::make_unique<app::Prepared>(app::prepare_run(c));
  const app::Prepared& prep = *r.prep;
  r.key = steady_key(c, ctx.info().name);
  const std::string name = c.name.empty() ? fs::path(c.source).stem().string() : c.name;
  if (!opt.cache_dir.empty()) {
    r.cache_path = (fs::path(opt.cache_dir) / (name + "-" + r.key)).string();
    if (app::has_checkpoint(r.cache_path)) {
      try {
        r.ck = app::load_checkpoint(r.cache_path);
        if (r.ck.host.value("radii_hash", "") != prep.radii_hash)
          throw std::runtime_error("its particles differ from the case's fill");
        r.from_cache = true;
        r.step = r.ck.host.at("step").get<uint64_t>();
        r.prepare_wall_s = r.ck.host.value("prepare_wall_s", 0.0);
        log(fmt::format("{}: steady state from the cache ({}), step {}", name, r.cache_path, r.step));
        return r;
      } catch (const std::exception& e) {
        log(fmt::format("{}: cache entry {} not usable ({}); preparing again", name, r.cache_path, e.what()));
      }
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  app::DrumSession s(ctx, prep, [&](const std::string& l) { log(name + ": " + l); });
  const app::Schedule& sch = s.schedule();
  log(fmt::format("{}: preparing {} particles: {} settle + {} rotating steps (dt {:.3g} s)", name,
                  prep.state.p.size(), sch.n_settle, sch.total - sch.n_settle, prep.derived.dt));
  double last = 0;
  while (!s.done()) {
    s.advance(sch.next_stop(s.step()));
    if (wall() - last > 30.0 || s.done()) {
      last = wall();
      log(fmt::format("{}: step {} / {} ({:.0f} s wall, {:.3g} particle-steps/s)", name, s.step(), sch.total,
                      wall(), double(prep.state.p.size()) * double(s.step()) / wall()));
    }
  }
  s.sample();  // health: throws on a blow-up, lost bridges or escaped particles
  r.prepare_wall_s = wall();
  r.step = s.step();
  r.ck = s.checkpoint({{"prepare_wall_s", r.prepare_wall_s}, {"key", r.key}});
  if (!r.cache_path.empty()) {
    fs::create_directories(r.cache_path);
    app::save_checkpoint(r.cache_path, r.ck);
  }
  return r;
}

}  // namespace wetdem::bench
