#include "sim/central_gravity.h"

#include "sim/cpu.h"
#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const CentralGravity& gravity, std::size_t) {
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(gravity.center[k])) {
            throw InputError("central_gravity.center must be finite, in m (got " + format_value(gravity.center[k]) +
                             ")");
        }
    }
    if (!(gravity.mu > 0.0) || !std::isfinite(gravity.mu)) {
        throw InputError("central_gravity.mu must be > 0 and finite, in m³/s² (got " + format_value(gravity.mu) + ")");
    }
}

namespace {

// The force loop: plain pointers and scalars, __restrict on the parameters
// (GCC ignores it on local pointers, and then gives up vectorising for the
// number of overlaps it would have to test), as the field pass has it. Its
// square root and division are most of a Kepler step.
//   f += -m μ d / r³                     (accumulate)
//   a = (f + -m μ d / r³) · (1/m)        (kToAcceleration: the step's M⁻¹ in
//                                         the same pass, the same products)
// kFromZero: f starts at +0 (no field force), added as the zero pass and
// accumulate would (+0 + -0 is +0: the addition stays). kAtOrigin: the
// centre is (+0, +0, +0), and d = x - c is x itself (x - +0 is x for every
// x, -0 and NaN included), so it is not computed.
// The loop is bound by its square root and division, and by how many of
// them can be in flight at once, which the latency around them limits:
// what waits on the division is kept short. The factor that silences the
// centre multiplies the numerator, not the quotient (the same bits: it is
// exactly 1 or 0, and the numerator is finite; tried on 5e7 random and
// special r² and masses); with the centre at the origin too, a Kepler batch
// of velocity Verlet went from 1.18 to 1.11-1.13 times odeint's step.
template <bool kFromZero, bool kToAcceleration, bool kAtOrigin>
[[gnu::always_inline]] inline void central_loop(const double* __restrict x, const double* __restrict y,
                                                const double* __restrict z, const double* __restrict m,
                                                const double* __restrict inv_m, double* __restrict fx,
                                                double* __restrict fy, double* __restrict fz, std::size_t n, double cx,
                                                double cy, double cz, double mu) {
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = kAtOrigin ? x[i] : x[i] - cx, dy = kAtOrigin ? y[i] : y[i] - cy,
                     dz = kAtOrigin ? z[i] : z[i] - cz;
        const double r2 = dx * dx + dy * dy + dz * dz;
        // -m μ / r³; at the centre (r = 0) no force: r² is replaced by 1
        // there and the result multiplied by 0, arithmetic rather than a
        // branch or a select (GCC vectorises neither around a division).
        // Elsewhere the factor is 1, which changes no bit.
        const double centre = static_cast<double>(r2 == 0.0);
        const double safe = r2 + centre;
        const double s = (1.0 - centre) * (-m[i] * mu) / (safe * std::sqrt(safe));
        double ax = (kFromZero ? 0.0 : fx[i]) + s * dx;
        double ay = (kFromZero ? 0.0 : fy[i]) + s * dy;
        double az = (kFromZero ? 0.0 : fz[i]) + s * dz;
        if constexpr (kToAcceleration) ax *= inv_m[i], ay *= inv_m[i], az *= inv_m[i];
        fx[i] = ax, fy[i] = ay, fz[i] = az;
    }
}

using CentralLoop = void (*)(const double*, const double*, const double*, const double*, const double*, double*,
                             double*, double*, std::size_t, double, double, double, double);

template <bool kFromZero, bool kToAcceleration, bool kAtOrigin, typename... A>
void central_base(A... a) {
    central_loop<kFromZero, kToAcceleration, kAtOrigin>(a...);
}

#if defined(__x86_64__) && defined(__GNUC__)
// Twice as wide where the CPU has AVX2 (chosen at run time, as the spring
// pass): square roots, divisions, products and sums are correctly rounded at
// any width and -ffp-contract=off forbids fusing, so both builds give the
// same bits (tests/sim/central_gravity_test.cpp). The square root and the
// division are what the wider registers speed up.
template <bool kFromZero, bool kToAcceleration, bool kAtOrigin, typename... A>
[[gnu::target("avx2")]] void central_avx2(A... a) {
    central_loop<kFromZero, kToAcceleration, kAtOrigin>(a...);
}
#endif

template <bool kFromZero, bool kToAcceleration, bool kAtOrigin>
CentralLoop central_build(bool wide) {
    using P = const double*;
    using Q = double*;
#if defined(__x86_64__) && defined(__GNUC__)
    if (wide)
        return &central_avx2<kFromZero, kToAcceleration, kAtOrigin, P, P, P, P, P, Q, Q, Q, std::size_t, double, double,
                             double, double>;
#endif
    (void)wide;
    return &central_base<kFromZero, kToAcceleration, kAtOrigin, P, P, P, P, P, Q, Q, Q, std::size_t, double, double,
                         double, double>;
}

// The centre at (+0, +0, +0), bit for bit (a -0 would turn x = -0 into +0).
bool at_origin(const CentralGravity& gravity) {
    for (int k = 0; k < 3; ++k) {
        if (gravity.center[k] != 0.0 || std::signbit(gravity.center[k])) return false;
    }
    return true;
}

template <bool kFromZero, bool kToAcceleration>
CentralLoop central_pass(const CentralGravity& gravity, bool wide) {
    return at_origin(gravity) ? central_build<kFromZero, kToAcceleration, true>(wide)
                              : central_build<kFromZero, kToAcceleration, false>(wide);
}

void run(CentralLoop loop, const CentralGravity& gravity, const ForceInput& in, Vec3Span f) {
    loop(in.x.c[0], in.x.c[1], in.x.c[2], in.mass, in.inv_mass, f.c[0], f.c[1], f.c[2], f.n, gravity.center.x(),
         gravity.center.y(), gravity.center.z(), gravity.mu);
}

}  // namespace

void accumulate(const CentralGravity& gravity, const ForceInput& in, Vec3Span f, bool wide) {
    run(central_pass<false, false>(gravity, wide), gravity, in, f);
}

void accumulate(const CentralGravity& gravity, const ForceInput& in, Vec3Span f) {
    accumulate(gravity, in, f, avx2_available());
}

void to_acceleration(const CentralGravity& gravity, const ForceInput& in, Vec3Span a, bool from_zero, bool wide) {
    run(from_zero ? central_pass<true, true>(gravity, wide) : central_pass<false, true>(gravity, wide), gravity, in, a);
}

double potential_energy(const CentralGravity& gravity, const ForceInput& in) {
    double u = 0.0;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const double r = (in.x.get(i) - gravity.center).norm();
        if (in.inv_mass[i] != 0.0 && r > 0.0) {
            u -= in.mass[i] * gravity.mu / r;
        }
    }
    return u;
}

void accumulate_jacobians(const CentralGravity& gravity, const ForceInput& in, Jacobians& jac) {
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const Vec3 d = in.x.get(i) - gravity.center;
        const double r2 = d.squaredNorm();
        if (r2 == 0.0) {
            continue;
        }
        const double r = std::sqrt(r2);
        const Eigen::Matrix3d k = -in.mass[i] * gravity.mu *
                                  (Eigen::Matrix3d::Identity() / (r2 * r) - 3.0 * d * d.transpose() / (r2 * r2 * r));
        Jacobians::add(jac.dfdx, i, i, k);
    }
}

}  // namespace sim
