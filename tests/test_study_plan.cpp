// Study files: expansion of [axes] x replicates and [[points]], run hashes, validation before any run.
#include <gtest/gtest.h>

#include <set>

#include "study/study_file.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

using study::StudyError;

std::string study_text(const std::string& axes, const std::string& extra = "") {
  return "name = \"t\"\nbase = \"" + micro_case() + "\"\nreplicates = 2\n" + extra + "[axes]\n" + axes;
}

std::vector<study::PlannedRun> plan(const std::string& dir, const std::string& text) {
  return study::expand(study::parse_study_file(write_text(dir + "/s.toml", text)));
}

TEST(StudyPlan, GridTimesReplicatesInFileOrder) {
  const std::string d = study_temp("grid");
  const auto runs = plan(d, study_text("\"liquid.v_max\" = [\"1 %\", \"4 %\"]\n"
                                       "\"liquid.content\" = [\"0 %\", \"5 %\", \"10 %\"]\n"));
  ASSERT_EQ(runs.size(), 12u);  // 2 x 3 points x 2 seeds
  // The first axis varies slowest, the seeds fastest.
  EXPECT_EQ(runs[0].values[0].key, "liquid.v_max");
  EXPECT_EQ(runs[0].values[0].written, "1 %");
  EXPECT_EQ(runs[0].values[1].written, "0 %");
  EXPECT_EQ(runs[1].seed, 2u);
  EXPECT_EQ(runs[2].values[1].written, "5 %");
  EXPECT_EQ(runs[6].values[0].written, "4 %");
  EXPECT_EQ(runs[11].point, 5u);
  EXPECT_DOUBLE_EQ(runs[3].values[1].si, 0.05);
  EXPECT_DOUBLE_EQ(runs[3].values[0].si, 0.01);
  EXPECT_DOUBLE_EQ(runs[3].resolved.liquid.content, 0.05);
  EXPECT_EQ(runs[3].resolved.run.seed, 2u);
  std::set<std::string> h;
  for (const auto& r : runs) h.insert(r.hash);
  EXPECT_EQ(h.size(), runs.size());
}

TEST(StudyPlan, HashIgnoresAxisOrderAndSpellingButNotValues) {
  const std::string d = study_temp("hash");
  const auto a =
      plan(d, study_text("\"liquid.v_max\" = [\"1 %\", \"4 %\"]\n\"liquid.content\" = [\"5 %\"]\n"));
  const auto b = plan(d, study_text("\"liquid.content\" = [0.05]\n\"liquid.v_max\" = [\"4 %\", 0.01]\n"));
  std::set<std::string> ha, hb;
  for (const auto& r : a) ha.insert(r.hash);
  for (const auto& r : b) hb.insert(r.hash);
  EXPECT_EQ(ha, hb);
  // One changed key of the resolved case changes every hash.
  const auto c = plan(d, study_text("\"liquid.v_max\" = [\"1 %\", \"4 %\"]\n\"liquid.content\" = [\"5 %\"]\n",
                                    "[set]\n\"drum.rpm\" = 31\n"));
  for (const auto& r : c) EXPECT_EQ(ha.count(r.hash), 0u);
  // So does the seed, and the code version.
  EXPECT_NE(study::run_hash(a[0].resolved, 1), study::run_hash(a[0].resolved, 2));
  EXPECT_NE(study::run_hash(a[0].resolved, 1, "0.1+aaaa"), study::run_hash(a[0].resolved, 1, "0.1+bbbb"));
}

TEST(StudyPlan, PointsAndSeeds) {
  const std::string d = study_temp("points");
  const std::string text = "base = \"" + micro_case() +
                           "\"\nseeds = [4, 9]\n[[points]]\n\"liquid.content\" = \"2 %\"\n"
                           "[[points]]\nliquid.content = \"3 %\"\nliquid.v_max = \"2 %\"\n";
  const auto runs = plan(d, text);
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[1].seed, 9u);
  ASSERT_EQ(runs[2].values.size(), 2u);
  EXPECT_DOUBLE_EQ(runs[2].resolved.liquid.v_max, 0.02);
}

TEST(StudyPlan, BadOverridesNameTheKeyAndTheFile) {
  const std::string d = study_temp("bad");
  try {
    plan(d, study_text("\"liquid.content\" = [\"5 %\", \"-3 %\"]\n"));
    FAIL() << "accepted a negative liquid content";
  } catch (const StudyError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("s.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("liquid.content"), std::string::npos) << m;
    EXPECT_NE(m.find("point 1"), std::string::npos) << m;
  }
  try {
    plan(d, study_text("\"liquid.content\" = [\"5 %\"]\n", "[set]\n\"drum.no_such_key\" = 1\n"));
    FAIL() << "accepted an unknown [set] key";
  } catch (const StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("drum.no_such_key"), std::string::npos) << e.what();
  }
  EXPECT_THROW(plan(d, study_text("\"liquid.content\" = []\n")), StudyError);
  EXPECT_THROW(plan(d, "base = \"nowhere.toml\"\n"), StudyError);
  EXPECT_THROW(plan(d, study_text("\"liquid.content\" = [\"5 %\"]\n", "colour = 1\n")), StudyError);
}

}  // namespace
}  // namespace wetdem::test
