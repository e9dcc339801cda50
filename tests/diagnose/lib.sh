# Shared by the diagnosis end-to-end scripts (sourced: `source "$(dirname "$0")/lib.sh" "$@"`): the arguments
# WETDEM SOURCE_DIR [STORE], a scratch folder $D removed on exit, the run store $S, and two helpers on a JSON file:
#   J FILE EXPR                  prints EXPR evaluated with j = the file's JSON (python syntax)
#   expect FILE EXPR WHY [SHOW]  fails with "FAIL: WHY" (and prints SHOW, e.g. the report) unless EXPR is True
#   expect_text FILE TEXT WHY    fails with "FAIL: WHY" (and prints FILE) unless FILE contains TEXT (a grep pattern)
set -euo pipefail
W=$1
SRC=$2
D=$(mktemp -d)
[ -n "${KEEP_D:-}" ] || trap 'rm -rf "$D"' EXIT
# The run store: STORE when given (the CI's micro scripts share one, tests/CMakeLists.txt, so that the baseline,
# the screen probes and the twins' runs are made once; a diagnosis never depends on what a store already holds),
# else a fresh one in the scratch folder.
S=${3:-$D/store}
J() { /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
expect() {
  [ "$(J "$1" "$2")" = True ] && return 0
  echo "FAIL: $3"
  [ -n "${4:-}" ] && cat "$4"
  exit 1
}
expect_text() {
  grep -q -- "$2" "$1" && return 0
  echo "FAIL: $3"
  cat "$1"
  exit 1
}
# `wd twin|diagnose ARGS`: the CLI call with the runs of each stage handed to one process as an ensemble
# (--batch; each run bitwise what it computes alone, docs/ensembles.md): one process and one pipeline set-up per
# stage instead of per run. The micro spread diagnosis: 202 s -> 174 s with --batch 16 (27 Nov 2026, lavapipe).
BATCH=${WETDEM_TEST_BATCH:-16}
wd() {
  local cmd=$1
  shift
  "$W" "$cmd" "$@" --batch "$BATCH"
}
t0=$(date +%s)
