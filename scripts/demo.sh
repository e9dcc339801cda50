#!/usr/bin/env bash
# The README's main job: installs what is missing (Debian 12), builds, and runs the demo case (a thin wet
# periodic slice of the paper's drum) on the default device: a real GPU when there is one, else lavapipe.
# Extra arguments go to `wetdem run` (e.g. --device cpu, --set run.duration_s=2).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target wetdem
./build/host/wetdem run assets/demo.toml --out runs/demo "$@"
