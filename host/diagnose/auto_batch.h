// The default of `diagnose --batch` and `twin --batch` (0 = auto): how many runs
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

#include "study/parallel.h"

namespace wetdem::diagnose {

inline constexpr size_t kGpuAutoBatch = 16;  // a diagnosis stage's runs are typically 8-24

// The batch for `device` (as --device: empty = $WETDEM_DEVICE or the best device): 1 on a CPU device,
// kGpuAutoBatch on any other. `why` (if given) gets a line for the log: "16 runs per process (auto: NVIDIA
// H200 is a GPU)". Throws std::runtime_error (from the Vulkan context) when no such device exists.
size_t auto_batch(study::DeviceKind& device, std::string* why = nullptr);

// The batch the user asked for, or auto_batch's when `asked` is 0. Pure for asked > 0.
size_t resolve_batch(size_t asked, study::DeviceKind& device, std::string* why = nullptr);
size_t resolve_batch(size_t asked, const std::string& device, std::string* why = nullptr);

// `--jobs`' default by device: study/parallel.h (study::resolve_jobs).

}  // namespace wetdem::diagnose
