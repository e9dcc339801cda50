// The run version's source text (cmake/run_digest.cpp, the tool the build runs): a comment edit, a reflow and
// a string literal split elsewhere give the same text, so stored runs are kept; a changed token, string,
// macro spacing or directive line does not. The tool itself is run, as the build runs it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

class RunDigest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("wetdem_run_digest_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The tool's text for one source file of the given name and content (its "== name" line stripped).
  std::string digest(const std::string& text, const std::string& name = "a.cpp") {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    const fs::path out = dir_ / "out.txt";
    fs::remove(out);
    const std::string cmd =
        std::string(WETDEM_RUN_DIGEST) + " " + dir_.string() + " " + out.string() + " " + name;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(out, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string all = ss.str();
    const std::string head = "== " + name + "\n";
    EXPECT_EQ(all.rfind(head, 0), 0u) << all;
    return all.substr(std::min(all.size(), head.size()));
  }

  fs::path dir_;
};

const char* kRunDigestBase =
    "#include <string>  // why\n"
    "#define SCALE 2.0\n"
    "/* a block\n   comment */\n"
    "double f(double a, double b) {\n"
    "  const char* s = \"one \"\n"
    "                  \"two\";\n"
    "  return SCALE * a - --b;  // the law\n"
    "}\n";

TEST_F(RunDigest, CommentsLayoutAndLiteralSplitsDoNotCount) {
  const std::string base = digest(kRunDigestBase);
  EXPECT_EQ(base,
            "#include <string>\n#define SCALE 2.0\n"
            "double f(double a,double b){const char* s = \"one two\";return SCALE * a - --b;}\n");
  // Reworded comments, the parameters reflowed, the literal split at another place, a comment between tokens.
  EXPECT_EQ(digest("#include <string>\n"
                   "#define SCALE 2.0  // the factor\n"
                   "double f(double a,\n         double b)\n{\n"
                   "  const char* s = \"one\" \" two\";  /* joined */\n"
                   "  return SCALE * a /* x */ - --b;\n}\n"),
            base);
}

TEST_F(RunDigest, EveryTokenAndStringCounts) {
  const std::string base = digest(kRunDigestBase);
  std::string t = kRunDigestBase;
  for (const auto& [from, to] :
       std::initializer_list<std::pair<std::string, std::string>>{
           {"2.0", "2.5"},              // a constant
           {"a - --b", "a-- - b"},      // the same characters, other tokens
           {"\"one \"", "\"one  \""},   // a string's text
           {"<string>", "<vector>"},    // an include
           {"double b)", "float b)"}})  // a type
  {
    std::string v = t;
    const size_t at = v.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    v.replace(at, from.size(), to);
    EXPECT_NE(digest(v), base) << from << " -> " << to;
  }
}

TEST_F(RunDigest, DirectivesKeepTheirLinesAndSpaces) {
  // A space before ( makes an object-like macro; a directive ends at its line.
  EXPECT_NE(digest("#define F (x) x\n"), digest("#define F(x) x\n"));
  EXPECT_NE(digest("#define A 1\nint x = A;\n"), digest("#define A 1 int x = A;\n"));
  // A continued directive is one line either way.
  EXPECT_EQ(digest("#define G(x) \\\n  ((x) + 1)\n"), digest("#define G(x) ((x) + 1)\n"));
}

TEST_F(RunDigest, LiteralsAreCopiedAsTheyAre) {
  // Comment markers and quotes inside literals are text, not comments.
  EXPECT_NE(digest("auto s = \"a // b\";\n"), digest("auto s = \"a \";\n"));
  EXPECT_NE(digest("auto r = R\"(x /* y */ \" z)\";\n"), digest("auto r = R\"(x  \" z)\";\n"));
  EXPECT_NE(digest("char c = '\"'; int n = 1'000;\n"), digest("char c = '\"'; int n = 1000;\n"));
  // A hex escape would run on into the next piece: "\x4" "1" is not "\x41", so the pieces stay apart.
  EXPECT_EQ(digest("auto s = \"\\x4\" \"1\";\n"), "auto s = \"\\x4\" \"1\";\n");
  EXPECT_NE(digest("auto s = \"\\x4\" \"1\";\n"), digest("auto s = \"\\x41\";\n"));
  // A prefixed piece is not joined.
  EXPECT_EQ(digest("auto s = u8\"a\" \"b\";\n"), "auto s = u8\"a\" \"b\";\n");
}

TEST_F(RunDigest, OtherFilesAreHashedAsTheyAre) {
  EXPECT_EQ(digest("# a CMake comment\nset(x 1)\n", "CMakeLists.txt"), "# a CMake comment\nset(x 1)\n\n");
}

}  // namespace
}  // namespace wetdem::test
