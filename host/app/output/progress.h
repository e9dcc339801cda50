// Progress of a run on stdout: a redrawn bar when stdout is a terminal, plain lines (at most one per
// `line_interval_s` of wall time) when it is a file or pipe, so logs stay readable.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace wetdem::app {

struct ProgressInfo {
  uint64_t step = 0, total_steps = 0;
  double sim_time = 0;       // s since the start of the run (settling included)
  const char* phase = "";    // "settle" / "rotate"
  double aor_deg = -1;       // last sample's |AoR| (< 0: none or flagged)
  double aor_mean_deg = -1;  // mean over the steady window so far (< 0: none yet)
};

class Progress {
 public:
  // tty < 0: detect with isatty(fileno(out)). quiet: print nothing.
  Progress(std::FILE* out, uint64_t first_step, bool quiet = false, int tty = -1,
           double line_interval_s = 10.0);
  void update(const ProgressInfo& p);  // rate-limited; call as often as convenient
  void finish(const ProgressInfo& p);  // final line (ends the bar with a newline)
  double steps_per_s() const;          // over this session

  static std::string format_duration(double seconds);  // "1 h 02 min", "3 min 05 s", "42 s"

 private:
  std::string line(const ProgressInfo& p, bool bar) const;
  std::FILE* out_;
  bool quiet_, tty_;
  double interval_;
  uint64_t first_step_, last_step_ = 0;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool printed_ = false;
};

}  // namespace wetdem::app
