// `wetdem study prune` (study/prune.h): the census of a store groups its complete runs by the run version
// their summary records, and prune removes those of another version (and their case files), keeping this
// version's runs and every run without a summary (partial, resumable, failed). A folder that is not a store
// is an error that says so.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "study/prune.h"
#include "study/study_file.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

// A run folder DIR/runs/HASH with a case file; `summary` "" writes none (a partial run).
void fake_run(const std::string& dir, const std::string& hash, const std::string& summary) {
  fs::create_directories(dir + "/runs/" + hash);
  fs::create_directories(dir + "/cases");
  write_text(dir + "/cases/" + hash + ".toml", "name = \"x\"\n");
  write_text(dir + "/runs/" + hash + "/timeseries.csv", std::string(5000, 'x'));
  if (!summary.empty()) write_text(dir + "/runs/" + hash + "/summary.json", summary);
}

TEST(StudyPrune, RemovesOnlyCompleteRunsOfOtherRunVersions) {
  const std::string dir = study_temp("prune");
  const std::string now = "0.1.0+run-aaaaaaaaaaaa";
  fake_run(dir, "0000000000000001", "{\"run_version\": \"" + now + "\"}");
  fake_run(dir, "0000000000000002", "{\"run_version\": \"0.1.0+run-bbbbbbbbbbbb\"}");
  fake_run(dir, "0000000000000003", "{\"code_version\": \"0.1.0+abc1234\"}");  // before run_version
  fake_run(dir, "0000000000000004", "");                                       // partial: kept
  fake_run(dir, "0000000000000005", "{\"run_version\": \"0.1.0+run-bbbbbbbbbbbb\"}");

  const study::StoreCensus c = study::take_census(dir, now);
  EXPECT_EQ(c.current.runs, 1u);
  ASSERT_EQ(c.other.size(), 1u);
  EXPECT_EQ(c.other.at("0.1.0+run-bbbbbbbbbbbb").runs, 2u);
  EXPECT_EQ(c.unrecorded.runs, 1u);
  EXPECT_EQ(c.incomplete.runs, 1u);
  EXPECT_GE(c.current.bytes, 5000u);
  EXPECT_EQ(c.removable,
            (std::vector<std::string>{"0000000000000002", "0000000000000003", "0000000000000005"}));
  const std::string text = study::describe_census(c);
  EXPECT_NE(text.find("this binary's run version " + now), std::string::npos) << text;
  EXPECT_NE(text.find("run version 0.1.0+run-bbbbbbbbbbbb (not reused here)"), std::string::npos) << text;
  EXPECT_NE(text.find("no run version recorded"), std::string::npos) << text;

  EXPECT_GE(study::prune_runs(dir, c), 3u * 5000u);
  for (const char* h : {"0000000000000001", "0000000000000004"}) {
    EXPECT_TRUE(fs::exists(dir + "/runs/" + h)) << h;
    EXPECT_TRUE(fs::exists(dir + "/cases/" + h + ".toml")) << h;
  }
  for (const char* h : {"0000000000000002", "0000000000000003", "0000000000000005"}) {
    EXPECT_FALSE(fs::exists(dir + "/runs/" + h)) << h;
    EXPECT_FALSE(fs::exists(dir + "/cases/" + h + ".toml")) << h;
  }
  const study::StoreCensus after = study::take_census(dir, now);
  EXPECT_TRUE(after.removable.empty());
  EXPECT_EQ(after.current.runs + after.incomplete.runs, 2u);
  fs::remove_all(dir);
}

TEST(StudyPrune, AFolderWithoutRunsIsNotAStore) {
  const std::string dir = study_temp("prune_not_a_store");
  fs::create_directories(dir);
  try {
    study::take_census(dir);
    FAIL() << "no error";
  } catch (const study::StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("not a run store"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wetdem::test
