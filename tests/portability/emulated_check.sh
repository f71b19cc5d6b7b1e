#!/bin/sh
# The golden checks' state hashes on another x86-64 CPU, emulated by
# qemu-user: Nehalem (SSE4.2, no AVX, no FMA: glibc's SSE2 libm, our pinned
# builds) or Haswell (AVX2 and FMA). Physics only (nothing rendered: the
# emulated llvmpipe would draw with other vector widths, and take minutes).
# Skipped (exit 77) where qemu-x86_64 is not installed.
#   emulated_check.sh PLAUSIBLE CPU REPORT_DIR
set -eu
plausible=$1
cpu=$2
report=$3
if ! command -v qemu-x86_64 >/dev/null 2>&1; then
  echo "emulated_check: qemu-x86_64 not found (Debian package qemu-user): skipped"
  exit 77
fi
exec qemu-x86_64 -cpu "$cpu" "$plausible" check --physics-only --report "$report"
