// sim/portable_math.cpp: the elementary functions every executable that links
// sim carries and exports under the C library's names. Checked here: that
// they are the ones called (by this executable and, through the dynamic
// linker, by shared libraries such as ODE), that sincos gives sin's and
// cos's bits, and that each stays within 2 ulp of glibc's libm (each side
// within about 1 ulp of the true value) over the ranges the physics uses and
// beyond.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include <dlfcn.h>

namespace {

// glibc's libm, loaded by name: its own definitions, not the executable's.
void* libm() {
    static void* handle = dlopen("libm.so.6", RTLD_NOW | RTLD_LOCAL);
    return handle;
}
template <class F>
F glibc(const char* name) {
    return reinterpret_cast<F>(dlsym(libm(), name));
}

// Distance in units in the last place between two finite doubles of one sign.
std::int64_t ulps(double a, double b) {
    if (a == b) return 0;
    std::int64_t ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    if ((ia < 0) != (ib < 0)) return std::numeric_limits<std::int64_t>::max();
    return ia > ib ? ia - ib : ib - ia;
}

// Evenly spread samples of [lo, hi], plus a fixed-seed jitter inside each step.
template <class Each>
void sweep(double lo, double hi, int count, Each each) {
    std::uint64_t state = 0x9e3779b97f4a7c15ULL;
    for (int i = 0; i < count; ++i) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        const double u = static_cast<double>(state >> 11) * 0x1.0p-53;
        each(lo + (hi - lo) * ((i + u) / count));
    }
}

constexpr std::int64_t kUlps = 2;  // ours against glibc's, each about 1 ulp from the truth

TEST(PortableMath, TheExecutableExportsItsOwnDefinitions) {
    // The global scope (the executable first, then its libraries in load
    // order) finds the executable's definitions: a shared library's import
    // of these names binds to them too (ODE's atan2, sincos, asin, acos).
    for (const char* name : {"sin", "cos", "sincos", "asin", "acos", "atan2", "exp", "log", "pow"}) {
        void* global = dlsym(RTLD_DEFAULT, name);
        ASSERT_NE(global, nullptr) << name;
        EXPECT_NE(global, dlsym(libm(), name)) << name << " resolves to glibc's libm, not to sim/portable_math.cpp";
        Dl_info info{};
        ASSERT_NE(dladdr(global, &info), 0) << name;
        EXPECT_EQ(std::string(info.dli_fname).find("libm.so"), std::string::npos)
            << name << " is in " << info.dli_fname;
    }
}

TEST(PortableMath, SincosGivesSinAndCosBits) {
    sweep(-100.0, 100.0, 20000, [](double x) {
        double s = 0.0, c = 0.0;
        sincos(x, &s, &c);
        const double sin_x = sin(x), cos_x = cos(x);  // NOLINT: the C names on purpose
        EXPECT_EQ(std::memcmp(&s, &sin_x, sizeof s), 0) << "x = " << x;
        EXPECT_EQ(std::memcmp(&c, &cos_x, sizeof c), 0) << "x = " << x;
    });
}

TEST(PortableMath, WithinTwoUlpsOfGlibc) {
    using F1 = double (*)(double);
    using F2 = double (*)(double, double);
    struct One {
        const char* name;
        F1 ours;
        double lo, hi;
    };
    // Ranges: what the scenes use (angles, unit-vector components, Box-Muller
    // logs) and wider.
    const One ones[] = {
        {"sin", &::sin, -1e4, 1e4},   {"cos", &::cos, -1e4, 1e4},     {"asin", &::asin, -1.0, 1.0},
        {"acos", &::acos, -1.0, 1.0}, {"exp", &::exp, -700.0, 700.0}, {"log", &::log, 1e-300, 1e300},
        {"log", &::log, 1e-3, 10.0},
    };
    for (const One& f : ones) {
        const F1 theirs = glibc<F1>(f.name);
        ASSERT_NE(theirs, nullptr) << f.name;
        std::int64_t worst = 0;
        double at = 0.0;
        sweep(f.lo, f.hi, 200000, [&](double x) {
            const std::int64_t d = ulps(f.ours(x), theirs(x));
            if (d > worst) worst = d, at = x;
        });
        EXPECT_LE(worst, kUlps) << f.name << " over [" << f.lo << ", " << f.hi << "]: " << worst
                                << " ulp at x = " << at;
    }
    const F2 atan2_glibc = glibc<F2>("atan2"), pow_glibc = glibc<F2>("pow");
    ASSERT_NE(atan2_glibc, nullptr);
    ASSERT_NE(pow_glibc, nullptr);
    std::int64_t worst_atan2 = 0, worst_pow = 0;
    sweep(-1.0, 1.0, 600, [&](double y) {
        sweep(-1.0, 1.0, 600,
              [&](double x) { worst_atan2 = std::max(worst_atan2, ulps(::atan2(y, x), atan2_glibc(y, x))); });
    });
    sweep(1e-3, 1e3, 600, [&](double x) {
        sweep(-20.0, 20.0, 600, [&](double y) { worst_pow = std::max(worst_pow, ulps(::pow(x, y), pow_glibc(x, y))); });
    });
    EXPECT_LE(worst_atan2, kUlps) << "atan2 over y, x in [-1, 1]";
    EXPECT_LE(worst_pow, kUlps) << "pow over x in [1e-3, 1e3], y in [-20, 20]";
}

TEST(PortableMath, SpecialValuesAsGlibc) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(std::isnan(::sin(inf)));
    EXPECT_TRUE(std::isnan(::log(-1.0)));
    EXPECT_TRUE(std::isnan(::asin(1.5)));
    EXPECT_EQ(::log(0.0), -inf);
    EXPECT_EQ(::exp(1000.0), inf);
    EXPECT_EQ(::exp(-1000.0), 0.0);
    EXPECT_EQ(::atan2(0.0, -1.0), glibc<double (*)(double, double)>("atan2")(0.0, -1.0));
    EXPECT_EQ(::pow(2.0, 10.0), 1024.0);
    EXPECT_EQ(::sin(0.0), 0.0);
    EXPECT_EQ(::cos(0.0), 1.0);
}

}  // namespace
