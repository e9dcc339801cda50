#include "support/backend.h"

#include <cstdlib>
#include <stdexcept>

#include "reference/reference.h"

namespace wetdem::test {

namespace {

class ReferenceBackend final : public Backend {
 public:
  explicit ReferenceBackend(const SimParams& prm) : sys_(prm) {}
  std::string name() const override { return "reference"; }
  void set_state(const SystemState& s) override { sys_.set_state(s); }
  SystemState state() override { return sys_.state(); }
  void step(uint64_t n) override {
    for (uint64_t i = 0; i < n; ++i) sys_.step();
  }
  EventCounts read_events() override { return sys_.read_events(); }

 private:
  ref::ReferenceSystem sys_;
};

}  // namespace

std::unique_ptr<Backend> make_gpu_backend(const SimParams& prm, size_t n);  // support/gpu_backend.cpp

std::unique_ptr<Backend> make_backend(const std::string& which, const SimParams& prm, size_t n) {
  if (which == "reference") return std::make_unique<ReferenceBackend>(prm);
  if (which == "gpu") return make_gpu_backend(prm, n);
  throw std::invalid_argument("unknown backend " + which);
}

const std::vector<std::string>& backends() {
  // WETDEM_TEST_BACKENDS (comma-separated, e.g. "reference,gpu") overrides the list, to try a backend on
  // every parameterised test before it joins the default list.
  static const std::vector<std::string> all = [] {
    std::vector<std::string> v;
    if (const char* env = std::getenv("WETDEM_TEST_BACKENDS")) {
      std::string s(env);
      for (size_t a = 0; a <= s.size();) {
        size_t b = s.find(',', a);
        if (b == std::string::npos) b = s.size();
        if (b > a) v.push_back(s.substr(a, b - a));
        a = b + 1;
      }
    }
    if (v.empty()) v = {"reference", "gpu"};
    return v;
  }();
  return all;
}

}  // namespace wetdem::test
