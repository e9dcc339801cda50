// A twin file's conditions: explicit points, each validated before any truth run, and `wetdem twin --check`,
// which validates them and runs nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "diagnose/driver.h"
#include "diagnose/files.h"
#include "diagnose/twin.h"
#include "support/diagnose_input.h"

namespace fs = std::filesystem;
using namespace wetdem::diagnose;
using wetdem::test_support::DiagnoseDir;
using wetdem::test_support::expect_diagnose_error;
using wetdem::test_support::kDiagnoseMicroCase;

// A twin's conditions as explicit points (a laboratory's table is rarely a full product).
TEST(DiagnoseTwinFile, TwinPointsAreExplicitConditions) {
  DiagnoseDir d;
  const std::string head = "case = \"" + kDiagnoseMicroCase + "\"\nseeds = [7]\n[noise]\naor_deg_mean = 1\n";
  const TwinSpec t = parse_twin_file(
      d.write("t.toml", head + "[[points]]\n\"liquid.content\" = \"0 %\"\n\"drum.rpm\" = 30\n"
                               "[[points]]\n\"liquid.content\" = \"10 %\"\n\"drum.rpm\" = 60\n"));
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_NE(std::find(t.points[1].begin(), t.points[1].end(),
                      std::pair<std::string, std::string>{"liquid.content", "\"10 %\""}),
            t.points[1].end());
  EXPECT_TRUE(t.condition_keys.empty());
  const auto err = [&](const std::string& body) {
    return expect_diagnose_error([&] { parse_twin_file(d.write("t.toml", head + body)); });
  };
  EXPECT_NE(err("[[points]]\n\"liquid.content\" = \"0 %\"\n[[points]]\n\"drum.rpm\" = 60\n")
                .find("[[points]] #2: every point needs the same condition keys"),
            std::string::npos);
  EXPECT_NE(err("[[points]]\n\"liquid.content\" = \"0 %\"\n").find("at least two"), std::string::npos);
  // A truth that sets a key the conditions vary would replace every condition's value.
  EXPECT_NE(
      err("[truth]\n\"liquid.content\" = \"5 %\"\n[conditions]\n\"liquid.content\" = [\"0 %\", \"10 %\"]\n")
          .find("[truth] liquid.content: the conditions vary this key"),
      std::string::npos);
  EXPECT_NE(err("[set]\n\"drum.rpm\" = 45\n[[points]]\n\"drum.rpm\" = 30\n[[points]]\n\"drum.rpm\" = 60\n")
                .find("[set] drum.rpm: the conditions vary this key"),
            std::string::npos);
  EXPECT_NE(err("[conditions]\n\"liquid.content\" = [\"0 %\", \"5 %\"]\n[[points]]\n\"drum.rpm\" = 60\n")
                .find("give one of them"),
            std::string::npos);
  // A point the case cannot express is named as written, before any truth run.
  DiagnoseOptions o;
  o.out = (d.p / "out").string();
  o.quiet = true;
  const std::string bad = expect_diagnose_error([&] {
    run_twin(parse_twin_file(d.write("t.toml", head + "[[points]]\n\"liquid.content\" = \"0 %\"\n[[points]]\n"
                                                      "\"liquid.content\" = \"120 %\"\n")),
             o);
  });
  EXPECT_NE(bad.find("t.toml: the condition liquid.content=120 % (the truth's run there): liquid.content: "
                     "must be in [0, 1]"),
            std::string::npos)
      << bad;
  // A condition listed twice would give the table two independent noisy values of one cell.
  const std::string dup = expect_diagnose_error([&] {
    run_twin(parse_twin_file(d.write("t.toml", head + "[conditions]\n\"liquid.content\" = [\"0 %\", \"5 %\", "
                                                      "0.05]\n")),
             o);
  });
  EXPECT_NE(dup.find("the conditions liquid.content=5 % and liquid.content=0.05 are the same condition"),
            std::string::npos)
      << dup;
  EXPECT_FALSE(fs::exists(d.p / "out" / "store" / "runs")) << "nothing may run on bad input";
}

TEST(DiagnoseTwinFile, TwinCheckValidatesEveryConditionAndRunsNothing) {
  DiagnoseDir d;
  const std::string head =
      "case = \"" + kDiagnoseMicroCase + "\"\nseeds = [7, 8]\n[noise]\naor_deg_mean = 1\n";
  DiagnoseOptions o;
  o.quiet = true;
  o.check = true;  // wetdem twin --check
  o.store = (d.p / "store").string();
  const nlohmann::json j =
      run_twin(parse_twin_file(d.write(
                   "t.toml", head + "[conditions]\n\"liquid.content\" = [\"0 %\", \"5 %\", \"10 %\"]\n")),
               o);
  EXPECT_TRUE(j.value("checked", false));
  EXPECT_EQ(j.value("conditions", 0), 3);
  EXPECT_EQ(j.value("runs", 0), 6);
  EXPECT_FALSE(fs::exists(d.p / "store")) << "a check writes nothing";
  // A slice too thin for the neighbour reach at one condition: refused naming the condition, with the bound
  // the slice must pass (twice the reach) printed as the number it is compared with.
  const std::string thin = expect_diagnose_error([&] {
    run_twin(parse_twin_file(d.write("t.toml", head + "[conditions]\n\"drum.slice_thickness\" = [\"18 mm\", "
                                                      "\"15 mm\"]\n")),
             o);
  });
  EXPECT_NE(
      thin.find("the condition drum.slice_thickness=15 mm (the truth's run there): drum.slice_thickness: "
                "must exceed twice the neighbour reach"),
      std::string::npos)
      << thin;
  const size_t at = thin.find("skin) = 2 x ");
  ASSERT_NE(at, std::string::npos) << thin;
  double reach = 0, bound = 0, got = 0;
  ASSERT_EQ(std::sscanf(thin.c_str() + at, "skin) = 2 x %lf m = %lf m", &reach, &bound), 2) << thin;
  const size_t g = thin.find("got ");
  ASSERT_NE(g, std::string::npos) << thin;
  ASSERT_EQ(std::sscanf(thin.c_str() + g, "got %lf m", &got), 1) << thin;
  EXPECT_NEAR(bound, 2.0 * reach, 1e-3 * bound);
  EXPECT_DOUBLE_EQ(got, 0.015);
  EXPECT_GT(bound, got);
  EXPECT_LT(bound, 0.018);  // the case's own slice passes
  // The same condition written twice is found from the SI values the check resolves.
  const std::string dup = expect_diagnose_error([&] {
    run_twin(
        parse_twin_file(d.write("t.toml", head + "[conditions]\n\"liquid.content\" = [\"5 %\", 0.05]\n")), o);
  });
  EXPECT_NE(dup.find("are the same condition"), std::string::npos) << dup;
  EXPECT_FALSE(fs::exists(d.p / "store"));
}
