#!/bin/bash
# The real-Slurm test of `wetdem study slurm`: starts a single-node Slurm on this host (munged + slurmctld +
# slurmd, generated slurm.conf in a temp dir, no cgroups; ../shared/guides/slurm-local.md), submits a micro study
# as a job array, waits, collects, runs the same study locally and checks that every run's summary is identical
# (runs are deterministic) apart from timing fields and paths. Then the same study with --batch 2 (one array
# task per batch, each stepped as one ensemble: issue 19): again identical, apart from the "ensemble" record.
# Usage: study_slurm.sh WETDEM_BINARY SOURCE_DIR. Exit 77 (skipped, reason printed) without root or Slurm.
set -eu
WETDEM=$1
SRC=$2
skip() { echo "SKIPPED: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "needs root to start slurmctld/slurmd/munged"
for b in slurmctld slurmd sbatch squeue sinfo munged munge; do
  command -v "$b" >/dev/null 2>&1 || [ -x "/usr/sbin/$b" ] || skip "$b not installed (scripts/setup-debian.sh installs slurm-wlm and munge)"
done
pgrep -x slurmctld >/dev/null && skip "a slurmctld is already running on this host"

D=$(mktemp -d /tmp/wetdem_slurm_XXXXXX)
H=$(hostname -s)
mkdir -p "$D"/{state,spool,log}
export SLURM_CONF=$D/slurm.conf
cat > "$SLURM_CONF" <<CONF
ClusterName=wetdemtest
SlurmctldHost=$H
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
MailProg=/bin/true
NodeName=$H CPUs=$(nproc) Sockets=1 CoresPerSocket=$(nproc) ThreadsPerCore=1 RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=$H Default=YES MaxTime=INFINITE State=UP
CONF

PIDS=""
MPID=""
stop() {
  [ -n "$PIDS" ] && kill $PIDS 2>/dev/null || true
  for p in $PIDS; do while kill -0 "$p" 2>/dev/null; do sleep 0.2; done; done
  [ -n "$MPID" ] && kill "$MPID" 2>/dev/null || true
  [ -n "$MPID" ] && while kill -0 "$MPID" 2>/dev/null; do sleep 0.2; done
  return 0
}
trap stop EXIT

if [ ! -s /run/munge/munged.pid ] || ! kill -0 "$(cat /run/munge/munged.pid)" 2>/dev/null; then
  [ -s /etc/munge/munge.key ] || { mungekey -c -f -k /etc/munge/munge.key; chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
  mkdir -p /run/munge && chown munge:munge /run/munge && chmod 755 /run/munge
  runuser -u munge -- /usr/sbin/munged
  for i in $(seq 1 50); do [ -s /run/munge/munged.pid ] && break; sleep 0.1; done
  MPID=$(cat /run/munge/munged.pid)
fi
munge -n | unmunge >/dev/null
slurmctld -c -f "$SLURM_CONF"
slurmd -c -f "$SLURM_CONF"
for f in "$D/slurmctld.pid" "$D/slurmd.pid"; do for i in $(seq 1 50); do [ -s "$f" ] && break; sleep 0.1; done; done
PIDS="$(cat "$D/slurmd.pid") $(cat "$D/slurmctld.pid")"
for i in $(seq 1 60); do sinfo -h -N -o '%T' 2>/dev/null | grep -qx idle && break; sleep 0.5; done
sinfo -h -N -o '%N %T' | grep -q idle || { cat "$D"/log/*.log; echo "FAIL: the Slurm node did not come up"; exit 1; }

# A micro study of 3 runs, each a few hundred steps.
cat > "$D/s.toml" <<TOML
name = "slurm-micro"
base = "$SRC/assets/studies/micro/micro_case.toml"
[set]
"run.settle" = "0.04 s"
"run.duration" = "0.06 s"
"run.steady_state_start" = "0.02 s"
[axes]
"liquid.content" = ["0 %", "5 %", "10 %"]
TOML

submit() {  # study dir, extra flags...
  local out=$1; shift
  "$WETDEM" study slurm "$D/s.toml" --out "$out" --submit "$@" | tee "$D/submit.txt"
  JID=$(sed -n 's/^submitted job \([0-9]*\).*/\1/p' "$D/submit.txt")
  [ -n "$JID" ] || { echo "FAIL: no job id"; exit 1; }
  for i in $(seq 1 600); do [ -z "$(squeue -h -j "$JID" 2>/dev/null)" ] && break; sleep 0.5; done
  [ -z "$(squeue -h -j "$JID" 2>/dev/null)" ] || { echo "FAIL: the array did not finish in 300 s"; exit 1; }
  "$WETDEM" study collect "$out" --no-figures
}
submit "$D/slurm_study"
submit "$D/slurm_batch" --batch 2
grep -q 'run-batch' "$D/slurm_batch/slurm/study.sbatch" || { echo "FAIL: --batch wrote no run-batch task"; exit 1; }
grep -q 'BATCHES=( 0,1 2 )' "$D/slurm_batch/slurm/study.sbatch" || { echo "FAIL: batches are not 0,1 and 2"; exit 1; }
"$WETDEM" study run "$D/s.toml" --out "$D/local_study" --no-collect

# Same runs (same hashes), identical summaries apart from timing and paths (and the batch's record).
for A in "$D/slurm_study" "$D/slurm_batch"; do
/usr/bin/python3 - "$A" "$D/local_study" <<'PY'
import json, os, sys
a, b = sys.argv[1], sys.argv[2]
ia, ib = json.load(open(a + "/index.json")), json.load(open(b + "/index.json"))
assert [r["hash"] for r in ia["runs"]] == [r["hash"] for r in ib["runs"]], "different plans"
skip = {"wall_time_s", "wall_split_s", "particle_steps_per_s", "case_source"}
if os.path.basename(a) == "slurm_batch":  # the batch's record and its shared neighbour-list schedule
    skip |= {"ensemble", "neighbour_list"}
for r in ia["runs"]:
    sa = json.load(open(os.path.join(a, r["run_dir"], "summary.json")))
    sb = json.load(open(os.path.join(b, r["run_dir"], "summary.json")))
    da = {k: v for k, v in sa.items() if k not in skip}
    db = {k: v for k, v in sb.items() if k not in skip}
    diff = [k for k in set(da) | set(db) if da.get(k) != db.get(k)]
    assert not diff, "run %d: summaries differ in %s" % (r["index"], diff)
    print("%s run %d (%s): identical, final state %s, AoR %s" % (os.path.basename(a), r["index"], r["hash"],
                                                                 sa["final_state_hash"], sa["aor_deg_mean"]))
PY
done
stop
trap - EXIT
rm -rf "$D"
echo "PASS: Slurm arrays (one run per task, and --batch 2) equal the local study"
