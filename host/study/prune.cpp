#include "study/prune.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/run/resources.h"
#include "study/store.h"
#include "study/study_file.h"

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

uint64_t bytes_under(const fs::path& p) {
  uint64_t n = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec))
    if (it->is_regular_file(ec)) n += it->file_size(ec);
  return n;
}

// The run version a complete run's summary records; "" when it records none (or cannot be read).
std::string recorded_version(const fs::path& summary) {
  std::ifstream f(summary);
  const nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("run_version") || !j["run_version"].is_string())
    return "";
  return j["run_version"].get<std::string>();
}

std::string group_line(const StoreCensus::Group& g, const std::string& what) {
  return fmt::format("  {:>5} run{}, {:>8}: {}\n", g.runs, g.runs == 1 ? " " : "s",
                     app::bytes_text(double(g.bytes)), what);
}

}  // namespace

StoreCensus take_census(const std::string& dir, const std::string& version) {
  const fs::path runs = fs::path(dir) / "runs";
  if (!fs::is_directory(runs))
    throw StudyError(
        fmt::format("{}: not a run store (no runs/ folder); give the --store or --out "
                    "directory of a study, twin or diagnosis",
                    dir));
  StoreCensus c;
  c.version = version;
  for (const fs::directory_entry& e : fs::directory_iterator(runs)) {
    if (!e.is_directory()) continue;
    const uint64_t bytes = bytes_under(e.path());
    StoreCensus::Group* g = &c.incomplete;
    if (run_state(e.path().string()) == RunState::Complete) {
      const std::string v = recorded_version(e.path() / "summary.json");
      g = v == version ? &c.current : v.empty() ? &c.unrecorded : &c.other[v];
      if (v != version) c.removable.push_back(e.path().filename().string());
    }
    g->runs++;
    g->bytes += bytes;
  }
  std::sort(c.removable.begin(), c.removable.end());
  return c;
}

std::string describe_census(const StoreCensus& c) {
  std::string s = group_line(c.current, "complete, this binary's run version " + c.version + " (reused)");
  for (const auto& [v, g] : c.other) s += group_line(g, "complete, run version " + v + " (not reused here)");
  if (c.unrecorded.runs)
    s += group_line(c.unrecorded, "complete, no run version recorded (an older binary; not reused here)");
  if (c.incomplete.runs)
    s += group_line(c.incomplete, "without a summary: partial, resumable or failed (kept)");
  return s;
}

uint64_t prune_runs(const std::string& dir, const StoreCensus& c) {
  StoreLock lock(dir);
  uint64_t freed = 0;
  for (const std::string& h : c.removable) {
    const fs::path run = fs::path(dir) / "runs" / h;
    // Re-checked under the lock: a run completed again by this version since the census is kept.
    if (run_state(run.string()) != RunState::Complete || recorded_version(run / "summary.json") == c.version)
      continue;
    freed += bytes_under(run);
    fs::remove_all(run);
    std::error_code ec;
    const fs::path cs = fs::path(dir) / "cases" / (h + ".toml");
    if (fs::exists(cs, ec)) {
      freed += fs::file_size(cs, ec);
      fs::remove(cs, ec);
    }
  }
  return freed;
}

}  // namespace wetdem::study
