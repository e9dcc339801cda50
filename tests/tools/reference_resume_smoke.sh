#!/bin/bash
# wetdem_reference_resume on the CI-sized closed slice (tests/cases/closed_slice_mini.toml, ~360 wet particles,
# turning end plates): from step 0, and from a checkpoint taken after the drum started turning, the CPU
# reference and the GPU passes step in lockstep. Over the first 0.02 s both beds stay within 1e-7 m of each
# other (particle by particle), hold the same bridges and the same angle; a bad option is refused. Seconds.
set -euo pipefail
wetdem=$1 tool=$2 src=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
check() {  # CSV of the tool: every sample agrees
  /usr/bin/python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) >= 3, rows
for r in rows:
    assert float(r["apart_max_m"]) < 1e-7, r
    assert abs(float(r["aor_ref_deg"]) - float(r["aor_gpu_deg"])) < 1e-4, r
    assert r["bridges_ref"] == r["bridges_gpu"], r
print(f"{sys.argv[1]}: {len(rows)} samples, last apart {rows[-1]['apart_max_m']} m, bridges {rows[-1]['bridges_ref']}")
PY
}
mkdir "$out/start"
cp "$src/tests/cases/closed_slice_mini.toml" "$out/start/case.toml"
"$tool" "$out/start" --from-start --until 0.02 --csv "$out/start.csv"
check "$out/start.csv"
# A checkpoint 83 steps (one sample) after rotation starts (settle 2063 steps at dt = 1.212e-4 s).
"$wetdem" run "$src/tests/cases/closed_slice_mini.toml" --out "$out/run" --quiet --no-figures \
  --set output.checkpoint_interval=2146 --stop-after-steps 2146
"$tool" "$out/run" --until 0.28 --csv "$out/resumed.csv"
check "$out/resumed.csv"
head -2 "$out/resumed.csv" | tail -1 | grep -q '^0.2601' || { echo "resumed at the wrong time"; exit 1; }
if "$tool" "$out/run" --until 0.28 --float32 halves 2>"$out/err"; then echo "bad --float32 accepted"; exit 1; fi
grep -q -- "--float32: velocities, springs or both, got 'halves'" "$out/err"
# --every / --worst: a sample every 5 steps, each naming the particle farthest apart (x, v in both codes).
"$tool" "$out/start" --from-start --until 0.002 --every 5 --worst > "$out/worst.txt"
[ "$(grep -c '^t ' "$out/worst.txt")" -ge 4 ] || { echo "--every 5: too few samples"; exit 1; }
[ "$(grep -c '^  worst id ' "$out/worst.txt")" -eq "$(grep -c '^t ' "$out/worst.txt")" ] || { echo "--worst: a sample without its worst particle"; exit 1; }
if "$tool" "$out/start" --from-start --until 0.002 --every 0 2>"$out/err"; then echo "--every 0 accepted"; exit 1; fi
grep -q -- "--every: steps per sample, >= 1" "$out/err"
# --sequential-events (MercuryDPM's event order) on the reference alone: it runs and reaches its peak line.
"$tool" "$out/start" --from-start --until 0.002 --no-gpu --sequential-events | grep -q '^peak: reference'
echo "reference and GPU in lockstep"
