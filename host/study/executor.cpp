#include "study/executor.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

volatile std::sig_atomic_t g_stop = 0;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string hms(double s) {
  if (!(s >= 0) || s > 1e8) return "?";
  const long t = long(s + 0.5);
  if (t >= 3600) return fmt::format("{}h{:02}m", t / 3600, (t / 60) % 60);
  if (t >= 60) return fmt::format("{}m{:02}s", t / 60, t % 60);
  return fmt::format("{}s", t);
}

double summary_wall(const fs::path& run_dir) {
  std::ifstream f(run_dir / "summary.json");
  if (!f) return 0;
  try {
    return nlohmann::json::parse(f).value("wall_time_s", 0.0);
  } catch (const std::exception&) {
    return 0;
  }
}

std::string first_line(const fs::path& p) {
  std::ifstream f(p);
  std::string l;
  std::getline(f, l);
  return l;
}

}  // namespace

void request_study_interrupt() {
  g_stop = 1;
  app::request_interrupt();
}

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

OneResult run_one(const std::string& dir, size_t index, const std::string& device, bool quiet,
                  const std::function<void(const IndexEntry&, app::RunOptions&)>& configure) {
  const StudyIndex ix = read_index(dir);
  if (index >= ix.runs.size())
    throw StudyError(fmt::format("{}: no run {} (the study has {} runs)", dir, index, ix.runs.size()));
  const IndexEntry& e = ix.runs[index];
  const fs::path run_dir = fs::path(dir) / e.run_dir;
  OneResult r;
  const RunState st = run_state(run_dir.string());
  if (st == RunState::Complete) return r.skipped = true, r;
  const std::string case_file = (fs::path(dir) / e.case_file).string();
  // The hash names what the run computes: refuse to compute something else under it.
  const app::Case c = app::parse_case_file(case_file);
  if (run_hash(c, e.seed) != e.hash)
    throw StudyError(
        fmt::format("{}: run {} was planned by wetdem {} (hash {}); this is {}: plan again with "
                    "`wetdem study run` or `study slurm`",
                    dir, index, ix.code_version, e.hash, code_version()));
  const bool ckpt = fs::exists(run_dir / "checkpoint") || fs::exists(run_dir / "checkpoint.old");
  app::RunOptions ro;
  ro.device = device;
  ro.quiet = quiet;
  ro.progress_tty = 0;
  if (ckpt) {
    ro.resume_dir = run_dir.string();
    r.resumed = true;
  } else {
    if (fs::exists(run_dir)) fs::remove_all(run_dir);  // killed before its first checkpoint: start over
    ro.case_path = case_file;
    ro.out_dir = run_dir.string();
  }
  if (configure) configure(e, ro);
  try {
    const app::RunResult rr = app::run_case(ro);
    r.completed = rr.completed;
    if (!rr.completed) r.error = "stopped before the end (resumable)";
  } catch (const std::exception& ex) {
    r.error = ex.what();
  }
  return r;
}

ExecReport run_study(const std::string& dir, const ExecOptions& opt) {
  const auto t0 = Clock::now();
  g_stop = 0;
  const StudyIndex ix = read_index(dir);
  ExecReport rep;
  rep.total = ix.runs.size();
  std::deque<size_t> queue;
  for (const IndexEntry& e : ix.runs) {
    std::string why;
    const RunState st = run_state((fs::path(dir) / e.run_dir).string(), &why);
    if (st == RunState::Complete) {
      ++rep.already_complete;
    } else if (st == RunState::Failed && !opt.retry_failed) {
      ++rep.skipped_failed;
      rep.failures.push_back(
          fmt::format("run {} ({}): {} [not retried; --retry-failed]", e.index, e.hash, why));
    } else {
      queue.push_back(e.index);
    }
  }
  const size_t todo = queue.size();
  const bool tty = isatty(STDOUT_FILENO);
  size_t running = 0, finished = 0;
  double finished_wall = 0;
  std::string last;
  auto progress = [&](bool final_line) {
    if (opt.quiet) return;
    const double el = seconds_since(t0);
    const double per = finished ? finished_wall / double(finished) : 0;
    const int jobs = std::max(1, opt.jobs);
    const std::string eta =
        finished ? hms(per * double(todo - finished) / double(std::min<size_t>(jobs, todo - finished + 1)))
                 : std::string("?");
    const std::string line = fmt::format(
        "study {}: {}/{} done ({} already), {} running, {} failed, {} queued | elapsed {}, ETA {}", ix.name,
        rep.already_complete + rep.completed, rep.total, rep.already_complete, running,
        rep.failed + rep.skipped_failed, queue.size(), hms(el), final_line ? "-" : eta);
    if (line == last && !final_line) return;
    last = line;
    if (tty)
      std::printf("\r%s\033[K%s", line.c_str(), final_line ? "\n" : "");
    else
      std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  auto account = [&](const IndexEntry& e, bool completed, const std::string& why, double wall) {
    ++finished;
    finished_wall += wall;
    rep.process_wall_s += wall;
    if (completed) {
      ++rep.completed;
      rep.run_wall_s += summary_wall(fs::path(dir) / e.run_dir);
    } else {
      std::string reason = why;
      const RunState st = run_state((fs::path(dir) / e.run_dir).string(), &reason);
      if (st == RunState::Resumable || st == RunState::Interrupted) {
        ++rep.stopped;
        rep.failures.push_back(fmt::format("run {} ({}): stopped, resumable: {}", e.index, e.hash, reason));
      } else {
        ++rep.failed;
        rep.failures.push_back(fmt::format(
            "run {} ({}): FAILED: {}", e.index, e.hash,
            reason.empty() ? std::string("see logs/run-") + std::to_string(e.index) + ".log" : reason));
      }
    }
  };
  progress(false);

  if (opt.exe.empty()) {
    while (!queue.empty() && !g_stop) {
      const IndexEntry& e = ix.runs[queue.front()];
      queue.pop_front();
      ++rep.started, running = 1;
      progress(false);
      const auto ts = Clock::now();
      OneResult r;
      try {
        r = run_one(dir, e.index, opt.device, true, opt.configure);
      } catch (const std::exception& ex) {
        r.error = ex.what();
      }
      running = 0;
      account(e, r.completed, r.error, seconds_since(ts));
      progress(false);
    }
  } else {
    std::map<pid_t, std::pair<size_t, Clock::time_point>> live;
    bool signalled = false;
    while (!queue.empty() || !live.empty()) {
      if (g_stop) {
        queue.clear();
        // A run stops at its next step boundary on SIGTERM; its last checkpoint stays for the next `study
        // run`.
        if (!signalled)
          for (const auto& [pid, v] : live) ::kill(pid, SIGTERM);
        signalled = true;
      }
      while (!g_stop && !queue.empty() && live.size() < size_t(std::max(1, opt.jobs))) {
        const IndexEntry& e = ix.runs[queue.front()];
        queue.pop_front();
        const std::string log = (fs::path(dir) / "logs" / fmt::format("run-{}.log", e.index)).string();
        const std::string idx = std::to_string(e.index);
        std::vector<std::string> args = {opt.exe, "study", "run-one", dir, "--index", idx, "--quiet"};
        if (!opt.device.empty()) args.insert(args.end(), {"--device", opt.device});
        std::fflush(stdout);
        const pid_t pid = ::fork();
        if (pid < 0) throw std::runtime_error("study: fork failed");
        if (pid == 0) {
          const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
          if (fd >= 0) ::dup2(fd, STDOUT_FILENO), ::dup2(fd, STDERR_FILENO), ::close(fd);
          std::vector<char*> argv;
          for (std::string& a : args) argv.push_back(a.data());
          argv.push_back(nullptr);
          ::execv(opt.exe.c_str(), argv.data());
          ::_exit(127);
        }
        live[pid] = {e.index, Clock::now()};
        ++rep.started;
        running = live.size();
        progress(false);
      }
      if (queue.empty() && live.empty()) break;
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, WNOHANG);
      if (pid <= 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      const auto it = live.find(pid);
      if (it == live.end()) continue;
      const IndexEntry& e = ix.runs[it->second.first];
      const double wall = seconds_since(it->second.second);
      live.erase(it);
      running = live.size();
      const bool ok = fs::exists(fs::path(dir) / e.run_dir / "summary.json");
      std::string why;
      if (!ok) {
        why = (WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                   : fmt::format("exit {}", WEXITSTATUS(status))) +
              fmt::format(" (see logs/run-{}.log)", e.index);
        const std::string l = first_line(fs::path(dir) / e.run_dir / "FAILED.txt");
        if (!l.empty()) why = l;
      }
      account(e, ok, why, wall);
      progress(false);
    }
  }
  if (g_stop) rep.interrupted = true;
  rep.wall_s = seconds_since(t0);
  progress(true);
  return rep;
}

}  // namespace wetdem::study
