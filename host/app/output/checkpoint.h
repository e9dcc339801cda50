// Checkpoints of a run: <run>/checkpoint/ holds system.bin (System::snapshot(), the device's own buffer
// image) and host.json (step, time, samples so far, liquid at the start, accumulated wall time, a hash of the
// inserted radii and of the resolved case). Written as checkpoint.tmp/ and swapped in by renames, so a run
// killed at any moment leaves either the previous or the new checkpoint complete.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wetdem::app {

struct Checkpoint {
  std::vector<uint8_t> system;  // System::snapshot()
  nlohmann::json host;          // driver state (run.cpp)
};

void save_checkpoint(const std::string& run_dir, const Checkpoint& c);
// Loads <run>/checkpoint (or checkpoint.old when a swap was interrupted). Throws std::runtime_error when
// there is none or it is damaged (size or hash of system.bin differs from host.json).
Checkpoint load_checkpoint(const std::string& run_dir);
bool has_checkpoint(const std::string& run_dir);

std::string bytes_hash(const void* data, size_t n);  // 64-bit FNV-1a, hex

}  // namespace wetdem::app
