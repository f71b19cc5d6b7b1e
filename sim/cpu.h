// The one question sim asks of the CPU. A few passes (the spring pass, central
// gravity, the watchdog's count) are compiled twice: for the pinned
// instruction set (x86-64-v2) and for AVX2, called only where the CPU has it.
// Square roots, divisions, products and sums are correctly rounded at any
// width and -ffp-contract=off forbids fusing, so both builds give the same
// bits (their tests run both).
#pragma once

namespace sim {

// True when this CPU runs the AVX2 builds; asked once.
inline bool avx2_available() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return available;
#else
    return false;
#endif
}

}  // namespace sim
