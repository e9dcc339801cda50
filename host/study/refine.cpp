#include "study/refine.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "app/output/summary.h"
#include "study/collect.h"
#include "study/executor.h"

namespace wetdem::study {

namespace fs = std::filesystem;

std::string refine(const std::string& dir, const RefineOptions& opt) {
  CalibrateOptions co = opt.calibrate;
  co.propose = opt.k;
  const Calibration cal = calibrate(dir, co);
  if (cal.proposals.empty()) return "refine: the emulator proposes no new value (the grid is dense enough)\n";
  const StudyIndex ix = read_index(dir);
  const StudySpec old = parse_study_file(ix.study_file);
  toml::table root = toml::parse_file(ix.study_file);
  root.insert_or_assign("base", old.base);
  if (auto* o = root["observations"].as_table()) o->insert_or_assign("file", old.observations.file);
  if (!root.contains("points")) root.insert("points", toml::array{});
  toml::array& pts = *root["points"].as_array();
  // One new point per proposal and per distinct observed condition.
  std::set<std::vector<std::pair<std::string, std::string>>> conds;
  for (const Observation& o : cal.obs) conds.insert(o.conditions);
  std::ostringstream what;
  for (const auto& p : cal.proposals) {
    what << "refine: adding";
    for (size_t k = 0; k < cal.fit.size(); ++k) what << ' ' << cal.fit[k] << fmt::format(" = {:.4g}", p[k]);
    what << fmt::format(" at {} conditions\n", conds.size());
    for (const auto& c : conds) {
      toml::table t;
      for (const auto& [k, w] : c) t.insert(k, w);
      // Four significant digits: the emulator's grid is no finer, and the study file stays readable.
      for (size_t k = 0; k < cal.fit.size(); ++k)
        t.insert(cal.fit[k], std::stod(fmt::format("{:.4g}", p[k])));
      pts.push_back(std::move(t));
    }
  }
  const fs::path rd = fs::path(dir) / "refine";
  fs::create_directories(rd);
  int n = 1;
  while (fs::exists(rd / fmt::format("round-{}.toml", n))) ++n;
  const fs::path file = rd / fmt::format("round-{}.toml", n);
  std::ostringstream os;
  os << "# refinement round " << n << " of " << ix.study_file << ", written by wetdem calibrate --refine\n"
     << root << '\n';
  app::write_file_atomic(file.string(), os.str());
  const StudySpec s = parse_study_file(file.string());
  const StoreLock lock(dir);
  write_plan(dir, s, expand(s));
  ExecOptions eo;
  eo.jobs = opt.jobs;
  eo.device = opt.device;
  eo.exe = opt.exe.empty() ? self_exe() : opt.exe;
  const ExecReport r = run_study(dir, eo);
  what << fmt::format("refine: round {} ({}): {} runs computed, {} failed; study now {} runs\n", n,
                      file.string(), r.completed, r.failed, r.total);
  return what.str();
}

}  // namespace wetdem::study
