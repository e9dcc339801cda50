// One test body, every backend: tests written against Backend run on the CPU reference and on the GPU
// system (lavapipe in CI). Add a backend to kBackends once it implements the whole step.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "wetdem/observables.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::test {

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual void set_state(const SystemState& s) = 0;
  virtual SystemState state() = 0;  // canonical
  virtual void step(uint64_t n) = 0;
  virtual EventCounts read_events() = 0;
};

// which: "reference" or "gpu". n: number of particles the state will hold.
std::unique_ptr<Backend> make_backend(const std::string& which, const SimParams& prm, size_t n);

// The backends every parameterised test runs on.
const std::vector<std::string>& backends();

}  // namespace wetdem::test
