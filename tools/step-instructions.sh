#!/bin/sh
# The fixed cost of a World step in instructions (issue 17): the fixed-cost
# bead (one particle on one spring) stepped by STEP_COST (the build's
# step_cost) under callgrind, STEPS and 2 x STEPS steps (default 100000),
# once per METHOD (default symplectic_euler velocity_verlet rk4); the
# difference over the extra steps is what one step executes, start-up and
# the World's construction cancelled out. Unlike a time it does not move
# with the machine's load: compare it before and after a change, then time
# the change with bench_sim's FixedCost (fewer instructions can still be
# slower: docs/fixed-cost-study.md). Needs valgrind (Debian's package).
#   usage: tools/step-instructions.sh STEP_COST [METHOD...]
#   e.g.   tools/step-instructions.sh build/step_cost rk4
# Environment: STEPS.
set -eu

if [ $# -lt 1 ] || [ ! -x "$1" ]; then
    echo "usage: $0 STEP_COST [METHOD...]   (STEP_COST: the build's step_cost)" >&2
    exit 2
fi
if ! command -v valgrind > /dev/null; then
    echo "$0: needs valgrind (apt-get install valgrind)" >&2
    exit 2
fi
step_cost=$1
case $step_cost in */*) ;; *) step_cost=./$step_cost ;; esac  # valgrind searches PATH for a bare name
shift
[ $# -gt 0 ] || set -- symplectic_euler velocity_verlet rk4
steps=${STEPS:-100000}

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# Instructions of a whole run of step_cost METHOD N.
count() {
    valgrind --tool=callgrind --error-exitcode=3 --callgrind-out-file="$dir/out" "$step_cost" "$1" "$2" \
        > "$dir/log" 2>&1 || { status=$?; grep -v '^==' "$dir/log" >&2; exit "$status"; }
    sed -n 's/^summary: *//p' "$dir/out"
}

for method in "$@"; do
    one=$(count "$method" "$steps")
    two=$(count "$method" $((2 * steps)))
    if [ -z "$one" ] || [ -z "$two" ]; then
        echo "$0: callgrind wrote no instruction summary for $method" >&2
        exit 1
    fi
    awk -v a="$one" -v b="$two" -v n="$steps" -v m="$method" \
        'BEGIN { printf "step-instructions: %s, %.0f instructions a step (%d steps)\n", m, (b - a) / n, n }'
done
