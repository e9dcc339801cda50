// The benchmark's arithmetic: rebuild interval, device bytes per particle, and the memory traffic of one step
// against the device's bandwidth (a roofline estimate). Pure functions, unit-tested
// (tests/test_bench_traffic.cpp).
//
// Traffic model (compulsory traffic: every live byte moved once, as with an ideal cache; docs/benchmark.md):
//   every step   2 n B_pset + 2 E (B_eset + B_escr)   current particle set and entry set read once and
//   written
//                                                     once; per-entry scratch (pair forces, events) written
//                                                     once and read once
//   per rebuild  2 n (B_pset + B_pscr) + 2 E B_eset    particle set reordered into the other set (read +
//   write),
//                                                     per-particle scratch (keys, reference positions, ...)
//                                                     written and read once, new entry set written and the
//                                                     old one read once (history carried over)
//   bytes/step = every step + per rebuild / rebuild interval
// n particles, E neighbour entries in the list (both directions), B_* bytes per element of one set or of the
// scratch, taken from the real buffer sizes (System::device_memory()). Neighbour reads through the list and
// cache misses are not counted, so the model is a lower bound on the bytes a step moves, and
// bandwidth / bytes-per-step an upper bound on the steps per second (the memory roofline).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace wetdem::bench {

// Steps per neighbour-list rebuild over a timed window; empty when the window saw no rebuild.
std::optional<double> rebuild_interval(uint64_t steps, uint64_t rebuilds);

// Bytes per element, from the buffer sizes.
struct ElementBytes {
  double particle_set = 0;      // one particle set, per particle
  double particle_scratch = 0;  // per-particle scratch, per particle
  double entry_set = 0;         // one entry set, per entry
  double entry_scratch = 0;     // per-entry scratch, per entry
};

struct Traffic {
  double every_step = 0;   // bytes moved by every step
  double per_rebuild = 0;  // extra bytes of one rebuild
  double per_step = 0;     // every_step + per_rebuild / interval
  double per_particle_step = 0;
};

// n particles, `entries` neighbour entries; interval empty: no rebuild (the rebuild term is dropped).
Traffic step_traffic(const ElementBytes& b, double n, double entries, std::optional<double> interval);

// Device bytes per particle at a coordination of `entries_per_particle` list entries: its share of both
// particle sets and the per-particle scratch, plus that many entries of both entry sets and the scratch.
double bytes_per_particle(const ElementBytes& b, double entries_per_particle);

// Peak memory bandwidth (GB/s = 1e9 B/s) assumed for a device name when --bandwidth is not given, and where
// the number comes from; 0 for an unknown device (then the roofline is not reported).
struct Bandwidth {
  double gbs = 0;
  std::string source;
};
Bandwidth default_bandwidth(const std::string& device_name);

}  // namespace wetdem::bench
