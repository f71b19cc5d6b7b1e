#!/bin/sh
# The golden checks as a CPU without FMA and AVX2 runs them: glibc's libm then
# takes its SSE2 builds of sin, atan2, ... (chosen at run time by CPU), which
# round differently from its FMA builds on some arguments. The physics calls
# none of them (sim/portable_math.cpp takes their names, for ODE too), so
# every state hash must still match (docs/design.md rule 7).
#   masked_check.sh PLAUSIBLE REPORT_DIR
set -eu
plausible=$1
report=$2
mask=glibc.cpu.hwcaps=-FMA,-AVX2
loader=$(ldd "$plausible" | sed -n 's/^[[:space:]]*\(\/[^ ]*ld-linux[^ ]*\).*/\1/p' | head -n 1)
# The mask takes effect (a misspelt one is ignored in silence): ld.so then no
# longer lists x86-64-v3 (AVX2 and FMA) as supported.
if GLIBC_TUNABLES=$mask "$loader" --help | grep -q 'x86-64-v3 (supported'; then
  echo "masked_check: GLIBC_TUNABLES=$mask did not mask FMA/AVX2 (ld.so still supports x86-64-v3)" >&2
  exit 1
fi
if ! "$loader" --help | grep -q 'x86-64-v3 (supported'; then
  echo "masked_check: this CPU has no FMA/AVX2: the unmasked golden run already tests the SSE2 builds"
fi
GLIBC_TUNABLES=$mask exec "$plausible" check --report "$report"
