// A shock wave pushes once, as its front passes: the impulse on a particle
// held still equals strength (r_ref / r)² thickness / speed.
#include "sim/shock_wave.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace sim::test {
namespace {

Vec3 force_at(const ShockWave& s, const Vec3& p, double t) {
    Vec3Array x(1), v(1), f(1);
    x.set(0, p);
    const double mass = 1.0, inv = 1.0;
    accumulate(s, {t, 0, x.span(), v.span(), &mass, &inv}, f.span());
    return f.get(0);
}

TEST(ShockWave, TheImpulseOfAPassingFront) {
    ShockWave s;
    s.center = Vec3(1, 0, 0);
    s.start_time = 0.5;
    s.speed = 20.0;
    s.thickness = 0.4;
    s.strength = 300.0;
    const Vec3 p(1, 0, 2);  // 2 m from the centre, along +z
    Vec3 impulse = Vec3::Zero();
    const double h = 1e-6;
    for (double t = 0.0; t < 1.0; t += h) impulse += force_at(s, p, t + 0.5 * h) * h;  // midpoint rule
    const double expected = 300.0 * 0.25 * 0.4 / 20.0;                                 // N·s
    // The midpoint sum misses or adds at most one step of 18.75 N at each edge
    // of the 20 ms window: 2 · 18.75 N · 1 µs ≈ 4e-5 N·s.
    EXPECT_NEAR(impulse.z(), expected, 1e-4) << "N·s";
    EXPECT_NEAR(impulse.x(), 0.0, 1e-12) << "radial: along +z only";
    EXPECT_NEAR(impulse.y(), 0.0, 1e-12) << "radial: along +z only";
    EXPECT_EQ(force_at(s, p, 0.5 + 1.7 / 20.0), Vec3::Zero()) << "before the front arrives";
    EXPECT_EQ(force_at(s, p, 0.5 + 2.3 / 20.0), Vec3::Zero()) << "after it passed";
    EXPECT_EQ(force_at(s, s.center, 0.5), Vec3::Zero()) << "the centre has no outward: no NaN";
}

TEST(ShockWave, RadialInverseSquareCappedInsideTheReferenceDistance) {
    ShockWave s;
    s.center = Vec3(0.5, -1.0, 2.0);
    s.strength = 80.0;
    s.reference_distance = 1.5;
    s.speed = 10.0;
    s.thickness = 0.2;
    const Vec3 dir = Vec3(2, -1, 2) / 3.0;  // unit
    for (double r : {0.5, 1.5, 3.0, 7.0}) {
        const Vec3 f = force_at(s, s.center + r * dir, r / s.speed);         // the front is on the particle
        const double expected = 80.0 * std::pow(1.5 / std::max(r, 1.5), 2);  // N
        EXPECT_NEAR(f.norm(), expected, 1e-12) << "N at r = " << r << " m";
        EXPECT_LT((f - expected * dir).norm(), 1e-12) << "N: radially outward at r = " << r << " m";
    }
    // Right next to the centre, as the front starts: capped, finite, outward.
    s.center = Vec3::Zero();
    const Vec3 near = force_at(s, 1e-150 * dir, 0.0);
    EXPECT_LT((near - 80.0 * dir).norm(), 1e-12) << "N, 1e-150 m from the centre";
    s.strength = 1e300;  // N: strength / r overflows here
    const Vec3 huge = force_at(s, 1e-150 * dir, 0.0);
    EXPECT_TRUE(huge.allFinite()) << huge.transpose();
    EXPECT_LT((huge / 1e300 - dir).norm(), 1e-12) << "outward, strength in size";
}

TEST(ShockWave, NothingBeyondMaxRadius) {
    ShockWave s;
    s.speed = 10.0;
    s.thickness = 0.2;
    s.max_radius = 4.0;
    EXPECT_NE(force_at(s, Vec3(3.9, 0, 0), 0.39), Vec3::Zero()) << "inside max_radius";
    EXPECT_EQ(force_at(s, Vec3(4.05, 0, 0), 0.405), Vec3::Zero()) << "beyond max_radius";
    EXPECT_EQ(force_at(s, Vec3(6.0, 0, 0), 0.6), Vec3::Zero()) << "the front died out";
    s.max_radius = 0.0;  // unlimited
    EXPECT_NE(force_at(s, Vec3(60.0, 0, 0), 6.0), Vec3::Zero()) << "no limit";
}

TEST(ShockWave, ValidationNamesTheField) {
    ShockWave s;
    s.speed = 0.0;
    try {
        validate(s, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "shock_wave.speed must be > 0 and finite, in m/s (got 0)");
    }
    s.speed = 20.0;
    s.thickness = -0.1;
    EXPECT_THROW(validate(s, 1), InputError);
    s.thickness = 0.5;
    s.strength = NAN;
    try {
        validate(s, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "shock_wave.strength must be >= 0 and finite, in N (got nan)");
    }
    s.strength = 100.0;
    s.center = Vec3(0, INFINITY, 0);
    EXPECT_THROW(validate(s, 1), InputError);
    s.center = Vec3::Zero();
    s.max_radius = -1.0;
    EXPECT_THROW(validate(s, 1), InputError);
    s.max_radius = 0.0;
    EXPECT_NO_THROW(validate(s, 1));
}

}  // namespace
}  // namespace sim::test
