// The elementary functions whose results glibc picks by CPU (an FMA/AVX2
// build or an SSE2 one, through ifunc: docs/libm-study.md), replaced by one
// implementation with the same bits on every x86-64 CPU: SLEEF's scalar
// "cinz" functions (Debian's libsleef), written in plain C with no fused
// multiply-add and documented as bit-wise consistent across platforms, at
// their 1.0-ulp accuracy (tests/sim/portable_math_test.cpp holds them to
// glibc's within 2 ulp).
//
// These are the C library's own names. Every executable that links sim
// carries them (sim/CMakeLists.txt: whole archive, since nothing names them)
// and exports them (portable_math.list), so that our calls and ODE's (its
// hinge and motor angles: atan2; its rotations: sincos, asin, acos) reach
// them: the dynamic linker binds a shared library's imports to the
// executable's definitions first. Built with -fno-builtin, so that the
// compiler does not turn a call here back into one of these names.
#include <sleef.h>

extern "C" {

double sin(double x) noexcept { return Sleef_cinz_sind1_u10purec(x); }
double cos(double x) noexcept { return Sleef_cinz_cosd1_u10purec(x); }
// sin and cos, each as above: compilers merge sin(x) and cos(x) into one
// sincos call where they see both, which must not change the bits.
void sincos(double x, double* s, double* c) noexcept {
    *s = Sleef_cinz_sind1_u10purec(x);
    *c = Sleef_cinz_cosd1_u10purec(x);
}
double asin(double x) noexcept { return Sleef_cinz_asind1_u10purec(x); }
double acos(double x) noexcept { return Sleef_cinz_acosd1_u10purec(x); }
double atan2(double y, double x) noexcept { return Sleef_cinz_atan2d1_u10purec(y, x); }
double exp(double x) noexcept { return Sleef_cinz_expd1_u10purec(x); }
double log(double x) noexcept { return Sleef_cinz_logd1_u10purec(x); }
double pow(double x, double y) noexcept { return Sleef_cinz_powd1_u10purec(x, y); }

}  // extern "C"
