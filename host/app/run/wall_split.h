// Where a run's wall-clock time goes, by the run loop's activities. Why: on an H100 a full-size PP2 l = 5 run
// moved at ~55 % of the rate `wetdem_bench` times for the same steps (docs/benchmark.md, 26 Nov 2026); the
// split in summary.json ("wall_split_s") and the run log says which of the loop's stops costs the rest.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

namespace wetdem::app {

struct WallSplit {
  // stepping: System::step calls (their submits and fence waits); sampling: the device reductions, the slim
  // download and the host's observables; frames: state downloads and frame files; checkpoints: snapshots
  // written to disk. The rest of the wall time (progress lines, logs) is "other".
  double stepping = 0, sampling = 0, frames = 0, checkpoints = 0;

  template <class F>
  void time(double& into, F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    into += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  double other(double wall) const { return wall - stepping - sampling - frames - checkpoints; }
  nlohmann::json json(double wall) const {
    return {{"stepping", stepping},       {"sampling", sampling}, {"frames", frames},
            {"checkpoints", checkpoints}, {"other", other(wall)}, {"wall", wall}};
  }
  std::string line(double wall) const {
    const double w = wall > 0 ? 100.0 / wall : 0.0;
    return fmt::format(
        "wall {:.1f} s: stepping {:.0f} %, sampling {:.0f} %, frames {:.0f} %, checkpoints {:.0f} %, other "
        "{:.0f} %",
        wall, stepping * w, sampling * w, frames * w, checkpoints * w, other(wall) * w);
  }
};

}  // namespace wetdem::app
