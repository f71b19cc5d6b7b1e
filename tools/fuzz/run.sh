#!/bin/sh
# Builds the scene loader's fuzzer (tools/fuzz/fuzz_scene.cpp) with clang into
# BUILD_DIR and runs it for SECONDS on the shipped scenes and the malformed
# ones (tests/data/bad_scenes) as seeds, with the loader's keys as a
# dictionary (tools/fuzz/scene.dict). What it finds is kept in
# BUILD_DIR/findings/ (crash-*, timeout-*, oom-*: replay one with
# `BUILD_DIR/fuzz_scene FILE`); the corpus it grows stays in BUILD_DIR/corpus
# for the next run. Exit 0 when it found nothing, 77 (ctest's skip) without
# clang++, else libFuzzer's exit code.
#   usage: tools/fuzz/run.sh SECONDS BUILD_DIR [libFuzzer options...]
# Environment: FUZZ_JOBS, the build's parallel jobs (default 1: inside
# `make test` it builds beside the other tests); FUZZ_OPT, the optimisation
# level of a build configured now (default -O1; make test's smoke: -O0).
set -eu

if [ $# -lt 2 ]; then
    echo "usage: $0 SECONDS BUILD_DIR [libFuzzer options...]" >&2
    exit 2
fi
seconds=$1
build=$2
shift 2
root=$(cd "$(dirname "$0")/../.." && pwd)

if ! command -v clang++ >/dev/null 2>&1; then
    echo "fuzz: skipped: clang++ not found (Debian: apt-get install clang libclang-rt-dev)"
    exit 77
fi

# Each library as one unity translation unit (batch size 0): this build has
# one job beside make test's other tests, so fewer, larger units cost least
# (measured: 128 CPU-seconds against 209 in batches of eight).
if [ ! -f "$build/build.ninja" ]; then
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLAUSIBLE_FUZZ=ON \
        -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DPLAUSIBLE_FUZZ_OPT="${FUZZ_OPT:--O1}" \
        -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=0 >/dev/null
fi
start=$(date +%s)
cmake --build "$build" --target fuzz_scene -j "${FUZZ_JOBS:-1}"
echo "fuzz: built in $(($(date +%s) - start)) s"

# The seeds are copied into the corpus libFuzzer grows (it writes new inputs
# to its first directory, and reads directories recursively: scenes/ holds
# the code too).
mkdir -p "$build/corpus" "$build/findings"
cp "$root"/scenes/*.toml "$root"/tests/data/bad_scenes/* "$build/corpus/"

# -timeout: an input whose load and 3 frames take longer is a hang (the
# loader refuses work over about a second a frame; the sanitizers slow a
# run down about tenfold). -rss_limit_mb: the loader's limits keep a scene
# far below it. -max_len: the largest shipped scene is 4 kB.
exec "$build/fuzz_scene" "$build/corpus" -dict="$root/tools/fuzz/scene.dict" \
    -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2560 -max_len=8192 \
    -artifact_prefix="$build/findings/" -print_final_stats=1 "$@"
