#!/usr/bin/env bash
# The paper, reproduced (issue 19, docs/paper.md): the calibration grids as ensembles on one device, the
# calibration on a twin with withheld pore absorption, the figures and the findings table, in one command.
#
#   scripts/paper.sh                    the REDUCED pipeline (no GPU needed: minutes on lavapipe) into paper-reduced/
#   scripts/paper.sh --full             the paper's sizes (a GPU: docs/paper.md "The plan") into paper-full/
#   scripts/paper.sh --figures-only     figures, tables and findings from the runs already in --out
#   scripts/paper.sh --smoke            a few runs of 0.18 s each: the machinery, for CI (tests/paper/paper_smoke.sh)
# Options:
#   --out DIR          where the studies go (default paper-reduced/ or paper-full/; ignored by git)
#   --budget MIN       minutes available (default: 30 reduced, 25 full). Before each stage the device is probed on
#                      the stage's first batch and the stage's time estimated; a stage that does not fit in what is
#                      left is not started: the script says how long it would take (--anyway starts it all the
#                      same, cut at the budget: a cut batch checkpoints and the next call resumes it)
#   --budget-s SEC     the same in seconds (a lent machine's call has a hard limit)
#   --batch K          runs per ensemble for every study stage (default: the plan's, docs/paper.md); a smaller batch
#                      keeps the runs of finished batches when the budget cuts the stage
#   --stages LIST      comma-separated, in this order by default:
#                      pp2_l5,extended,pp2_l3,calibration,diagnosis,pp1_l5
#                      (calibration: the twin's table and the calibration of pp2_l5 against it)
#   --device D         device for every run (index, name substring, gpu, cpu)
#   --export DIR       copy what the figures need (summaries, timeseries, logs, calibration and diagnosis outputs,
#                      the two bed frames) into DIR, e.g. $OUT on a lent GPU machine
#   --no-probe         no probe, no estimates (runs every stage)
# Environment: WETDEM (default build/host/wetdem), PYTHON (default /usr/bin/python3, with matplotlib).
set -euo pipefail
cd "$(dirname "$0")/.."
WETDEM=${WETDEM:-$PWD/build/host/wetdem}
PYTHON=${PYTHON:-/usr/bin/python3}
size=reduced out="" budget="" budget_s="" batch_all="" stages="" device="" export_dir="" figures_only=0 anyway=0 probe=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --full) size=full ;;
    --reduced) size=reduced ;;
    --smoke) size=smoke ;;
    --out) out=$2; shift ;;
    --budget) budget=$2; shift ;;
    --budget-s) budget_s=$2; shift ;;
    --batch) batch_all=$2; shift ;;
    --stages) stages=$2; shift ;;
    --device) device=$2; shift ;;
    --export) export_dir=$2; shift ;;
    --figures-only) figures_only=1 ;;
    --anyway) anyway=1 ;;
    --no-probe) probe=0 ;;
    -h | --help) sed -n '2,25p' "$0"; exit 0 ;;
    *) echo "paper.sh: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
  shift
done
out=${out:-paper-$size}
budget=${budget:-$(case $size in full) echo 25 ;; smoke) echo 10 ;; *) echo 30 ;; esac)}
stages=${stages:-pp2_l5,extended,pp2_l3,calibration,diagnosis,pp1_l5}
A=assets/paper/$size
mkdir -p "$out"
out=$(cd "$out" && pwd)
[[ -x $WETDEM ]] || { echo "paper.sh: no wetdem binary at $WETDEM (build it, or set WETDEM)" >&2; exit 2; }
dev=()
[[ -n $device ]] && dev=(--device "$device")
log() { printf '[paper %s] %s\n' "$(date +%H:%M:%S)" "$*" | tee -a "$out/paper.log"; }
t0=$(date +%s)
deadline=$((t0 + ${budget_s:-$((budget * 60))}))
left() { echo $((deadline - $(date +%s))); }

# Runs per ensemble (one batch per stage where it fits in memory; docs/paper.md "The plan").
batch_of() {
  [[ -n $batch_all && $1 != twin ]] && { echo "$batch_all"; return; }
  case "$size:$1" in
    full:pp2_l5) echo 20 ;;      # the 20 wet runs in one batch, the dry run alone (last in the study file)
    full:extended) echo 8 ;;
    full:pp2_l3) echo 5 ;;
    full:pp1_l5) echo 16 ;;
    full:twin) echo 8 ;;
    *:pp1_l5) echo 8 ;;
    *) echo 20 ;;
  esac
}
study_file() {
  case $1 in
    pp2_l5) echo "$A/pp2_l5.toml" ;;
    extended) echo "$A/pp2_l5_extended.toml" ;;
    pp2_l3) echo "$A/pp2_l3.toml" ;;
    pp1_l5) echo "$A/pp1_l5.toml" ;;
  esac
}

# The first number after "key": in a JSON file, as an integer (0 when absent). No python needed: a lent GPU machine
# may have none.
json_number() {
  [[ -f $1 ]] || { echo 0; return; }
  tr -d '\n' <"$1" | sed -n "s/.*\"$2\": *\([-0-9.eE+]*\).*/\1/p" | awk '{ printf "%d\n", $1 + 0.5 } END { if (NR == 0) print 0 }'
}

# A study stage: probe and estimate, then run what is missing as ensembles (and collect).
run_stage() {
  local st=$1 file dir k secs
  file=$(study_file "$st")
  dir=$out/$st
  k=$(batch_of "$st")
  local reuse=()
  [[ $st == extended && -d $out/pp2_l5 ]] && reuse=(--reuse "$out/pp2_l5")
  if ((probe)); then
    secs=$(left)
    log "stage $st: $file, batches of $k; probing the device (budget left: $((secs / 60)) min)"
    rm -f "$out/$st.estimate.json"
    "$WETDEM" study plan "$file" --out "$dir" --probe --batch "$k" --budget "$secs" --json "$out/$st.estimate.json" \
      "${reuse[@]}" --probe-steps "$([[ $size == smoke ]] && echo 30 || echo 200)" "${dev[@]}" 2>&1 |
      grep -E '^(study|probe|measured|estimate|budget|nothing|note|[0-9]+ of|wetdem: error)' | tee -a "$out/paper.log" || true
    local est
    est=$(json_number "$out/$st.estimate.json" total_s)
    if ((est > secs)) && ((!anyway)); then
      log "stage $st NOT started: it would take about $((est / 60)) min ($est s), $((secs / 60)) min are left." \
        "Run it with more time: scripts/paper.sh --$size --out $out --stages $st --budget $((est / 60 + 5))"
      return 0
    fi
  fi
  log "stage $st: wetdem study run $file --out $dir --batch $k"
  local cut=()
  ((probe)) && ((anyway)) && cut=(timeout -s TERM -k 120 "$(left)")
  local rc=0
  "${cut[@]}" "$WETDEM" study run "$file" --out "$dir" --batch "$k" "${reuse[@]}" "${dev[@]}" --no-collect \
    >>"$out/$st.log" 2>&1 || rc=$?
  tail -n 3 "$out/$st.log" | tee -a "$out/paper.log"
  "$WETDEM" study collect "$dir" --no-figures >>"$out/$st.log" 2>&1 || true
  log "stage $st: exit $rc (a stopped batch resumes on the next call)"
}

# Minutes that `ps` particle-steps take at the rate the pp2_l5 probe measured (0: unknown).
minutes_at_probe() {
  local rate
  rate=$(json_number "$out/pp2_l5.estimate.json" particle_steps_per_s)
  awk -v ps="$1" -v r="$rate" 'BEGIN { print (r > 0 ? int(ps / r / 60 + 0.5) : 0) }'
}

# Calibration at this size (item 5): a twin with pore absorption withheld makes the observation table (its truth
# seeds stepped as one ensemble); the PP2 l = 5 grid is calibrated against it (V_max).
run_calibration() {
  local twin
  twin=$([[ $size == full ]] && echo assets/diagnosis/pp2_l5/twin_absorption.toml || echo "$A/twin_absorption.toml")
  [[ -f $out/pp2_l5/index.json ]] || { log "calibration: needs the pp2_l5 stage first"; return 0; }
  if [[ $size == full ]] && ((probe)); then
    local m
    m=$(minutes_at_probe 1.15e11)  # 8 runs of ~1.43e10 particle-steps
    if ((m * 60 > $(left))) && ((!anyway)); then
      log "stage calibration NOT started: the twin's 8 runs take about $m min, $(($(left) / 60)) min are left"
      return 0
    fi
  fi
  log "stage calibration: twin $twin (truth: pore absorption), then calibrate pp2_l5 against its table (V_max)"
  if [[ ! -f $out/twin/observations.csv ]]; then
    "$WETDEM" twin "$twin" --out "$out/twin" --store "$out/diag_store" --batch "$(batch_of twin)" "${dev[@]}" \
      >>"$out/calibration.log" 2>&1 || { log "twin failed (see $out/calibration.log)"; return 0; }
  fi
  "$WETDEM" calibrate "$out/pp2_l5" --observations "$out/twin/observations.csv" --fit liquid.v_max \
    >>"$out/calibration.log" 2>&1 || log "calibrate failed (see $out/calibration.log)"
  grep -h -m3 -E 'optimum|best' "$out/pp2_l5/calibration/calibration.md" 2>/dev/null | tee -a "$out/paper.log" || true
}

# The diagnosis of the calibrated model against the twin's table: which candidate explains the gap.
run_diagnosis() {
  local diag
  diag=$([[ $size == full ]] && echo assets/diagnosis/pp2_l5/diagnose.toml || echo "$A/diagnose.toml")
  [[ -f $out/twin/observations.csv ]] || { log "diagnosis: needs the calibration stage first"; return 0; }
  if [[ $size == full ]] && ((probe)); then
    local m
    m=$(minutes_at_probe 1.1e12)  # ~80 runs (README "Sim-to-real diagnosis") of ~1.43e10 particle-steps
    if ((m * 60 > $(left))) && ((!anyway)); then
      log "stage diagnosis NOT started: ~80 runs, about $m min at the probed rate; $(($(left) / 60)) min are left" \
        "(run it alone: scripts/paper.sh --full --out $out --stages diagnosis --budget $((m + 10)))"
      return 0
    fi
  fi
  if [[ ! -f $out/diagnosis/diagnosis.json ]]; then
    log "stage diagnosis: $diag against the twin's table"
    local cut=()
    ((anyway)) && cut=(timeout -s TERM -k 120 "$(left)")
    "${cut[@]}" "$WETDEM" diagnose "$diag" --observations "$out/twin/observations.csv" --out "$out/diagnosis" \
      --store "$out/diag_store" --batch 20 "${dev[@]}" >>"$out/calibration.log" 2>&1 ||
      log "diagnose failed or was cut (see $out/calibration.log)"
  fi
  log "stage diagnosis: $(grep -h -m1 '"verdict"' "$out/diagnosis/diagnosis.json" 2>/dev/null | tr -d ' ,')"
}

if ((!figures_only)); then
  log "wetdem paper pipeline, $size size, into $out; budget $budget min; stages $stages; $("$WETDEM" --version 2>/dev/null | head -1)"
  IFS=, read -ra list <<<"$stages"
  for st in "${list[@]}"; do
    if (($(left) <= 0)); then
      log "budget spent: stage $st and the rest not started (run them with --stages)"
      break
    fi
    case $st in
      calibration) run_calibration ;;
      diagnosis) run_diagnosis ;;
      pp2_l5 | extended | pp2_l3 | pp1_l5) run_stage "$st" ;;
      *) log "unknown stage $st"; exit 2 ;;
    esac
  done
  log "runs done in $(($(date +%s) - t0)) s wall"
fi

if [[ -n $export_dir ]]; then
  mkdir -p "$export_dir"
  # Everything small (no frames, no checkpoints), with coreutils only: a lent machine has no rsync or cpio.
  (cd "$out" && find . -type f \( -name '*.json' -o -name '*.csv' -o -name '*.log' -o -name '*.md' -o -name '*.toml' \
    -o -name '*.png' \) -not -path '*/checkpoint*' -not -path '*/ensemble/*' -print0 |
    xargs -0 -r cp --parents -t "$export_dir")
  # The frames of the bed pictures: the last frame of the dry run and of 10 % at V_max = 1 % (PP2 l = 5).
  for r in "$out"/pp2_l5/runs/*/; do
    c=$(sed -n 's/^content *= *//p' "$r/case.toml" | head -1) v=$(sed -n 's/^v_max *= *//p' "$r/case.toml" | head -1)
    if [[ $c == 0 || $c == 0.0 || ($c == 0.1 && $v == 0.01) ]]; then
      f=$(ls "$r"frames/*.glb 2>/dev/null | tail -1)
      [[ -n $f ]] && (cd "$out" && cp --parents -t "$export_dir" "${f#$out/}" "${r#$out/}frames/frames.json")
    fi
  done
  log "exported to $export_dir ($(du -sh "$export_dir" | cut -f1))"
fi

if "$PYTHON" -c "import matplotlib" 2>/dev/null; then
  "$PYTHON" scripts/paper_figures.py "$out" --size "$size" | tee -a "$out/paper.log"
else
  log "no matplotlib here: figures skipped (make them where it is: scripts/paper.sh --figures-only --out DIR)"
fi
