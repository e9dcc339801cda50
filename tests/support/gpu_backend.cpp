// The GPU system behind the test Backend interface (lavapipe in CI, validation on).
#include <memory>

#include "support/backend.h"
#include "support/gpu.h"
#include "wetdem/system.h"

namespace wetdem::test {

namespace {

class GpuBackend final : public Backend {
 public:
  GpuBackend(const SimParams& prm, size_t n) : sys_(gpu(), prm, n, options()) {}
  std::string name() const override { return "gpu"; }
  void set_state(const SystemState& s) override { sys_.upload(s); }
  SystemState state() override { return sys_.download(); }
  void step(uint64_t n) override { sys_.step(n); }
  EventCounts read_events() override { return sys_.read_events(); }

 private:
  static SystemOptions options() {
    SystemOptions o;
    o.steps_per_submit = 100;
    return o;
  }
  System sys_;
};

}  // namespace

std::unique_ptr<Backend> make_gpu_backend(const SimParams& prm, size_t n) {
  return std::make_unique<GpuBackend>(prm, n);
}

}  // namespace wetdem::test
