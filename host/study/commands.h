// The study commands of the CLI: `wetdem study plan|run|run-one|slurm|collect` and `wetdem calibrate`.
// Registered on the CLI11 app by main.cpp; the logic is in this folder.
#pragma once

#include <memory>

namespace CLI {
class App;
}

namespace wetdem::study {

class Commands {
 public:
  virtual ~Commands() = default;
  // True when one of the study commands was given on the command line.
  virtual bool selected() const = 0;
  // Runs it. Exit codes: 0 done; 2 bad input (nothing run); 1 a run failed or the device failed.
  virtual int execute() = 0;
};

std::unique_ptr<Commands> add_commands(CLI::App& cli);

}  // namespace wetdem::study
