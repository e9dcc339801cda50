#ifdef WETDEM_HAVE_APP

#include "support/small_run.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "support/gpu.h"
#include "support/small_case.h"

namespace wetdem::test {

SmallRun run_small(const std::string& tag, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("wetdem_test_small_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "small.toml") << kSmall;
  app::RunOptions o;
  o.case_path = (dir / "small.toml").string();
  o.out_dir = (dir / "run").string();
  o.overrides = {"output.checkpoint_interval=0"};
  o.overrides.insert(o.overrides.end(), overrides.begin(), overrides.end());
  o.quiet = true;
  o.context = &gpu();
  SmallRun out;
  o.on_sample = [&](const app::Sample& s) { out.samples.push_back(s); };
  out.result = app::run_case(o);
  EXPECT_TRUE(out.result.completed) << tag;
  fs::remove_all(dir);
  return out;
}

}  // namespace wetdem::test

#endif
