// Shared by the tests of bad diagnosis and twin input (test_diagnose_files.cpp, test_diagnose_twin_file.cpp):
// a scratch folder per test, the micro study case, and the DiagnoseError a call must throw.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "diagnose/driver.h"
#include "diagnose/files.h"

namespace wetdem::test_support {

// A folder of its own under the temporary directory, removed with the test.
struct DiagnoseDir {
  std::filesystem::path p;
  DiagnoseDir()
      : p(std::filesystem::temp_directory_path() /
          std::filesystem::path("wetdem-diag-" + std::to_string(::getpid()) + "-" +
                                ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
  }
  ~DiagnoseDir() { std::filesystem::remove_all(p); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(p / name) << text;
    return (p / name).string();
  }
};

inline const std::string kDiagnoseMicroCase =
    std::string(WETDEM_SOURCE_DIR) + "/assets/studies/micro/micro_case.toml";

// The message of the DiagnoseError f throws; a test failure (and "") when it throws none.
inline std::string expect_diagnose_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const diagnose::DiagnoseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no DiagnoseError";
  return "";
}

// Options for a diagnosis or twin in a test: outputs under `out`, no progress line, no figures.
inline diagnose::DiagnoseOptions quiet_options(const std::string& out) {
  diagnose::DiagnoseOptions o;
  o.out = out;
  o.figures = false;
  o.quiet = true;
  return o;
}

}  // namespace wetdem::test_support
