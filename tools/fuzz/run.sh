#!/bin/sh
# Builds the fuzzers (tools/fuzz: the scene loader, fuzz_scene.cpp; the
# recording reader, fuzz_recording.cpp; the viewer's input scripts,
# fuzz_input_script.cpp) with clang into BUILD_DIR and runs them one after
# another for SECONDS in all: the input scripts a tenth of it, the
# recordings a quarter, the scene loader the rest. Seeds: the shipped
# scenes and the malformed ones (tests/data/bad_scenes), and
# tools/fuzz/seeds/; dictionaries beside this script. What they find is kept in BUILD_DIR/findings/ (crash-*, timeout-*,
# oom-*, prefixed recording- or input- for those two: replay one with
# `BUILD_DIR/fuzz_scene FILE`, or fuzz_recording, fuzz_input_script); the
# corpora they grow stay in BUILD_DIR/corpus, corpus-recording and
# corpus-input for the next run. Exit 0 when they found nothing, 77 (ctest's
# skip) without clang++, else the first failing fuzzer's exit code.
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
cmake --build "$build" --target fuzz_scene fuzz_recording fuzz_input_script -j "${FUZZ_JOBS:-1}"
echo "fuzz: built in $(($(date +%s) - start)) s"

# The seeds are copied into the corpora libFuzzer grows (it writes new inputs
# to its first directory, and reads directories recursively: scenes/ holds
# the code too).
mkdir -p "$build/corpus" "$build/corpus-recording" "$build/corpus-input" "$build/findings"
cp "$root"/scenes/*.toml "$root"/tests/data/bad_scenes/* "$build/corpus/"
cp "$root"/tools/fuzz/seeds/recording/* "$build/corpus-recording/"
cp "$root"/tools/fuzz/seeds/input/* "$build/corpus-input/"

# -timeout: an input whose load and 3 frames take longer is a hang (the
# loader refuses work over about a second a frame; the sanitizers slow a
# run down about tenfold). -rss_limit_mb: the loader's limits keep a scene
# far below it. -max_len: the largest shipped scene is 4 kB, the largest
# seed recording 64 kB.
status=0
fuzz() {  # NAME CORPUS SECONDS DICTIONARY MAX_LEN PREFIX [options...]
    name=$1 corpus=$2 time=$3 dict=$4 len=$5 prefix=$6
    shift 6
    echo "fuzz: $name for $time s"
    "$build/$name" "$corpus" -dict="$root/tools/fuzz/$dict" -max_total_time="$time" -timeout=30 \
        -rss_limit_mb=2560 -max_len="$len" -artifact_prefix="$build/findings/$prefix" -print_final_stats=1 "$@" ||
        { code=$?; [ $status -ne 0 ] || status=$code; }
}
# The input-script parser runs thousands of inputs a second, the scene
# loader a few (its seeds' first pass is much of its time): a tenth, a
# quarter and the rest; 0 would mean no limit, hence at least 1.
tenth=$((seconds >= 10 ? seconds / 10 : 1))
quarter=$((seconds >= 4 ? seconds / 4 : 1))
fuzz fuzz_input_script "$build/corpus-input" "$tenth" input.dict 4096 input- "$@"
fuzz fuzz_recording "$build/corpus-recording" "$quarter" recording.dict 65536 recording- "$@"
fuzz fuzz_scene "$build/corpus" $((seconds > tenth + quarter ? seconds - tenth - quarter : 1)) scene.dict 8192 "" "$@"
exit $status
