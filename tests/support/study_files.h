// Helpers for the study tests: temporary folders and files.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace wetdem::test {

inline std::string study_temp(const std::string& name) {
  const auto p =
      std::filesystem::temp_directory_path() / ("wetdem_study_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
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
