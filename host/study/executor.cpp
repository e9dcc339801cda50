#include "study/executor.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <thread>

#include "app/run/ensemble.h"
#include "vk/context.h"
#include "wetdem/version.h"

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
    const nlohmann::json j = nlohmann::json::parse(f);
    // A run of an ensemble reports the ensemble's wall time: its share is that over the runs stepped
    // together. A resumed run's wall_time_s also holds the segments before its checkpoint, spent by an
    // earlier call: this call's part is the last process's wall (wall_split_s.wall).
    const double runs = j.contains("ensemble") ? j["ensemble"].value("runs", 1.0) : 1.0;
    const double wall =
        j.contains("wall_split_s") ? j["wall_split_s"].value("wall", 0.0) : j.value("wall_time_s", 0.0);
    return wall / std::max(1.0, runs);
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

// The study indices of the runs of the batch (stopped with a checkpoint) that run `index` belongs to, in the
// batch's order; empty when it belongs to none. A batch member outside the study cannot be resumed from it.
std::vector<size_t> batch_of(const std::string& dir, const StudyIndex& ix, size_t index) {
  const std::vector<std::string> members =
      app::ensemble_members((fs::path(dir) / ix.runs[index].run_dir).string());
  std::vector<size_t> out;
  for (const std::string& m : members) {
    bool found = false;
    for (const IndexEntry& e : ix.runs)
      if (fs::exists(fs::path(dir) / e.run_dir) && fs::equivalent(fs::path(dir) / e.run_dir, m)) {
        out.push_back(e.index);
        found = true;
        break;
      }
    if (!found)
      throw StudyError(fmt::format(
          "{}: run {} was stepped in a batch with {}, which is not a run of this study", dir, index, m));
  }
  return out;
}

}  // namespace

std::vector<std::vector<size_t>> plan_batches(const std::string& dir, const std::vector<size_t>& todo,
                                              size_t batch, size_t jobs) {
  const StudyIndex ix = read_index(dir);
  std::vector<std::vector<size_t>> out;
  std::vector<bool> taken(ix.runs.size(), false);
  for (size_t i : todo) {
    if (i >= ix.runs.size() || taken[i]) continue;
    const std::vector<size_t> b = batch_of(dir, ix, i);
    if (b.empty()) continue;
    for (size_t m : b) taken[m] = true;
    out.push_back(b);
  }
  std::vector<size_t> rest;
  for (size_t i : todo)
    if (i < ix.runs.size() && !taken[i]) rest.push_back(i), taken[i] = true;
  if (rest.empty()) return out;
  // k batches: as few as the cap allows, raised to a multiple of the processes (at most one run each); the
  // first n mod k get one run more.
  const size_t n = rest.size(), cap = std::max<size_t>(1, batch), j = std::max<size_t>(1, jobs);
  size_t k = (n + cap - 1) / cap;
  k = std::min(n, (k + j - 1) / j * j);
  for (size_t b = 0, at = 0; b < k; ++b) {
    const size_t size = n / k + (b < n % k ? 1 : 0);
    out.emplace_back(rest.begin() + long(at), rest.begin() + long(at + size));
    at += size;
  }
  return out;
}

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
  if (!app::ensemble_members(run_dir.string()).empty())  // stopped inside a batch: resumes with it
    return run_batch_of(dir, {index}, device, quiet, configure)[0];
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

std::vector<OneResult> run_batch_of(
    const std::string& dir, const std::vector<size_t>& indices, const std::string& device, bool quiet,
    const std::function<void(const IndexEntry&, app::RunOptions&)>& configure) {
  const StudyIndex ix = read_index(dir);
  std::vector<OneResult> res(indices.size());
  // Fresh runs, grouped by what they must share to be stepped together (their prepared dt, drum, schedule).
  std::map<std::string, std::vector<size_t>> groups;  // key -> positions in `indices`
  std::vector<app::RunOptions> opts(indices.size());
  // Batches stopped with a checkpoint: resumed whole, once, before anything else.
  std::vector<std::vector<size_t>> resumed;
  std::map<size_t, std::pair<size_t, size_t>> in_resumed;  // study index -> (batch, position)
  for (size_t q = 0; q < indices.size(); ++q) {
    const size_t index = indices[q];
    if (index >= ix.runs.size())
      throw StudyError(fmt::format("{}: no run {} (the study has {} runs)", dir, index, ix.runs.size()));
    if (in_resumed.count(index) ||
        run_state((fs::path(dir) / ix.runs[index].run_dir).string()) == RunState::Complete)
      continue;
    const std::vector<size_t> b = batch_of(dir, ix, index);
    if (b.empty()) continue;
    for (size_t m = 0; m < b.size(); ++m) in_resumed[b[m]] = {resumed.size(), m};
    resumed.push_back(b);
  }
  std::unique_ptr<vk::Context> own;
  auto context_for = [&](const app::RunOptions& ro) {
    if (ro.context) return ro.context;
    if (!own) {
      vk::ContextOptions co;
      co.device = device;
      co.quiet = true;
      own = std::make_unique<vk::Context>(co);
    }
    return own.get();
  };
  std::vector<std::vector<OneResult>> resumed_res(resumed.size());
  for (size_t b = 0; b < resumed.size(); ++b) {
    std::vector<app::RunOptions> batch;
    for (size_t index : resumed[b]) {
      const IndexEntry& e = ix.runs[index];
      const app::Case c = app::parse_case_file((fs::path(dir) / e.case_file).string());
      if (run_hash(c, e.seed) != e.hash)
        throw StudyError(fmt::format("{}: run {} was planned by wetdem {} (hash {}); this is {}: plan again",
                                     dir, index, ix.code_version, e.hash, code_version()));
      app::RunOptions ro;
      ro.device = device;
      ro.quiet = true;
      ro.progress_tty = 0;
      ro.resume_dir = (fs::path(dir) / e.run_dir).string();
      if (configure) configure(e, ro);
      batch.push_back(ro);
    }
    resumed_res[b].assign(batch.size(), OneResult{});
    for (OneResult& o : resumed_res[b]) o.resumed = true;
    try {
      const std::vector<app::RunResult> rr = app::run_batch(batch, *context_for(batch[0]));
      for (size_t m = 0; m < rr.size(); ++m) {
        resumed_res[b][m].completed = rr[m].completed;
        if (!rr[m].completed) resumed_res[b][m].error = "stopped before the end (resumable)";
      }
    } catch (const std::exception& ex) {
      for (OneResult& o : resumed_res[b]) o.error = ex.what();
    }
  }
  for (size_t q = 0; q < indices.size(); ++q) {
    const size_t index = indices[q];
    const IndexEntry& e = ix.runs[index];
    const fs::path run_dir = fs::path(dir) / e.run_dir;
    if (const auto it = in_resumed.find(index); it != in_resumed.end()) {
      res[q] = resumed_res[it->second.first][it->second.second];
      continue;
    }
    const RunState st = run_state(run_dir.string());
    if (st == RunState::Complete) {
      res[q].skipped = true;
      continue;
    }
    if (fs::exists(run_dir / "checkpoint") || fs::exists(run_dir / "checkpoint.old")) {
      res[q] = run_one(dir, index, device, quiet, configure);  // resumes alone
      continue;
    }
    const std::string case_file = (fs::path(dir) / e.case_file).string();
    const app::Case c = app::parse_case_file(case_file);
    if (run_hash(c, e.seed) != e.hash)
      throw StudyError(fmt::format("{}: run {} was planned by wetdem {} (hash {}); this is {}: plan again",
                                   dir, index, ix.code_version, e.hash, code_version()));
    if (fs::exists(run_dir)) fs::remove_all(run_dir);
    app::RunOptions& ro = opts[q];
    ro.device = device;
    ro.quiet = true;
    ro.progress_tty = 0;
    ro.case_path = case_file;
    ro.out_dir = run_dir.string();
    if (configure) configure(e, ro);
    std::string key;
    try {
      const app::Prepared p = app::prepare_run(c);
      const app::Schedule s = app::Schedule::of(c, p.derived.dt);
      const DrumParams& d = p.prm.drum;
      key = fmt::format("{:a} {:a} {:a} {} {} {} {} {} {} {}", p.derived.dt, d.radius, d.length, d.periodic_z,
                        d.plate_lo.present, d.plate_hi.present, s.n_settle, s.total, s.sample, s.snapshot);
    } catch (const std::exception& ex) {
      res[q].error = ex.what();
      continue;
    }
    groups[key].push_back(q);
  }
  // Steps the fresh runs at positions `qs` as one ensemble and records their outcomes (throws as run_batch).
  auto step_together = [&](const std::vector<size_t>& qs) {
    std::vector<app::RunOptions> batch;
    for (size_t q : qs) batch.push_back(opts[q]);
    const std::vector<app::RunResult> rr = app::run_batch(batch, *context_for(batch[0]));
    for (size_t m = 0; m < qs.size(); ++m) {
      res[qs[m]].completed = rr[m].completed;
      if (!rr[m].completed) res[qs[m]].error = "stopped before the end (resumable)";
    }
  };
  for (const auto& [key, members] : groups) {
    try {
      step_together(members);
    } catch (const std::exception& ex) {
      for (size_t q : members) res[q].error = ex.what();
      // A batch fails whole (app::run_batch: its error is one run's, or a counter of the shared System, and
      // cannot always be pinned on a run), so a probe that blows up would fail its healthy batchmates too and
      // leave them FAILED in the store, failing every later diagnosis that needs them. Each run of a failed
      // batch is therefore run again alone (bitwise what it computes in the batch): only the runs that fail
      // on their own stay failed, each with its own reason. Not after an interruption: that batch resumes
      // whole.
      if (members.size() > 1 && !app::interrupt_requested())
        for (size_t q : members) {
          const fs::path run_dir(opts[q].out_dir);
          if (fs::exists(run_dir)) fs::remove_all(run_dir);  // not FAILED for its batchmate's reason
          res[q] = OneResult{};
          if (app::interrupt_requested()) {  // not run again: it starts afresh next time
            res[q].error = "interrupted before it was run again alone";
            continue;
          }
          try {
            step_together({q});
          } catch (const std::exception& alone) {
            res[q].error = alone.what();
          }
        }
    }
  }
  return res;
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
  const size_t batch = std::max<size_t>(1, opt.batch);
  // The processes' work: batches stopped with a checkpoint first, whole, then even batches of at most
  // `batch`.
  std::deque<std::vector<size_t>> batches;
  for (auto& b : plan_batches(dir, std::vector<size_t>(queue.begin(), queue.end()), batch,
                              size_t(std::max(1, opt.jobs))))
    batches.push_back(b);
  queue.clear();
  size_t queued = todo;
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
        rep.failed + rep.skipped_failed, queued, hms(el), final_line ? "-" : eta);
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
    while (!batches.empty() && !g_stop) {
      const std::vector<size_t> take = batches.front();
      batches.pop_front();
      queued -= take.size();
      rep.started += take.size(), running = take.size();
      progress(false);
      const auto ts = Clock::now();
      std::vector<OneResult> r(take.size());
      try {
        if (take.size() > 1 || batch > 1)
          r = run_batch_of(dir, take, opt.device, true, opt.configure);
        else
          r[0] = run_one(dir, take[0], opt.device, true, opt.configure);
      } catch (const std::exception& ex) {
        for (OneResult& x : r) x.error = ex.what();
      }
      running = 0;
      const double wall = seconds_since(ts) / double(take.size());
      for (size_t q = 0; q < take.size(); ++q) account(ix.runs[take[q]], r[q].completed, r[q].error, wall);
      progress(false);
    }
  } else {
    std::map<pid_t, std::pair<std::vector<size_t>, Clock::time_point>> live;
    bool signalled = false;
    while (!batches.empty() || !live.empty()) {
      if (g_stop) {
        batches.clear();
        queued = 0;
        // A run stops at its next step boundary on SIGTERM; its last checkpoint stays for the next `study
        // run`.
        if (!signalled)
          for (const auto& [pid, v] : live) ::kill(pid, SIGTERM);
        signalled = true;
      }
      while (!g_stop && !batches.empty() && live.size() < size_t(std::max(1, opt.jobs))) {
        const std::vector<size_t> take = batches.front();
        batches.pop_front();
        queued -= take.size();
        const bool as_batch = take.size() > 1 || batch > 1;
        std::string idx;
        for (size_t q : take) idx += (idx.empty() ? "" : ",") + std::to_string(q);
        // One process per run (run-one), or per batch of runs stepped together (run-batch).
        const std::string log =
            (fs::path(dir) / "logs" / fmt::format("{}-{}.log", as_batch ? "batch" : "run", take[0])).string();
        std::vector<std::string> args = {
            opt.exe, "study", as_batch ? "run-batch" : "run-one", dir, "--index", idx, "--quiet"};
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
        live[pid] = {take, Clock::now()};
        rep.started += take.size();
        running = 0;
        for (const auto& [p, v] : live) running += v.first.size();
        progress(false);
      }
      if (batches.empty() && live.empty()) break;
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, WNOHANG);
      if (pid <= 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      const auto it = live.find(pid);
      if (it == live.end()) continue;
      const std::vector<size_t> done_runs = it->second.first;
      const double wall = seconds_since(it->second.second) / double(done_runs.size());
      live.erase(it);
      running = 0;
      for (const auto& [p, v] : live) running += v.first.size();
      for (size_t q : done_runs) {
        const IndexEntry& e = ix.runs[q];
        const bool ok = fs::exists(fs::path(dir) / e.run_dir / "summary.json");
        std::string why;
        if (!ok) {
          why = (WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                     : fmt::format("exit {}", WEXITSTATUS(status))) +
                fmt::format(" (see logs/{}-{}.log)", done_runs.size() > 1 || batch > 1 ? "batch" : "run",
                            done_runs[0]);
          const std::string l = first_line(fs::path(dir) / e.run_dir / "FAILED.txt");
          if (!l.empty()) why = l;
        }
        account(e, ok, why, wall);
      }
      progress(false);
    }
  }
  if (g_stop) rep.interrupted = true;
  rep.wall_s = seconds_since(t0);
  progress(true);
  return rep;
}

}  // namespace wetdem::study
