#!/usr/bin/env bash
# The README's main job: installs what is missing (Debian 12), builds, and runs assets/quick_drum.toml, a small
# wet drum that reaches steady rotation and a quotable dynamic AoR in a few minutes on lavapipe, with its two
# figures. On the default device: a real GPU when there is one, else lavapipe. When a GPU is found it also
# offers the paper-scale drum:
#   bash scripts/demo.sh --paper     the paper's PP2 drum at l = 5 (assets/pp2_l5.toml: ~22k particles, 24 s of
#                                    rotation; minutes on a GPU, about a day on lavapipe)
# Other arguments go to `wetdem run` (e.g. --device cpu, --no-figures, --set run.duration="10 s").
set -euo pipefail
cd "$(dirname "$0")/.."
case_file=assets/quick_drum.toml
out=runs/quick
if [ "${1:-}" = "--paper" ]; then
  shift
  case_file=assets/pp2_l5.toml
  out=runs/pp2_l5
fi
bash scripts/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target wetdem
W=./build/host/wetdem
gpu=$("$W" devices | grep -E '\((discrete|integrated|virtual) GPU\)' | head -1 || true)
if [ "$case_file" = assets/pp2_l5.toml ] && [ -z "$gpu" ]; then
  echo "note: no GPU found; the paper-scale drum takes about a day on lavapipe (Ctrl-C stops it, --resume continues)"
fi
# A run folder holds one run: a second demo writes a new folder beside the first.
if [ -e "$out" ]; then out="$out-$(date +%Y%m%d-%H%M%S)"; fi
"$W" run "$case_file" --out "$out" "$@"
if [ "$case_file" = assets/quick_drum.toml ] && [ -n "$gpu" ]; then
  echo
  echo "A GPU is here (${gpu#*: }): bash scripts/demo.sh --paper runs the paper's PP2 drum at l = 5"
  echo "(~22k particles, 24 s of rotation: a few minutes on an NVIDIA H100, docs/benchmark.md)."
fi
