#!/usr/bin/env bash
# Runs wetdem on a lent GPU machine (guides/gpu-machine.md) from binaries built here: the machine has no package
# registry, so the Vulkan loader, the GL vendor-neutral libraries, the validation layer and wetdem's shared
# libraries travel in .gl/, the binaries in .devbuild/ (both ignored by git, carried by the device tool). Once:
#   mkdir -p .gl/lib .devbuild; o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64'
#   (cd .gl && apt-get $o download libvulkan1 libglvnd0 libegl1 libgl1 libglx0 libopengl0 libgles2 \
#      vulkan-validationlayers)
#   for l in libtomlplusplus.so.3 libtinygltf.so.2d libfmt.so.9 libstb.so.0; do cp -L /lib/x86_64-linux-gnu/$l .gl/lib/; done
#   cp build/host/wetdem build/host/wetdem_bench build/tests/wetdem_tests .devbuild/
#   scripts/device_run.sh tests [GTEST_FILTER]   the whole test suite on the GPU with the Khronos validation layer,
#                                                16 shards at once; one log per shard and a summary in $OUT
#   scripts/device_run.sh bench ARGS...          wetdem_bench ARGS (JSON into $OUT)
#   scripts/device_run.sh wetdem ARGS...         the wetdem CLI
#   scripts/device_run.sh paper ARGS...          the paper pipeline, scripts/paper.sh ARGS (docs/paper.md); give
#                                                --export "$OUT/px" to bring back what its figures need, packed
#                                                as $OUT/px.tgz
#   scripts/device_run.sh script FILE            a bash script with $WETDEM set, e.g. the validation matrix's
#                                                (scripts/twin_matrix.py --script FILE; docs/validation.md)
# Results go to $OUT (the device tool brings that folder back); elsewhere to ./device-out.
set -uo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-$PWD/device-out}
mkdir -p "$OUT"
{
  # The loader and the GL vendor-neutral libraries the NVIDIA ICD loads go to / (as the guide says); the
  # validation layer and any other library stay in /tmp/vl.
  for f in .gl/libvulkan1_*.deb .gl/libglvnd0_*.deb .gl/libegl1_*.deb .gl/libgl1_*.deb .gl/libglx0_*.deb \
    .gl/libopengl0_*.deb .gl/libgles2_*.deb; do [[ -e "$f" ]] && dpkg -x "$f" /; done
  mkdir -p /tmp/vl && for f in .gl/*.deb; do case "$f" in *libvulkan1_* | *libglvnd0_* | *libegl1_* | *libgl1_* | *libglx0_* | *libopengl0_* | *libgles2_*) ;; *) dpkg -x "$f" /tmp/vl ;; esac; done
  ldconfig
}
export LD_LIBRARY_PATH=$PWD/.gl/lib:/tmp/vl/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export VK_LAYER_PATH=/tmp/vl/usr/share/vulkan/explicit_layer.d
if [[ -e /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
# The tests find assets through the source path compiled in (WETDEM_SOURCE_DIR).
src=$(strings .devbuild/wetdem_tests | grep -m1 -o '^/[^ ]*/main$' || true)
if [[ -n "$src" && ! -e "$src" ]]; then mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"; fi
B=$PWD/.devbuild
mode=${1:-}
shift || true
case "$mode" in
  tests)
    # Shards run at once (the GPU tests mostly wait on submits); each is cut at WETDEM_SHARD_TIMEOUT seconds so
    # that one slow test cannot lose the other shards' logs. One log comes back: tests.log.
    filter=${1:-*}
    shards=${WETDEM_SHARDS:-32}
    export WETDEM_VALIDATION=1 WETDEM_DEVICE=gpu GTEST_TOTAL_SHARDS=$shards
    for ((i = 0; i < shards; i++)); do
      GTEST_SHARD_INDEX=$i timeout "${WETDEM_SHARD_TIMEOUT:-420}" "$B/wetdem_tests" --gtest_filter="$filter" \
        >"$OUT/shard-$i.log" 2>&1 &
    done
    wait
    cat "$OUT"/shard-*.log >"$OUT/tests.log"
    rm -f "$OUT"/shard-*.log
    echo "passed: $(grep -c '^\[       OK' "$OUT/tests.log"), failed: $(grep -c '^\[  FAILED  \].*(' "$OUT/tests.log")"
    grep '^\[  FAILED  \].*(' "$OUT/tests.log" | sort -u
    # A test that started and never ended was cut by the timeout.
    awk '/^\[ RUN/{r[$4]=1} /^\[       OK|^\[  FAILED/{delete r[$4]} END{for (t in r) print "unfinished: " t}' \
      "$OUT/tests.log"
    ;;
  bench) "$B/wetdem_bench" "$@" ;;
  wetdem) "$B/wetdem" "$@" ;;
  paper)
    WETDEM=$B/wetdem bash scripts/paper.sh "$@"
    # The device tool brings back neither deep trees nor many files (a study's runs/<hash>/frames/ are both), so
    # an export under $OUT comes back as one archive: DIR.tgz, unpacked here with tar xzf.
    ex=""
    prev=""
    for a in "$@"; do
      [[ $prev == --export ]] && ex=$a
      prev=$a
    done
    if [[ -n $ex && -d $ex && $(realpath "$ex") == $(realpath "$OUT")/* ]]; then
      tar czf "$ex.tgz" -C "$(dirname "$ex")" "$(basename "$ex")" && rm -rf "$ex" && echo "export packed: $ex.tgz"
    fi
    ;;
  script) WETDEM=$B/wetdem bash "$@" ;;
  *) echo "usage: $0 tests|bench|wetdem|paper|script ..." >&2; exit 2 ;;
esac
