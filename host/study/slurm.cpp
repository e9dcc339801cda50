#include "study/slurm.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "app/output/summary.h"
#include "study/executor.h"
#include "study/store.h"

namespace wetdem::study {

namespace fs = std::filesystem;

std::string array_spec(const std::vector<size_t>& idx) {
  std::string s;
  for (size_t i = 0; i < idx.size();) {
    size_t j = i;
    while (j + 1 < idx.size() && idx[j + 1] == idx[j] + 1) ++j;
    s += (s.empty() ? "" : ",") + (j == i ? std::to_string(idx[i]) : fmt::format("{}-{}", idx[i], idx[j]));
    i = j + 1;
  }
  return s;
}

namespace {
// Single quotes for the shell.
std::string sq(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

SlurmScript write_slurm(const std::string& dir, const SlurmOptions& opt) {
  const StudyIndex ix = read_index(dir);
  const fs::path d = fs::absolute(dir).lexically_normal();
  SlurmScript s;
  for (const IndexEntry& e : ix.runs) {
    const RunState st = run_state((d / e.run_dir).string());
    if (st == RunState::Complete || (st == RunState::Failed && !opt.retry_failed)) continue;
    s.indices.push_back(e.index);
  }
  if (s.indices.empty()) return s;
  // Batches: the ones `study run --batch` steps with one process (and any batch stopped with a checkpoint,
  // whole).
  std::vector<std::vector<size_t>> b = plan_batches(d.string(), s.indices, opt.batch);
  const bool batched =
      opt.batch > 1 || std::any_of(b.begin(), b.end(), [](const auto& v) { return v.size() > 1; });
  if (batched) {
    s.batches = b;
    s.indices.clear();
    for (size_t t = 0; t < b.size(); ++t) s.indices.push_back(t);
  }
  fs::create_directories(d / "slurm" / "logs");
  const std::string exe = opt.exe.empty() ? self_exe() : opt.exe;
  std::string t = "#!/bin/bash\n";
  if (batched) {
    size_t runs = 0;
    for (const auto& v : s.batches) runs += v.size();
    t += fmt::format(
        "# wetdem study {}: one array task per batch of up to {} runs ({} tasks, {} of {} runs), written by "
        "wetdem {}.\n",
        ix.name, opt.batch, s.batches.size(), runs, ix.runs.size(), code_version());
    t += "# Each task steps its runs as one ensemble (README \"Ensembles\"); tasks are independent. A task\n"
         "# stopped by its time limit leaves a checkpoint: submit again and it resumes. Collect when done:\n";
  } else {
    t += fmt::format("# wetdem study {}: one array task per missing run ({} of {}), written by wetdem {}.\n",
                     ix.name, s.indices.size(), ix.runs.size(), code_version());
    t += "# Each task runs one run of DIR/index.json; tasks are independent. Collect when the array is "
         "done:\n";
  }
  t += fmt::format("#   {} study collect {}\n", exe, d.string());
  t += fmt::format("#SBATCH --job-name=wetdem-{}\n", ix.name);
  std::string arr = array_spec(s.indices);
  if (opt.max_parallel > 0) arr += fmt::format("%{}", opt.max_parallel);
  t += fmt::format("#SBATCH --array={}\n", arr);
  t += fmt::format("#SBATCH --output={}/slurm/logs/%A_%a.out\n", d.string());
  t += "#SBATCH --ntasks=1\n";
  if (!opt.partition.empty()) t += fmt::format("#SBATCH --partition={}\n", opt.partition);
  if (!opt.time.empty()) t += fmt::format("#SBATCH --time={}\n", opt.time);
  if (opt.gpus_per_task > 0) t += fmt::format("#SBATCH --gpus-per-task={}\n", opt.gpus_per_task);
  t += "set -eu\n";
  if (batched) {
    t += "BATCHES=(";
    for (const auto& v : s.batches) {
      std::string idx;
      for (size_t i : v) idx += (idx.empty() ? "" : ",") + std::to_string(i);
      t += " " + idx;
    }
    t += " )\n";
    t += fmt::format("exec {} study run-batch {} --index \"${{BATCHES[$SLURM_ARRAY_TASK_ID]}}\" --quiet{}\n",
                     sq(exe), sq(d.string()), opt.device.empty() ? "" : " --device " + sq(opt.device));
  } else {
    t += fmt::format("exec {} study run-one {} --index \"$SLURM_ARRAY_TASK_ID\" --quiet{}\n", sq(exe),
                     sq(d.string()), opt.device.empty() ? "" : " --device " + sq(opt.device));
  }
  s.path = (d / "slurm" / "study.sbatch").string();
  app::write_file_atomic(s.path, t);
  fs::permissions(s.path, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  s.sbatch_line = "sbatch " + sq(s.path);
  return s;
}

std::string submit_slurm(const SlurmScript& s) {
  const std::string cmd = "sbatch --parsable " + sq(s.path) + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) throw std::runtime_error("cannot run sbatch");
  std::string out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  const int rc = ::pclose(p);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  if (rc != 0) throw std::runtime_error("sbatch failed: " + out);
  return out.substr(0, out.find(';'));
}

}  // namespace wetdem::study
