#include "diagnose/auto_batch.h"

#include <fmt/format.h>

#include "vk/context.h"

namespace wetdem::diagnose {

size_t auto_batch(const std::string& device, std::string* why) {
  vk::ContextOptions co;
  co.device = device;
  co.quiet = true;
  const vk::Context ctx(co);  // only to learn which device the runs will get; no pipeline is built
  const bool cpu = ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  const size_t k = cpu ? 1 : kGpuAutoBatch;
  if (why)
    *why = fmt::format("{} run{} per process (auto: {} is a {}; --batch K to choose)", k, k == 1 ? "" : "s",
                       ctx.info().name, cpu ? "CPU device, where ensembles do not pay" : "GPU");
  return k;
}

size_t resolve_batch(size_t asked, const std::string& device, std::string* why) {
  if (asked > 0) {
    if (why) *why = fmt::format("{} run{} per process (--batch)", asked, asked == 1 ? "" : "s");
    return asked;
  }
  return auto_batch(device, why);
}

}  // namespace wetdem::diagnose
