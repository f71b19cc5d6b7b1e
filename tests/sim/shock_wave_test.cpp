// A shock wave pushes once, as its front passes: the impulse on a particle
// held still equals strength (r_ref / r)² thickness / speed.
#include "sim/shock_wave.h"
#include "sim/error.h"

#include <gtest/gtest.h>

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
    EXPECT_NEAR(impulse.z(), expected, 1e-4) << "N·s";
    EXPECT_NEAR(impulse.x(), 0.0, 1e-12) << "radial: along +z only";
    EXPECT_EQ(force_at(s, p, 0.5 + 1.7 / 20.0), Vec3::Zero()) << "before the front arrives";
    EXPECT_EQ(force_at(s, p, 0.5 + 2.3 / 20.0), Vec3::Zero()) << "after it passed";
    EXPECT_EQ(force_at(s, s.center, 0.5), Vec3::Zero()) << "the centre has no outward: no NaN";
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
}

}  // namespace
}  // namespace sim::test
