// A shipped case brought into rotation through the real run phases (prepare_run, DrumSession: settle, then
// rotate), checkpointed in a cache folder so the set-up is paid once per machine. The cache entry is keyed by
// the resolved case (with the preparation's settle and rotation lengths), the code version and the device.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "app/output/checkpoint.h"
#include "app/run/run.h"

namespace wetdem::vk {
class Context;
}

namespace wetdem::bench {

struct SteadyOptions {
  std::string cache_dir;  // empty: no cache (prepare every time)
  double settle_s = -1;   // drum at rest (s); < 0: the case's run.settle
  double rotate_s = -1;   // rotation before timing (s); < 0: the case's run.steady_state_start
};

struct Steady {
  std::unique_ptr<app::Prepared>
      prep;                // the case as prepared, with run.settle/run.duration = the preparation
  app::Checkpoint ck;      // the state where timing starts (DrumSession::checkpoint)
  std::string key;         // cache key
  std::string cache_path;  // the cache entry's folder (empty without a cache)
  bool from_cache = false;
  double prepare_wall_s = 0;  // wall time of the preparation when it ran (from the cache entry otherwise)
  double settle_s = 0, rotate_s = 0;
  uint64_t step = 0;  // steps done (settle + rotation)
};

using Log = std::function<void(const std::string&)>;

// The cache key of a case prepared with these settle/rotate lengths on this device with this build.
std::string steady_key(const app::Case& c, const std::string& device);

Steady reach_steady(vk::Context& ctx, app::Case c, const SteadyOptions& opt, const Log& log);

}  // namespace wetdem::bench
