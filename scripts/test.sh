#!/usr/bin/env bash
# The README's test command: installs what is missing (Debian 12), checks formatting, builds, runs every test on lavapipe with
# the Khronos validation layer on, then builds the host code with ASan/UBSan and runs the tests again there.
# WETDEM_SKIP_SANITIZE=1 skips the sanitizer pass (quicker local runs).
set -euo pipefail
cd "$(dirname "$0")/.."
t0=$(date +%s)
phase() { echo "== $1 done at $(($(date +%s) - t0)) s"; }  # where a slow CI spends its time
bash scripts/setup-debian.sh
phase setup
jobs=$(nproc)
# A fresh build directory has no ctest cost data, so ctest would start the tests in file order and leave the long
# ones (the paper pipeline, the serial Slurm test) as a tail on one core. Seed it with the times of a reference run
# (tests/ci/ctest-costs.txt): ctest then starts the longest first. Only the order changes; ctest keeps its own
# measured times from then on. To refresh it after tests are added or renamed: copy a Release build's
# Testing/Temporary/CTestCostData.txt over it (ctest's own format, "name runs seconds" per line, nothing else).
seed_costs() {
  mkdir -p "$1/Testing/Temporary"
  [ -f "$1/Testing/Temporary/CTestCostData.txt" ] || cp tests/ci/ctest-costs.txt "$1/Testing/Temporary/CTestCostData.txt"
}

# Formatting is part of the build contract (.clang-format at the root).
find host include tests cmake \( -name '*.cpp' -o -name '*.h' \) -print0 | xargs -0 clang-format --dry-run --Werror

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
phase "Release build"
seed_costs build
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 900
phase "Release tests"

if [ "${WETDEM_SKIP_SANITIZE:-0}" != "1" ]; then
  # Host code under AddressSanitizer + UndefinedBehaviorSanitizer. The Vulkan driver is not instrumented;
  # its own allocations are not leak-checked (detect_leaks=0), every host-side error aborts the test.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWETDEM_SANITIZE=ON
  # Only the test binary is built here: the end-to-end scripts that drive the `wetdem` CLI (real Slurm, the
  # micro diagnosis, the help texts, the paper pipeline, the benchmark tool, the reference-resume tool, the
  # group SIGTERM of a study, the shipped twins' checks) ran in the Release pass above and are left out.
  cmake --build build-asan -j"$jobs" --target wetdem_tests
  phase "ASan build"
  seed_costs build-asan
  # Also left out: the long lavapipe runs (drum-scale runs, bitwise comparisons of whole GPU runs) whose time goes
  # to the uninstrumented driver, not to host code; the host paths they take (case, fill, step loop, resume,
  # batches, ensembles) are run here by the shorter tests of the same rooms.
  long_gpu="DryInert\\.|DrumPhysics\\.|PlateRolling\\.|DrumLiquidEffects\\.|DrumRun\\.(Batch|Resume|Stopped)"
  long_gpu+="|GpuSystem\\.(FusedStep|StepsWriteTheirScratch|SameRunTwice)|Backends/Liquid\\.HangingSphere/gpu"
  long_gpu+="|Backends/CandidateForces\\.ViscousForceFollowsPitois/gpu|Backends/Sinks\\.LiquidConservedExactlyOver1e5Steps/gpu"
  long_gpu+="|CandidateDrum\\.|LiquidSoak\\.|GpuSystem\\.(SplitRebuilds|NeighbourListEqualsBruteForce|RunIsBitwiseIndependent|SkinTestInTheDrumFrame)"
  long_gpu+="|Ensemble\\.EachRunIsBitwise|SampleDevice\\.EachRunOfAnEnsemble|Sort\\.OneTileSortIsTheMultiPassSort"
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 \
    -E "^(StudySlurm|StudySignals|DiagnoseMicro|Cli|PaperPipeline|Bench|ReferenceResume)\\.|^TwinMatrix\\.EveryShippedTwinChecks$|^($long_gpu)${WETDEM_SANITIZE_EXCLUDE:+|$WETDEM_SANITIZE_EXCLUDE}"
  phase "ASan tests"
fi
