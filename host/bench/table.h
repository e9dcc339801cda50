// The benchmark's printed summary (wetdem_bench): one line per case and variant, then the ensembles, skins,
// split rebuilds and levers, from the JSON the benchmark writes (docs/benchmark.md "Running the benchmark").
#pragma once

#include <nlohmann/json.hpp>

namespace wetdem::bench {

// Prints the table of `runs` (the JSON array wetdem_bench writes as "runs") to stdout.
void print_table(const nlohmann::json& runs);

}  // namespace wetdem::bench
