#include "bench/traffic.h"

#include <algorithm>
#include <cctype>
#include <utility>
#include <vector>

namespace wetdem::bench {

std::optional<double> rebuild_interval(uint64_t steps, uint64_t rebuilds) {
  if (rebuilds == 0) return std::nullopt;
  return double(steps) / double(rebuilds);
}

Traffic step_traffic(const ElementBytes& b, double n, double entries, std::optional<double> interval) {
  Traffic t;
  t.every_step = 2.0 * n * b.particle_set + 2.0 * entries * (b.entry_set + b.entry_scratch);
  t.per_rebuild = 2.0 * n * (b.particle_set + b.particle_scratch) + 2.0 * entries * b.entry_set;
  t.per_step = t.every_step + (interval ? t.per_rebuild / *interval : 0.0);
  t.per_particle_step = n > 0 ? t.per_step / n : 0.0;
  return t;
}

double bytes_per_particle(const ElementBytes& b, double entries_per_particle) {
  return 2.0 * b.particle_set + b.particle_scratch +
         entries_per_particle * (2.0 * b.entry_set + b.entry_scratch);
}

Bandwidth default_bandwidth(const std::string& device_name) {
  std::string s = device_name;
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  auto has = [&](const char* w) { return s.find(w) != std::string::npos; };
  // Vendor data sheets (HBM peak); the first match wins, so the more specific names come first.
  const std::vector<std::pair<const char*, Bandwidth>> table = {
      {"h200", {4800, "NVIDIA H200 data sheet, 4.8 TB/s HBM3e"}},
      {"h100 pcie", {2000, "NVIDIA H100 PCIe data sheet, 2.0 TB/s HBM2e"}},
      {"h100", {3350, "NVIDIA H100 SXM data sheet, 3.35 TB/s HBM3"}},
      {"a100-pcie-40gb", {1555, "NVIDIA A100 40GB data sheet, 1.56 TB/s"}},
      {"a100-sxm4-40gb", {1555, "NVIDIA A100 40GB data sheet, 1.56 TB/s"}},
      {"a100", {2039, "NVIDIA A100 80GB data sheet, 2.0 TB/s"}},
      {"l40s", {864, "NVIDIA L40S data sheet, 864 GB/s"}},
      {"rtx 4090", {1008, "NVIDIA RTX 4090 data sheet, 1.0 TB/s"}},
      {"mi300x", {5300, "AMD MI300X data sheet, 5.3 TB/s"}},
      {"llvmpipe", {20, "assumed for lavapipe on a 2-core share of a server's DRAM (docs/benchmark.md)"}},
  };
  for (const auto& [key, bw] : table)
    if (has(key)) return bw;
  return {0, "unknown device: give --bandwidth GB/s"};
}

}  // namespace wetdem::bench
