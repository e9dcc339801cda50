// Helpers for the study tests: temporary folders and files.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace wetdem::test {

// The folders study_temp made in this process, removed when it exits (each test runs as its own process), so
// a passing suite leaves nothing in the temporary directory. WETDEM_KEEP_TEST_DIRS=1 keeps them for a
// post-mortem.
struct StudyTempFolders {
  std::vector<std::filesystem::path> made;
  ~StudyTempFolders() {
    if (std::getenv("WETDEM_KEEP_TEST_DIRS") != nullptr) return;
    std::error_code ec;  // best effort: a folder already gone is fine
    for (const auto& p : made) std::filesystem::remove_all(p, ec);
  }
};

inline std::string study_temp(const std::string& name) {
  static StudyTempFolders folders;
  const auto p =
      std::filesystem::temp_directory_path() / ("wetdem_study_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  folders.made.push_back(p);
  return p.string();
}

inline std::string write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

// The micro case shipped with the micro study.
inline std::string micro_case() {
  return std::string(WETDEM_SOURCE_DIR) + "/assets/studies/micro/micro_case.toml";
}

}  // namespace wetdem::test
