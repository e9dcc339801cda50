#include "app/output/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace wetdem::app {

Progress::Progress(std::FILE* out, uint64_t first_step, bool quiet, int tty, double line_interval_s)
    : out_(out),
      quiet_(quiet),
      tty_(tty < 0 ? bool(isatty(fileno(out))) : tty > 0),
      interval_(line_interval_s),
      first_step_(first_step),
      last_step_(first_step),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

double Progress::steps_per_s() const {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return s > 0 ? double(last_step_ - first_step_) / s : 0.0;
}

std::string Progress::format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const long t = std::lround(s);
  if (t >= 3600) return fmt::format("{} h {:02d} min", t / 3600, int((t % 3600) / 60));
  if (t >= 60) return fmt::format("{} min {:02d} s", t / 60, int(t % 60));
  return fmt::format("{} s", t);
}

std::string Progress::line(const ProgressInfo& p, bool bar) const {
  const double rate = steps_per_s();
  const double eta = rate > 0 ? double(p.total_steps - p.step) / rate : -1.0;
  std::string aor = p.aor_deg >= 0 ? fmt::format("AoR {:.1f}°", p.aor_deg) : "AoR -";
  if (p.aor_mean_deg >= 0) aor += fmt::format(" (mean {:.1f}°)", p.aor_mean_deg);
  const double frac = p.total_steps ? double(p.step) / double(p.total_steps) : 1.0;
  std::string head;
  if (bar) {
    const int width = 24, filled = int(std::floor(frac * width));
    head = "[" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.') + "] ";
  }
  return fmt::format("{}{:5.1f}%  {} step {}/{}  t = {:.3f} s  {:.0f} steps/s  {}  ETA {}", head,
                     100.0 * frac, p.phase, p.step, p.total_steps, p.sim_time, rate, aor,
                     format_duration(eta));
}

void Progress::update(const ProgressInfo& p) {
  last_step_ = p.step;
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (printed_ && since < (tty_ ? 0.2 : interval_)) return;
  last_print_ = now;
  printed_ = true;
  if (tty_)
    std::fprintf(out_, "\r%s\x1b[K", line(p, true).c_str());
  else
    std::fprintf(out_, "%s\n", line(p, false).c_str());
  std::fflush(out_);
}

void Progress::finish(const ProgressInfo& p) {
  last_step_ = p.step;
  if (quiet_) return;
  if (tty_)
    std::fprintf(out_, "\r%s\x1b[K\n", line(p, true).c_str());
  else
    std::fprintf(out_, "%s\n", line(p, false).c_str());
  std::fflush(out_);
}

}  // namespace wetdem::app
