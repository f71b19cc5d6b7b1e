#!/bin/bash
# Issue 21's check on a machine with a GPU, as one script: which EGL devices
# are found, bench_video (it takes the fastest context: the GPU), the showcase
# as a video at 1280x720 and 1920x1080 (--verbose: pass by pass) beside ffmpeg
# alone encoding the same frames, one frame rendered on the GPU, and check on
# the GPU against the (llvmpipe) goldens, judged with another renderer's
# tolerance. Every step runs even when one before failed; each says its exit
# status. Everything goes to OUT: log.txt, bench_video.json, check.json
# (and the whole report, check-report.tgz), showcase-gpu.png.
#   usage: tools/gpu-check.sh PLAUSIBLE BENCH_VIDEO OUT
#   e.g.   tools/gpu-check.sh build/plausible build/bench_video /tmp/gpu
# ffmpeg is the one on PATH; STEP_LIMIT (default 240) caps each step, s.
set -u

if [ $# -ne 3 ]; then
    echo "usage: $0 PLAUSIBLE BENCH_VIDEO OUT" >&2
    exit 2
fi
plausible=$1
bench_video=$2
out=$3
limit=${STEP_LIMIT:-240}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
log="$out/log.txt"

# step NAME COMMAND...: runs it under the limit, its output into the log, and
# says how long it took and how it ended.
step() {
    name=$1
    shift
    echo "== $name: $*" >> "$log"
    start=$(date +%s.%N)
    timeout "$limit" "$@" >> "$log" 2>&1
    status=$?
    end=$(date +%s.%N)
    echo "== $name: exit $status, $(awk "BEGIN { print $end - $start }") s" >> "$log"
    echo "$name: exit $status"
}

# The showcase at SIZE, timed pass by pass (each pass waits for the GPU), then
# whole (the frames/s to compare), then ffmpeg alone on its frames (decoded
# back to raw) with the same encoding command.
video_against_encoder() {
    size=$1
    clip="$work/showcase-$size.mp4"
    step "video $size, pass by pass" "$plausible" video showcase -o "$clip" --size "$size" --fps 30 --verbose
    rm -f "$clip"
    step "video $size" "$plausible" video showcase -o "$clip" --size "$size" --fps 30
    [ -f "$clip" ] || return
    ffmpeg -nostdin -loglevel error -y -i "$clip" -f rawvideo -pix_fmt rgb24 "$work/frames.rgb" >> "$log" 2>&1
    if [ ! -s "$work/frames.rgb" ]; then
        echo "== ffmpeg alone $size: the video could not be decoded" >> "$log"
        return
    fi
    frames=$(($(stat -c %s "$work/frames.rgb") / (3 * ${size%x*} * ${size#*x})))
    start=$(date +%s.%N)
    # scenes::ffmpeg_command's encoding, as video runs it (bench_video calls it).
    ffmpeg -y -nostdin -loglevel error -f rawvideo -pix_fmt rgb24 -s "$size" -r 30 -i - -c:v libx264 \
        -preset medium -crf 20 -pix_fmt yuv420p -colorspace bt709 -color_primaries bt709 -color_trc bt709 \
        -color_range tv -movflags +faststart -f mp4 "$work/alone.mp4" < "$work/frames.rgb" >> "$log" 2>&1
    end=$(date +%s.%N)
    awk "BEGIN { printf \"== ffmpeg alone $size: $frames frames in %.2f s, %.1f frames/s\\n\", \
        $end - $start, $frames / ($end - $start) }" >> "$log"
    rm -f "$work/frames.rgb"
}

{
    echo "== $(date -u) on $(uname -srm), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
    nvidia-smi -L 2>&1 || echo "(no nvidia-smi)"
    ffmpeg -version 2>&1 | head -1
} >> "$log"
step "backends" "$plausible" render --backend list
step "bench_video" "$bench_video" --benchmark_out="$out/bench_video.json" --benchmark_out_format=json
video_against_encoder 1280x720
video_against_encoder 1920x1080
step "render on the gpu" "$plausible" render showcase --backend gpu --frames 120 --size 1280x720 --out "$work/render"
find "$work/render" -name '*.png' | sort | tail -1 | xargs -r -I{} cp {} "$out/showcase-gpu.png"
step "check on the gpu" "$plausible" check --backend gpu --report "$work/check"
cp "$work/check/report.json" "$out/check.json" 2>/dev/null
tar czf "$out/check-report.tgz" -C "$work" check 2>/dev/null
echo "== done $(date -u), load $(cut -d' ' -f1-3 /proc/loadavg)" >> "$log"
