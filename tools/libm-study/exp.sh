#!/bin/bash
# exp.sh LABEL [ENV=VAL ...] -- [scenes...]: run `plausible check` (copy of /work/main/build/plausible) with the
# given environment into reports/LABEL, print the failing scenes.
cd "$(dirname "$0")"
label=$1; shift; envs=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do envs+=("$1"); shift; done; shift
mkdir -p reports logs
env SHIM_QUIET=1 "${envs[@]}" nice -n 15 ./plausible check --report reports/$label "$@" > logs/$label.txt 2>&1
echo "== $label: ${envs[*]}"; grep -v ' pass ' logs/$label.txt | sed -E 's/; image.*//' 
