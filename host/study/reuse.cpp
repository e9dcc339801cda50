#include "study/reuse.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "app/case/case.h"
#include "study/store.h"

namespace fs = std::filesystem;

namespace wetdem::study {

OtherVersionRuns other_version_runs(const std::string& other, const std::vector<PlannedRun>& todo) {
  OtherVersionRuns out;
  if (todo.empty()) return out;
  StudyIndex ix;
  try {
    ix = read_index(other);
  } catch (const StudyError&) {
    return out;  // no study there: --reuse copies nothing, and there is nothing to say
  }
  std::map<std::string, const PlannedRun*> by_identity;  // run_hash without the version -> planned run
  for (const PlannedRun& r : todo) by_identity[run_hash(r.resolved, r.seed, "")] = &r;
  std::set<const PlannedRun*> found;
  for (const IndexEntry& e : ix.runs) {
    const fs::path run = fs::path(other) / e.run_dir;
    if (run_state(run.string()) != RunState::Complete) continue;
    std::string id;
    try {
      id = run_hash(app::parse_case_file((fs::path(other) / e.case_file).string()), e.seed, "");
    } catch (const std::exception&) {
      continue;  // a case file this code cannot read is not this study's run
    }
    const auto it = by_identity.find(id);
    if (it == by_identity.end() || it->second->hash == e.hash || !found.insert(it->second).second) continue;
    ++out.runs;
    std::ifstream f(run / "summary.json");
    try {
      const nlohmann::json s = nlohmann::json::parse(f);
      out.code_versions.insert(s.value("code_version", std::string("unknown")));
    } catch (const std::exception&) {
      out.code_versions.insert("unknown");
    }
  }
  return out;
}

std::string other_version_note(const std::string& other, const OtherVersionRuns& o) {
  if (o.runs == 0) return "";
  std::string versions;
  for (const std::string& v : o.code_versions) versions += (versions.empty() ? "" : ", ") + v;
  return fmt::format(
      "note: {} run{} of --reuse {} {} this study's case and seed but {} computed by another run version "
      "(code {}): not reused, they run again here. Binaries of that version would reuse them "
      "(a run is reused only when the code that computes it is the same).",
      o.runs, o.runs == 1 ? "" : "s", other, o.runs == 1 ? "has" : "have", o.runs == 1 ? "was" : "were",
      versions);
}

}  // namespace wetdem::study
