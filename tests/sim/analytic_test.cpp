// The closed forms checked against their own differential equations and
// conservation laws, so that the integrators are measured against something
// independently right.
#include "sim/analytic.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace sim::analytic {
namespace {

TEST(Ballistic, FollowsTheLecturesParabola) {
    // p(t) = (vx t, vy t - 9.8/2 t²) from the origin
    const auto s = ballistic(Vec3::Zero(), Vec3(3, 4, 0), Vec3(0, -9.8, 0), 0.5);
    EXPECT_NEAR(s.x.x(), 1.5, 1e-15) << "m";
    EXPECT_NEAR(s.x.y(), 4 * 0.5 - 4.9 * 0.25, 1e-15) << "m";
    EXPECT_NEAR(s.v.y(), 4 - 9.8 * 0.5, 1e-15) << "m/s";
}

// Central-difference check of m x'' + c x' + k x = 0 and of v = x'.
void expect_solves_oscillator(const Oscillator& o) {
    const Vec3 x0(1.0, -0.5, 0.2), v0(0.3, 2.0, -1.0);
    const double h = 1e-4;
    for (double t : {0.0, 0.7, 2.5, 6.0}) {
        const auto s = oscillator(o, x0, v0, t + h);
        const auto m = oscillator(o, x0, v0, t + (t > 0 ? 0.0 : h));
        const auto a = oscillator(o, x0, v0, t + (t > 0 ? -h : 0.0));
        if (t == 0.0) {
            EXPECT_LT((oscillator(o, x0, v0, 0.0).x - x0).norm(), 1e-14);
            EXPECT_LT((oscillator(o, x0, v0, 0.0).v - v0).norm(), 1e-14);
            continue;
        }
        const Vec3 xdd = (s.x - 2 * m.x + a.x) / (h * h);
        const Vec3 xd = (s.x - a.x) / (2 * h);
        EXPECT_LT((o.mass * xdd + o.damping * m.v + o.stiffness * m.x).norm(), 1e-5) << "N, residual at t = " << t;
        EXPECT_LT((xd - m.v).norm(), 1e-7) << "m/s at t = " << t;
    }
}

TEST(Oscillator, SolvesItsEquationInEveryRegime) {
    expect_solves_oscillator({1.0, 4.0, 0.0});  // undamped
    expect_solves_oscillator({2.0, 3.0, 0.8});  // underdamped
    expect_solves_oscillator({1.0, 4.0, 4.0});  // critical: c = 2 sqrt(k m)
    expect_solves_oscillator({1.0, 4.0, 9.0});  // overdamped
}

TEST(Kepler, ConservesEnergyAndAngularMomentum) {
    const double mu = 2.5;
    const Vec3 r0(1.2, 0.1, -0.3), v0(0.2, 1.1, 0.4);
    const double e0 = 0.5 * v0.squaredNorm() - mu / r0.norm();
    const Vec3 h0 = r0.cross(v0);
    for (double t : {0.3, 1.7, 4.0, 11.0, 40.0}) {
        const auto s = kepler(mu, r0, v0, t);
        EXPECT_NEAR(0.5 * s.v.squaredNorm() - mu / s.x.norm(), e0, 1e-12) << "J/kg at t = " << t;
        EXPECT_LT((s.x.cross(s.v) - h0).norm(), 1e-12) << "m²/s at t = " << t;
    }
}

TEST(Kepler, ReturnsAfterOnePeriodAndSolvesTheEquation) {
    for (double e : {0.0, 0.5, 0.9}) {
        const Vec3 r0(1.0 - e, 0, 0), v0(0, std::sqrt((1 + e) / (1 - e)), 0);
        const OrbitElements el = orbit_elements(1.0, r0, v0);
        EXPECT_NEAR(el.e, e, 1e-12);
        EXPECT_NEAR(el.period, 2 * std::numbers::pi, 1e-12) << "s";
        const auto back = kepler(1.0, r0, v0, el.period);
        EXPECT_LT((back.x - r0).norm(), 1e-11) << "m, e = " << e;
        // r'' = -μ r / |r|³ by central differences
        const double h = 1e-4, t = 1.234;
        const auto a = kepler(1.0, r0, v0, t - h), m = kepler(1.0, r0, v0, t), b = kepler(1.0, r0, v0, t + h);
        const Vec3 rdd = (b.x - 2 * m.x + a.x) / (h * h);
        EXPECT_LT((rdd + m.x / std::pow(m.x.norm(), 3)).norm(), 1e-5) << "m/s², e = " << e;
    }
}

TEST(Kepler, RefusesUnboundOrbits) { EXPECT_THROW(kepler(1.0, Vec3(1, 0, 0), Vec3(0, 2, 0), 1.0), std::domain_error); }

TEST(Pendulum, SmallAngleAndExactPeriodAgreeForSmallAmplitude) {
    const double length = 2.0, g = 9.81;
    const double t_small = 2 * std::numbers::pi * std::sqrt(length / g);
    const auto s = small_angle_pendulum(length, g, 0.01, 0.0, t_small);
    EXPECT_NEAR(s.theta, 0.01, 1e-15) << "rad after one period";
    // T(θ0) = T0 (1 + θ0²/16 + 11 θ0⁴/3072 + 173 θ0⁶/737280 + O(θ0⁸)); the
    // next term is 4e-11 s here
    const double theta0 = 0.2;
    EXPECT_NEAR(
        pendulum_period(length, g, theta0),
        t_small * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072 + 173 * std::pow(theta0, 6) / 737280),
        1e-9)
        << "s";
    // A pendulum released horizontally: T = 1.18034 T0 (tabulated K(1/√2) = 1.854075)
    EXPECT_NEAR(pendulum_period(length, g, std::numbers::pi / 2) / t_small, 2 * 1.8540746773013719 / std::numbers::pi,
                1e-12);
}

}  // namespace
}  // namespace sim::analytic
