#include "study/store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/output/summary.h"
#include "app/run/ensemble.h"

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

nlohmann::json values_json(const std::vector<AxisValue>& vs) {
  nlohmann::json j = nlohmann::json::array();
  for (const AxisValue& a : vs)
    j.push_back({{"key", a.key},
                 {"written", a.written},
                 {"toml", a.toml},
                 {"si", std::isfinite(a.si) ? nlohmann::json(a.si) : nlohmann::json(nullptr)}});
  return j;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

nlohmann::json index_to_json(const StudyIndex& ix) {
  nlohmann::json j;
  j["name"] = ix.name;
  j["study_file"] = ix.study_file;
  j["base"] = ix.base;
  j["code_version"] = ix.code_version;
  j["axis_keys"] = ix.axis_keys;
  j["observations"] = {{"file", ix.observations}, {"fit", ix.fit}};
  j["points"] = ix.points;
  j["runs"] = nlohmann::json::array();
  for (const IndexEntry& e : ix.runs)
    j["runs"].push_back({{"index", e.index},
                         {"point", e.point},
                         {"seed", e.seed},
                         {"hash", e.hash},
                         {"values", values_json(e.values)},
                         {"run_dir", e.run_dir},
                         {"case_file", e.case_file}});
  return j;
}

StudyIndex write_plan(const std::string& dir, const StudySpec& s, const std::vector<PlannedRun>& runs) {
  const fs::path d(dir);
  fs::create_directories(d / "cases");
  fs::create_directories(d / "runs");
  fs::create_directories(d / "logs");
  app::write_file_atomic((d / "study.toml").string(),
                         "# copy of " + s.path + " (base = " + s.base + ")\n" + slurp(s.path));
  StudyIndex ix;
  ix.name = s.name;
  ix.study_file = s.path;
  ix.base = s.base;
  ix.code_version = code_version();
  ix.fit = s.observations.fit;
  ix.observations = s.observations.file;
  ix.points = s.points.size();
  for (const auto& p : s.points)
    for (const AxisValue& a : p)
      if (std::find(ix.axis_keys.begin(), ix.axis_keys.end(), a.key) == ix.axis_keys.end())
        ix.axis_keys.push_back(a.key);
  for (const PlannedRun& r : runs) {
    IndexEntry e;
    e.index = r.index;
    e.point = r.point;
    e.seed = r.seed;
    e.hash = r.hash;
    e.values = r.values;
    e.run_dir = "runs/" + r.hash;
    e.case_file = "cases/" + r.hash + ".toml";
    const fs::path cf = d / e.case_file;
    if (!fs::exists(cf))
      app::write_file_atomic(
          cf.string(), fmt::format("# run {} of study {}: resolved case (SI), hash {}\n{}", r.index, s.name,
                                   r.hash, app::case_to_toml(r.resolved)));
    ix.runs.push_back(e);
  }
  app::write_file_atomic((d / "index.json").string(), index_to_json(ix).dump(1) + "\n");
  return ix;
}

StudyIndex read_index(const std::string& dir) {
  const fs::path p = fs::path(dir) / "index.json";
  if (!fs::exists(p))
    throw StudyError(dir + ": no index.json (not a study directory; run `wetdem study run`)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(slurp(p));
    StudyIndex ix;
    ix.name = j.at("name");
    ix.study_file = j.at("study_file");
    ix.base = j.at("base");
    ix.code_version = j.at("code_version");
    ix.axis_keys = j.at("axis_keys").get<std::vector<std::string>>();
    ix.observations = j.at("observations").at("file");
    ix.fit = j.at("observations").at("fit").get<std::vector<std::string>>();
    ix.points = j.at("points");
    for (const auto& r : j.at("runs")) {
      IndexEntry e;
      e.index = r.at("index");
      e.point = r.at("point");
      e.seed = r.at("seed");
      e.hash = r.at("hash");
      e.run_dir = r.at("run_dir");
      e.case_file = r.at("case_file");
      for (const auto& v : r.at("values")) {
        AxisValue a;
        a.key = v.at("key");
        a.written = v.at("written");
        a.toml = v.at("toml");
        a.si = v.at("si").is_null() ? std::nan("") : v.at("si").get<double>();
        e.values.push_back(a);
      }
      ix.runs.push_back(e);
    }
    return ix;
  } catch (const nlohmann::json::exception& e) {
    throw StudyError(p.string() + ": malformed: " + e.what());
  }
}

const char* state_name(RunState s) {
  switch (s) {
    case RunState::Missing:
      return "missing";
    case RunState::Partial:
      return "partial";
    case RunState::Resumable:
      return "resumable";
    case RunState::Interrupted:
      return "interrupted";
    case RunState::Failed:
      return "failed";
    case RunState::Complete:
      return "complete";
  }
  return "?";
}

RunState run_state(const std::string& run_dir, std::string* reason) {
  const fs::path d(run_dir);
  if (fs::exists(d / "summary.json")) return RunState::Complete;
  if (!fs::exists(d)) return RunState::Missing;
  // Its own checkpoint, or that of the batch it was stepped in (app/run/ensemble.h).
  const bool ckpt = fs::exists(d / "checkpoint") || fs::exists(d / "checkpoint.old") ||
                    !app::ensemble_members(run_dir).empty();
  if (fs::exists(d / "FAILED.txt")) {
    std::string why = slurp(d / "FAILED.txt");
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
    if (reason) *reason = why;
    if (why.rfind("interrupted", 0) == 0) return ckpt ? RunState::Interrupted : RunState::Partial;
    return RunState::Failed;
  }
  return ckpt ? RunState::Resumable : RunState::Partial;
}

StoreLock::StoreLock(const std::string& dir) {
  fs::create_directories(dir);
  const std::string path = (fs::path(dir) / ".lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw StudyError(fmt::format("{}: cannot open the store's lock file", path));
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  std::fprintf(stderr, "waiting for another process using the run store %s\n", dir.c_str());
  while (::flock(fd_, LOCK_EX) != 0)
    if (errno != EINTR) throw StudyError(fmt::format("{}: cannot lock the store", path));
}

StoreLock::~StoreLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

}  // namespace wetdem::study
