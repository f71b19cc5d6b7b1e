// The one question sim asks of the CPU. A few passes (the spring pass, central
// gravity, the watchdog's count, the integrators' loops, M⁻¹) are compiled
// twice: for the pinned instruction set (x86-64-v2) and for AVX2, called only
// where the CPU has it.
// Square roots, divisions, products and sums are correctly rounded at any
// width and -ffp-contract=off forbids fusing, so both builds give the same
// bits (their tests run both).
#pragma once

#include <utility>

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

// Runs f(args...) built for AVX2 where `wide`, else for the pinned set: f
// and everything it calls is inlined into the wrapper (flatten), so that its
// loops are vectorised at that width. For short, hot loops over particle
// arrays (the integrators' passes); `wide` is avx2_available() or false.
template <class F, class... A>
[[gnu::flatten]] inline void run_pinned(const F& f, A... a) {
    f(a...);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <class F, class... A>
[[gnu::target("avx2"), gnu::flatten]] inline void run_avx2(const F& f, A... a) {
    f(a...);
}
#endif
template <class F, class... A>
inline void run_at_width(bool wide, const F& f, A... a) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (wide) {
        run_avx2(f, a...);
        return;
    }
#endif
    (void)wide;
    run_pinned(f, a...);
}

}  // namespace sim
