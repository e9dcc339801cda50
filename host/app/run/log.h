// The run log: run.log in the run folder and (unless quiet) stdout. Lines logged before the folder exists are
// kept and written once it does, so the log of a run starts with its set-up.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace wetdem::app {

class RunLog {
 public:
  explicit RunLog(bool quiet) : quiet_(quiet) {}
  void open(const std::filesystem::path& file) {
    out_.open(file, std::ios::app);
    for (const std::string& l : pending_) out_ << l << '\n';
    pending_.clear();
    out_.flush();
  }
  void operator()(const std::string& line) {
    if (!quiet_) std::printf("%s\n", line.c_str()), std::fflush(stdout);
    if (out_.is_open())
      out_ << line << '\n', out_.flush();
    else
      pending_.push_back(line);
  }

 private:
  bool quiet_;
  std::ofstream out_;
  std::vector<std::string> pending_;
};

}  // namespace wetdem::app
