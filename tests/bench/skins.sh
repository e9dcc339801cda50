#!/bin/bash
# wetdem_bench --skin-mm times the same steady state with other neighbour-list skins. A thinner skin must rebuild
# more often and hold fewer entries per particle than a thicker one: the trade the lever measures (docs/benchmark.md).
# Seconds: the micro drum, a short settle, 200 steps.
set -euo pipefail
bench=$1 src=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bench" "$src/assets/studies/micro/micro_case.toml" --variants wet --steps 200 --settle-s 0.05 --rotate-s 0.05 \
  --no-cache --ensemble 2 --skin-mm 0.2,1.2 --json "$out/b.json" | tee "$out/log"
grep -q "^skin 0.2 mm" "$out/log"
/usr/bin/python3 - "$out/b.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["runs"][0]
thin, thick = r["skins"]
assert abs(thin["skin_m"] - 2e-4) < 1e-12 and abs(thick["skin_m"] - 1.2e-3) < 1e-12, r["skins"]
assert thin["rebuilds"] > thick["rebuilds"] >= 0, (thin, thick)
assert thin["entries_per_particle"] < thick["entries_per_particle"], (thin, thick)
for s in (thin, thick):
    assert s["particle_steps_per_s"] > 0 and s["ensemble"]["runs"] == 2, s
    assert s["ensemble"]["particle_steps_per_s"] > 0, s
print("skins:", [(s["skin_m"], s["rebuilds"], round(s["entries_per_particle"], 2)) for s in (thin, thick)])
PY
# A skin the periodic slice cannot hold is refused before any work, naming the option.
if "$bench" "$src/assets/studies/micro/micro_case.toml" --variants wet --steps 20 --no-cache --skin-mm 2.0 \
  >"$out/bad" 2>&1; then
  echo "a 2 mm skin on the 18 mm slice was accepted"; exit 1
fi
grep -q "wetdem_bench: --skin-mm: 2 mm does not fit" "$out/bad" || { cat "$out/bad"; exit 1; }
! grep -q "preparing" "$out/bad" || { echo "work started before the check"; exit 1; }
