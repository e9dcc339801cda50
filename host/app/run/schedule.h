// The steps at which a drum run does things. All are absolute step numbers, so a resumed run splits its work
// into the same System::step calls as an uninterrupted one (bitwise equal results).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "app/case/case.h"

namespace wetdem::app {

struct Schedule {
  uint64_t n_settle = 0, total = 0, sample = 1, snapshot = 0, checkpoint = 0, chunk = 1000;

  static uint64_t steps(double seconds, double dt) { return uint64_t(std::llround(seconds / dt)); }
  // From the case: settle, then rotate for run.duration; sample/snapshot/checkpoint intervals; a chunk of
  // 5 submits bounds the time between progress lines.
  static Schedule of(const Case& c, double dt) {
    Schedule s;
    s.n_settle = steps(c.run.settle, dt);
    s.total = s.n_settle + steps(c.run.duration, dt);
    s.sample = std::max<uint64_t>(1, steps(c.run.sample_interval, dt));
    if (!c.output.formats.empty())
      s.snapshot =
          c.output.snapshot_interval > 0 ? std::max<uint64_t>(1, steps(c.output.snapshot_interval, dt)) : 0;
    s.checkpoint = c.output.checkpoint_interval;
    s.chunk = 5ull * c.run.steps_per_submit;
    return s;
  }
  bool rotating(uint64_t s) const { return s >= n_settle; }
  bool due(uint64_t s, uint64_t every) const { return every > 0 && s % every == 0; }
  uint64_t next_multiple(uint64_t s, uint64_t every) const { return every ? (s / every + 1) * every : total; }
  // Next step at which the driver must stop stepping to do something (the settle -> rotate switch included).
  uint64_t next_stop(uint64_t s) const {
    uint64_t n = std::min({next_multiple(s, sample), next_multiple(s, snapshot), next_multiple(s, checkpoint),
                           next_multiple(s, chunk), total});
    if (s < n_settle) n = std::min(n, n_settle);
    return n;
  }
};

}  // namespace wetdem::app
