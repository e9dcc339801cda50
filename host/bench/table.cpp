#include "bench/table.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

namespace wetdem::bench {

namespace {

// The k largest passes by share of the profiled GPU time.
std::string passes_text(const nlohmann::json& j, size_t k) {
  std::string s;
  for (size_t i = 0; i < std::min(k, j["passes"].size()); ++i)
    s += fmt::format("{}{} {:.0f}%", i ? ", " : "", j["passes"][i]["name"].get<std::string>(),
                     100.0 * j["passes"][i]["share"].get<double>());
  return s.empty() ? "(no GPU timestamps)" : s;
}

}  // namespace

void print_table(const nlohmann::json& runs) {
  fmt::print("\n{:<14} {:<4} {:>7} {:>9} {:>9} {:>7} {:>8} {:>8} {:>7} {:>6} {:>6} {:>7}  {}\n", "case",
             "var", "n", "p-steps/s", "rot (s)", "rebuild", "contacts", "bridges", "entr/p", "B/p", "B/p-st",
             "roofl.", "largest passes");
  for (const auto& j : runs) {
    const auto& t = j["traffic"];
    fmt::print(
        "{:<14} {:<4} {:>7} {:>9.3g} {:>9.3g} {:>7} {:>8} {:>8} {:>7.1f} {:>6.0f} {:>6.0f} {:>7}  {}\n",
        j["case"].get<std::string>(), j["variant"].get<std::string>(), j["particles"].get<size_t>(),
        j["particle_steps_per_s"].get<double>(), j["timing"]["rotation_s"].get<double>(),
        j["rebuild_interval_steps"].is_null()
            ? std::string("-")
            : fmt::format("{:.1f}", j["rebuild_interval_steps"].get<double>()),
        j["contacts"].get<uint64_t>(), j["bridges"].get<uint64_t>(), j["entries_per_particle"].get<double>(),
        j["memory"]["bytes_per_particle_at_measured_entries"].get<double>(),
        t["bytes_per_particle_step"].get<double>(),
        t.contains("fraction_of_roofline")
            ? fmt::format("{:.1f}%", 100.0 * t["fraction_of_roofline"].get<double>())
            : std::string("-"),
        passes_text(j, 3));
  }
  for (const auto& j : runs)
    if (j.contains("ensembles"))
      for (const auto& e : j["ensembles"])
        fmt::print("ensemble {} {} x {}: {:.3g} particle-steps/s aggregate, {:.2f}x one run\n",
                   j["case"].get<std::string>(), j["variant"].get<std::string>(), e["runs"].get<size_t>(),
                   e["particle_steps_per_s"].get<double>(), e["speedup_over_one_run"].get<double>());
  for (const auto& j : runs)
    if (j.contains("skins"))
      for (const auto& e : j["skins"])
        fmt::print("skin {} {} {:.3g} mm: {:.3g} particle-steps/s, {:.2f}x the case's skin{}\n",
                   j["case"].get<std::string>(), j["variant"].get<std::string>(),
                   1e3 * e["skin_m"].get<double>(), e["particle_steps_per_s"].get<double>(),
                   e["speedup_over_case_skin"].get<double>(),
                   e.contains("ensemble") ? fmt::format("; ensemble {:.3g} aggregate",
                                                        e["ensemble"]["particle_steps_per_s"].get<double>())
                                          : "");
  fmt::print("split rebuilds against the gated chain in every step (same steps, same device):");
  for (const auto& j : runs)
    fmt::print(" {} {} {:.2f}x;", j["case"].get<std::string>(), j["variant"].get<std::string>(),
               j["gated_rebuilds"]["split_speedup"].get<double>());
  fmt::print("\n");
  fmt::print(
      "levers, each against the timed run with that switch turned back (wall-clock / CPU-time speed-up):\n");
  for (const auto& j : runs) {
    fmt::print("  {} {}: {:.1f} dispatches/step, CPU {:.3g} ms/step, liquid passes on {:.0f} % of steps;",
               j["case"].get<std::string>(), j["variant"].get<std::string>(),
               j["dispatches_per_step"].get<double>(), 1e3 * j["cpu_s_per_step"].get<double>(),
               100.0 * j["liquid_pass_fraction"].get<double>());
    for (const auto& [name, l] : j["levers"].items())
      fmt::print(" {} {:.2f}x / {:.2f}x;", name, l["speedup"].get<double>(), l["cpu_speedup"].get<double>());
    fmt::print("\n");
  }
}

}  // namespace wetdem::bench
