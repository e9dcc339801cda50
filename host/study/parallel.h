// How many runs a study, twin or diagnosis starts at a time when the user does not say (`--jobs`), by device.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

namespace wetdem::study {

// The default of `--jobs` (0 = auto) for `study run`, `study calibrate --refine`, `diagnose` and `twin`:
// processes at a time. On a CPU device one per
// core, up to kCpuAutoJobsMax: lavapipe spreads each dispatch over every core, but a small drum's passes
// leave them idle between dispatches, and two flowing-model runs at once on 2 cores gave 1.34x one run alone,
// their four threads on two cores costing <= 3 % (docs/benchmark.md, "Lavapipe's threads and --jobs 2"). On a
// GPU 1: the batch (an ensemble per process) does that work. Like the batch it never changes a run, only the
// wall time. `cores`: the machine's (std::thread::hardware_concurrency; 0 when unknown counts as 1).
inline constexpr size_t kCpuAutoJobsMax = 8;
size_t auto_jobs(bool cpu_device, unsigned cores);

// Whether the runs' device is a CPU (lavapipe) and its name: what the defaults of `--jobs` and `--batch`
// (diagnose/auto_batch.h) both depend on. Learnt once, on first use, from a Vulkan context that builds no
// pipeline (tens of ms), so a command that resolves both opens one context, not two.
class DeviceKind {
 public:
  explicit DeviceKind(std::string device) : device_(std::move(device)) {}
  bool cpu() { return learn().cpu; }
  const std::string& name() { return learn().name; }

 private:
  struct Known {
    bool cpu = true;
    std::string name;
  };
  const Known& learn();  // throws std::runtime_error (from the Vulkan context) when no such device exists
  std::string device_;   // as --device: empty = $WETDEM_DEVICE or the best device
  std::optional<Known> known_;
};

// The jobs the user asked for, or auto_jobs's for `device` and this machine when `asked` is 0; `why` gets a
// line for the log. Pure for asked > 0; else throws std::runtime_error (from the Vulkan context) when no such
// device exists.
size_t resolve_jobs(size_t asked, DeviceKind& device, std::string* why = nullptr);
size_t resolve_jobs(size_t asked, const std::string& device, std::string* why = nullptr);

}  // namespace wetdem::study
