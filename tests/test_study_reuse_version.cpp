// `study plan|run --reuse OTHER` and the run version (study/reuse.h): a complete run of OTHER with this
// study's resolved case and seed but another run version is found and named with the version that computed
// it; a run with the same hash (reused as is), an incomplete one, one not to compute and a folder without a
// study are not. Planning only: nothing runs.
#include <gtest/gtest.h>

#include <filesystem>

#include "study/reuse.h"
#include "study/store.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

TEST(StudyReuse, RunsOfAnotherRunVersionAreFoundAndNamed) {
  const std::string dir = study_temp("reuse_version");
  const std::string text = "name = \"tiny\"\nbase = \"" + micro_case() +
                           "\"\nreplicates = 2\n[axes]\n\"liquid.content\" = [\"0 %\", \"5 %\"]\n";
  const auto s = study::parse_study_file(write_text(dir + "/tiny.toml", text));
  const std::vector<study::PlannedRun> runs = study::expand(s);
  ASSERT_EQ(runs.size(), 4u);
  // OTHER: the same runs under another run version's hashes; two of them complete.
  std::vector<study::PlannedRun> old = runs;
  for (study::PlannedRun& r : old) r.hash = study::run_hash(r.resolved, r.seed, "another-run-version");
  const std::string other = dir + "/other";
  study::write_plan(other, s, old);
  const auto complete = [](const std::string& run, const std::string& version) {
    fs::create_directories(run);
    write_text(run + "/summary.json", "{\"code_version\": \"" + version + "\"}");
  };
  for (size_t i : {size_t(0), size_t(3)}) complete(other + "/runs/" + old[i].hash, "0.1.0+abc1234");
  fs::create_directories(other + "/runs/" + old[1].hash);  // begun, not complete: not counted
  // SAME: this version's hashes, run 0 complete (reused by hash, nothing to say).
  const std::string same = dir + "/same";
  study::write_plan(same, s, runs);
  complete(same + "/runs/" + runs[0].hash, "0.1.0+def5678");

  const study::OtherVersionRuns o = study::other_version_runs(other, runs);
  EXPECT_EQ(o.runs, 2u);
  EXPECT_EQ(o.code_versions, std::set<std::string>{"0.1.0+abc1234"});
  const std::string note = study::other_version_note(other, o);
  EXPECT_NE(note.find("2 runs of --reuse " + other), std::string::npos) << note;
  EXPECT_NE(note.find("code 0.1.0+abc1234"), std::string::npos) << note;
  EXPECT_EQ(study::other_version_runs(other, {runs[1], runs[2]}).runs, 0u);  // their twins are not complete
  EXPECT_EQ(study::other_version_runs(other, {runs[3]}).runs, 1u);
  EXPECT_EQ(study::other_version_runs(same, runs).runs, 0u);  // the same hash: reused, not another version
  EXPECT_EQ(study::other_version_runs(dir + "/no-study-here", runs).runs, 0u);
  EXPECT_EQ(study::other_version_note(same, study::other_version_runs(same, runs)), "");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wetdem::test
