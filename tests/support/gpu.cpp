#include "support/gpu.h"

#include <memory>

namespace wetdem::test {

vk::Context& gpu() {
  static std::unique_ptr<vk::Context> ctx = [] {
    vk::ContextOptions o;
    o.quiet = false;
    return std::make_unique<vk::Context>(o);
  }();
  return *ctx;
}

}  // namespace wetdem::test
