// `wetdem diagnose` and `wetdem twin` on the CLI (registered by main.cpp; the logic is in this folder).
#pragma once

#include <memory>

namespace CLI {
class App;
}

namespace wetdem::diagnose {

class Commands {
 public:
  virtual ~Commands() = default;
  virtual bool selected() const = 0;
  // Exit codes: 0 done; 2 bad input (nothing run); 1 a run or the device failed.
  virtual int execute() = 0;
};

std::unique_ptr<Commands> add_commands(CLI::App& cli);

}  // namespace wetdem::diagnose
