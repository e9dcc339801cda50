#include "study/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <thread>

#include "vk/context.h"

namespace wetdem::study {

size_t auto_jobs(bool cpu_device, unsigned cores) {
  if (!cpu_device) return 1;
  return std::min<size_t>(kCpuAutoJobsMax, std::max(1u, cores));
}

const DeviceKind::Known& DeviceKind::learn() {
  if (!known_) {
    vk::ContextOptions co;
    co.device = device_;
    co.quiet = true;
    const vk::Context ctx(co);  // only to learn which device the runs will get; no pipeline is built
    known_ = Known{ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU, ctx.info().name};
  }
  return *known_;
}

size_t resolve_jobs(size_t asked, const std::string& device, std::string* why) {
  DeviceKind kind(device);
  return resolve_jobs(asked, kind, why);
}

size_t resolve_jobs(size_t asked, DeviceKind& device, std::string* why) {
  if (asked > 0) {
    if (why) *why = fmt::format("{} run{} at a time (--jobs)", asked, asked == 1 ? "" : "s");
    return asked;
  }
  const bool cpu = device.cpu();
  const unsigned cores = std::thread::hardware_concurrency();
  const size_t k = auto_jobs(cpu, cores);
  if (why)
    *why = cpu ? fmt::format(
                     "{} run{} at a time (auto: one per CPU core, {} core{}, up to {}; --jobs N to choose)",
                     k, k == 1 ? "" : "s", cores, cores == 1 ? "" : "s", kCpuAutoJobsMax)
               : fmt::format(
                     "1 run at a time (auto: {} is a GPU, where the batch runs them together; --jobs N "
                     "to choose)",
                     device.name());
  return k;
}

}  // namespace wetdem::study
