#!/bin/bash
# A batch stopped the way `timeout` (scripts/paper.sh --anyway) and Slurm stop it: SIGTERM to the whole process
# group. The run process then gets two SIGTERMs, the group's and the one `study run` forwards. It must still stop at
# its next step boundary and write its checkpoint (app/run/stop_signals.h): before the fix, the second signal
# ended it by default and the batch resumed from its last periodic checkpoint (on an H200 that lost ~160,000 steps
# of a 5-run PP2 l = 5 batch, docs/paper.md). Here there is no periodic checkpoint, so a resume from step > 0 can
# only come from the checkpoint written on the signal. `--jobs 1` keeps the two runs in one process (on a CPU device
# `study run` would start one process per core).
# Usage: group_sigterm.sh WETDEM_BINARY SOURCE_DIR
set -eu
WETDEM=$1
SRC=$2
D=$(mktemp -d /tmp/wetdem_sigterm_XXXXXX)
trap 'rm -rf "$D"' EXIT
cat > "$D/s.toml" <<TOML
name = "sigterm"
base = "$SRC/assets/studies/micro/micro_case.toml"
replicates = 2
[set]
"run.settle" = "0.04 s"
"run.duration" = "2 s"
"run.steady_state_start" = "0.02 s"
"output.checkpoint_interval" = 1000000
"output.snapshot_interval" = "0 s"
TOML
setsid "$WETDEM" study run "$D/s.toml" --out "$D/st" --batch 2 --jobs 1 --no-collect > "$D/out.log" 2>&1 &
pid=$!
# Stop it once the batch is stepping (the run log says the drum turns), well before its end.
for _ in $(seq 600); do
  grep -qs "drum starts turning" "$D"/st/runs/*/run.log && break
  kill -0 $pid 2>/dev/null || { cat "$D/out.log"; echo "FAIL: the study ended before it was signalled"; exit 1; }
  sleep 0.1
done
sleep 1
kill -TERM -- -$pid
wait $pid && rc=0 || rc=$?
cat "$D/out.log"
fail=0
[ "$rc" -ne 0 ] || { echo "FAIL: an interrupted study exited 0"; fail=1; }
grep -q "killed by signal" "$D/out.log" && { echo "FAIL: a run process died of the signal"; fail=1; }
[ "$(grep -c "stopped, resumable" "$D/out.log")" = 2 ] || { echo "FAIL: not both runs resumable"; fail=1; }
# Resume to the end: the batch must start from the checkpoint the signal wrote.
"$WETDEM" study run "$D/s.toml" --out "$D/st" --no-collect > "$D/out2.log" 2>&1 || { cat "$D/out2.log"; fail=1; }
for r in "$D"/st/runs/*/; do
  step=$(sed -n 's/^resumed the batch at step \([0-9]*\).*/\1/p' "$r/run.log" | head -1)
  echo "$(basename "$r"): resumed at step ${step:-none}"
  [ -n "$step" ] && [ "$step" -gt 0 ] || { echo "FAIL: no checkpoint written on the signal"; fail=1; }
  [ -f "$r/summary.json" ] || { echo "FAIL: the resumed run has no summary"; fail=1; }
done
[ $fail = 0 ] && echo "PASS: a group SIGTERM leaves a checkpoint and the batch resumes from it"
exit $fail
