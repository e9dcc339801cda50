#include "diagnose/auto_batch.h"

#include <fmt/format.h>

namespace wetdem::diagnose {

size_t auto_batch(study::DeviceKind& device, std::string* why) {
  const bool cpu = device.cpu();
  const size_t k = cpu ? 1 : kGpuAutoBatch;
  if (why)
    *why = fmt::format("{} run{} per process (auto: {} is a {}; --batch K to choose)", k, k == 1 ? "" : "s",
                       device.name(), cpu ? "CPU device, where ensembles do not pay" : "GPU");
  return k;
}

size_t resolve_batch(size_t asked, const std::string& device, std::string* why) {
  study::DeviceKind kind(device);
  return resolve_batch(asked, kind, why);
}

size_t resolve_batch(size_t asked, study::DeviceKind& device, std::string* why) {
  if (asked > 0) {
    if (why) *why = fmt::format("{} run{} per process (--batch)", asked, asked == 1 ? "" : "s");
    return asked;
  }
  return auto_batch(device, why);
}

}  // namespace wetdem::diagnose
