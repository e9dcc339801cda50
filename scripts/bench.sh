#!/usr/bin/env bash
# The benchmark of docs/benchmark.md in one command. Steady states are cached (~/.cache/wetdem/bench, or
# --cache DIR), so a second call times only.
#   scripts/bench.sh                 GPU machine: every shipped case, wet and dry, prepared through each case's own
#                                    settle and run.steady_state_start (full steady rotation); bench.json
#   scripts/bench.sh --lavapipe      the lavapipe table of docs/benchmark.md: demo slice and closed demo drum (wet and dry, own
#                                    preparation) and PP2 l = 5 wet (short preparation: 0.03 s settle, 0.01 s
#                                    rotation, 200 timed steps); docs/bench/lavapipe-*.json
#   Both also time ensembles (docs/ensembles.md) of the micro drum and the closed demo drum: 8 and 32 copies
#   (and 128 on a GPU) stepped together in one System.
# Further arguments go to wetdem_bench (--device, --cache, --bandwidth, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
BENCH=${WETDEM_BENCH:-./build/host/wetdem_bench}
if [[ "${1:-}" == "--lavapipe" ]]; then
  shift
  "$BENCH" assets/demo.toml assets/demo_closed.toml --variants wet,dry --steps 1000 --json docs/bench/lavapipe-demo.json "$@"
  "$BENCH" assets/pp2_l5.toml --variants wet --settle-s 0.03 --rotate-s 0.01 --steps 200 --warmup 20 \
    --json docs/bench/lavapipe-pp2_l5.json "$@"
  "$BENCH" assets/studies/micro/micro_case.toml assets/demo_closed.toml --variants wet --steps 1000 --ensemble 8,32 \
    --json docs/bench/lavapipe-ensembles.json "$@"
  /usr/bin/python3 scripts/bench_table.py docs/bench/lavapipe-demo.json docs/bench/lavapipe-pp2_l5.json \
    docs/bench/lavapipe-ensembles.json
else
  "$BENCH" --variants wet,dry --steps 2000 --json bench.json "$@"
  "$BENCH" assets/studies/micro/micro_case.toml assets/demo_closed.toml --variants wet --steps 3000 \
    --ensemble 8,32,128 --json bench-ensembles.json "$@"
  /usr/bin/python3 scripts/bench_table.py bench.json bench-ensembles.json
fi
