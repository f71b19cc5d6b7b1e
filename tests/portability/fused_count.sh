#!/bin/sh
# Our own code fuses no multiply-add on any architecture (docs/design.md rule
# 6): cross-compiles every physics source for arm64, where FMA is always
# there, with the flags and definitions the build would use on arm64 (passed
# in by CMake), and counts the fused instructions (fmadd, fmsub, fnmadd,
# fnmsub, fmla, fmls) in the objects. Any is a failure, named by file.
# Eigen's NEON code calls vfmaq_f64 itself whatever -ffp-contract says, so
# this is what shows the definitions work. -O2: GCC contracts a*b + c from -O2
# on, so a lost -ffp-contract=off shows too (at -O1 it would not).
# Skipped (exit 77) without a cross compiler (Debian's g++-aarch64-linux-gnu,
# which make does not install: the check is for machines that have it).
#   fused_count.sh SOURCE_DIR OUT_DIR "FLAGS" "DEFINITIONS"
set -eu
src=$1
out=$2
flags=$3
defs=$4
cxx=aarch64-linux-gnu-g++
if ! command -v "$cxx" >/dev/null 2>&1; then
  echo "fused_count: $cxx not found (Debian package g++-aarch64-linux-gnu): skipped"
  exit 77
fi
mkdir -p "$out"
dflags=""
for d in $defs; do dflags="$dflags -D$d"; done
# The cross compiler's own headers first; Eigen, ODE and SLEEF's (header
# only, or architecture-neutral) from the host after them.
# shellcheck disable=SC2086 # the flag lists are meant to split
ls "$src"/sim/*.cpp | grep -v portable_math | xargs -P 2 -I{} sh -c \
  "$cxx -std=c++20 -O2 $flags $dflags -I'$src' -idirafter /usr/include/eigen3 -idirafter /usr/include \
   -c {} -o '$out'/\$(basename {} .cpp).o"
total=0
for obj in "$out"/*.o; do
  n=$(aarch64-linux-gnu-objdump -d "$obj" | grep -cE '[[:space:]](fmadd|fmsub|fnmadd|fnmsub|fmla|fmls)[[:space:]]' || true)
  [ "$n" -eq 0 ] || echo "fused_count: $(basename "$obj" .o).cpp: $n fused multiply-add instructions on arm64"
  total=$((total + n))
done
echo "fused_count: $(ls "$out"/*.o | wc -l) objects, $total fused multiply-add instructions (definitions: ${defs:-none})"
[ "$total" -eq 0 ]
