#!/bin/sh
# The viewer's time a frame, as issue 21 measures it: SCENE in a window of
# SIZE (under xvfb-run where there is no display), running one scene step a
# drawn frame (an input script, as the view tests drive it), closed at frame
# 30 and again, in a second run, at frame 150. The time a frame is the
# difference over the 120 frames between: start-up and the first frames
# (the window, the targets, the shaders) cancel out. REPEATS pairs (default
# 2), a line each; options after SIZE go to view (--render-scale 1: whole
# frames; --msaa 4). Wall-clock figures: compare runs made together.
#   usage: tools/viewer-frame-time.sh PLAUSIBLE SCENE [SIZE [view options...]]
#   e.g.   tools/viewer-frame-time.sh build/plausible showcase 1280x720 --no-panel
# Environment: REPEATS.
set -eu

if [ $# -lt 2 ]; then
    echo "usage: $0 PLAUSIBLE SCENE [WIDTHxHEIGHT [view options...]]" >&2
    exit 2
fi
plausible=$1
scene=$2
size=${3:-1280x720}
if [ $# -ge 3 ]; then shift 3; else shift 2; fi
width=${size%x*}
height=${size#*x}

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "30 key Escape" > "$dir/30.txt"
echo "150 key Escape" > "$dir/150.txt"

# Nanoseconds the viewer takes to show N frames and close: run N [view options...].
run() {
    n=$1
    shift
    start=$(date +%s%N)
    if [ -n "${DISPLAY:-}" ]; then
        "$plausible" view "$scene" --size "$size" --input "$dir/$n.txt" "$@" > "$dir/log" 2>&1
    else
        xvfb-run -a -s "-screen 0 ${width}x${height}x24" \
            "$plausible" view "$scene" --size "$size" --input "$dir/$n.txt" "$@" > "$dir/log" 2>&1
    fi || { cat "$dir/log" >&2; exit 1; }
    echo $(($(date +%s%N) - start))
}

for k in $(seq "${REPEATS:-2}"); do
    t30=$(run 30 "$@")
    t150=$(run 150 "$@")
    awk -v a="$t30" -v b="$t150" -v k="$k" -v s="$scene" -v z="$size" \
        'BEGIN { printf "viewer-frame-time: %s %s, run %d: %.1f ms a frame (frames 30 to 150)\n", s, z, k, (b - a) / 120 / 1e6 }'
    tail -1 "$dir/log"
done
