// The defaults of `diagnose --batch`, `twin --batch` and their `--jobs` (0 = auto). The batch: how many runs
// of a stage one process steps together as an ensemble (docs/ensembles.md). Batching never changes a run
// (each is bitwise what it is alone), only the wall time, and the two kinds of device answer in opposite
// ways. On a GPU a small drum is bound by ~100 us of dispatches and round trips per step, whatever its size:
// 8 micro drums (410 particles) in one ensemble ran at 6.9x one run on the H100 (docs/ensembles.md, "Speed").
// On lavapipe the CPU cores are already busy with one drum and the runs of a batch share one rebuild
// schedule: 4 flowing-model runs (dry and 5 % wet) took 122 s as one batch against 103 s one by one (0.85x;
// 27 Nov 2026).
#pragma once

#include <cstddef>
#include <string>

namespace wetdem::diagnose {

inline constexpr size_t kGpuAutoBatch = 16;  // a diagnosis stage's runs are typically 8-24

// The batch for `device` (as --device: empty = $WETDEM_DEVICE or the best device): 1 on a CPU device,
// kGpuAutoBatch on any other. `why` (if given) gets a line for the log: "16 runs per process (auto: NVIDIA
// H200 is a GPU)". Throws std::runtime_error (from the Vulkan context) when no such device exists.
size_t auto_batch(const std::string& device, std::string* why = nullptr);

// The batch the user asked for, or auto_batch's when `asked` is 0. Pure for asked > 0.
size_t resolve_batch(size_t asked, const std::string& device, std::string* why = nullptr);

// The default of `diagnose --jobs` and `twin --jobs` (0 = auto): processes at a time. On a CPU device one per
// core, up to kCpuAutoJobsMax: lavapipe spreads each dispatch over every core, but a small drum's passes
// leave them idle between dispatches, and two flowing-model runs at once on 2 cores gave 1.34x one run alone,
// their four threads on two cores costing <= 3 % (docs/benchmark.md, "Lavapipe's threads and --jobs 2"). On a
// GPU 1: the batch (an ensemble per process) does that work. Like the batch it never changes a run, only the
// wall time. `cores`: the machine's (std::thread::hardware_concurrency; 0 when unknown counts as 1).
inline constexpr size_t kCpuAutoJobsMax = 8;
size_t auto_jobs(bool cpu_device, unsigned cores);

// The jobs the user asked for, or auto_jobs's for `device` and this machine when `asked` is 0; `why` gets a
// line for the log. Pure for asked > 0; else throws std::runtime_error as auto_batch.
size_t resolve_jobs(size_t asked, const std::string& device, std::string* why = nullptr);

}  // namespace wetdem::diagnose
