#!/bin/bash
# wetdem_bench --timed-only (one System restored from the steady state, one lever setting) runs to its end and
# writes its JSON with the fields the log line and a caller read. Seconds: a short settle and rotation, 20 steps.
set -euo pipefail
bench=$1 src=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bench" "$src/assets/studies/micro/micro_case.toml" --variants wet --steps 20 --settle-s 0.02 --rotate-s 0.01 \
  --no-cache --timed-only --fused-step false --json "$out/b.json" | tee "$out/log"
grep -q "timed only, 20 steps" "$out/log"
/usr/bin/python3 - "$out/b.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["runs"][0]
assert r["particle_steps_per_s"] > 0, r
assert r["timing"]["steps"] == 20 and r["timing"]["wall_s"] > 0, r["timing"]
assert r["timing"]["rotation_s"] > 0, r["timing"]
print("timed-only JSON:", {k: r[k] for k in ("case", "particles", "particle_steps_per_s", "dispatches_per_step")})
PY
