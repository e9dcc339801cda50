#!/usr/bin/env bash
# The command line as a newcomer meets it (issue 21): `wetdem` with no arguments exits 0 and prints the tour's
# first command, whose case file exists and which the README gives too; `wetdem --help` and every command's
# --help end with a one-line example.
# usage: help_examples.sh WETDEM SOURCE_DIR
set -euo pipefail
W=$1
SRC=$2
fail() { echo "FAIL: $*"; exit 1; }

out=$("$W") || fail "wetdem with no arguments exited $?"
first=$(printf '%s\n' "$out" | grep -E '^  wetdem run ' | sed 's/^  //') || fail "no 'wetdem run' line in: $out"
echo "first command: $first"
case_file=$(printf '%s\n' "$first" | awk '{print $3}')
[ -f "$SRC/$case_file" ] || fail "the first command's case $case_file does not exist"
grep -qF "$case_file" "$SRC/README.md" || fail "README.md does not mention $case_file"

for cmd in "" run check devices study "study plan" "study run" "study run-one" "study run-batch" "study slurm" \
  "study collect" calibrate diagnose twin; do
  # shellcheck disable=SC2086
  help=$("$W" $cmd --help) || fail "wetdem $cmd --help exited $?"
  printf '%s\n' "$help" | grep -qE '^Example: wetdem' || fail "wetdem $cmd --help shows no example"
done
echo "every --help shows an example"
