// Scripted control forces: on during [start, end), the impulse of a key is
// force x duration (momentum change of a symplectic Euler run).
#include "sim/control_force.h"
#include "sim/error.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sim::test {
namespace {

TEST(ControlForces, AKeyPushesDuringItsIntervalAndItsImpulseIsForceTimesDuration) {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 2.0, false});
    model.particles.push_back({Vec3(1, 0, 0), Vec3::Zero(), 1.0, false});
    // 3 N along x on particle 0 during [0.25, 0.75) s, and 1 N along y on both during [0.5, 1) s.
    model.forces.push_back(ControlForces{{{0.25, 0.75, {0}, Vec3(3, 0, 0)}, {0.5, 1.0, {0, 1}, Vec3(0, 1, 0)}}});
    World world(std::move(model));
    for (int i = 0; i < 80; ++i) world.step({Integrator::symplectic_euler, 1.0 / 64.0, 1});  // dt divides the keys
    const Vec3 p0 = 2.0 * world.state().v.get(0), p1 = world.state().v.get(1);
    EXPECT_NEAR(p0.x(), 3.0 * 0.5, 1e-12) << "kg·m/s";
    EXPECT_NEAR(p0.y(), 1.0 * 0.5, 1e-12) << "kg·m/s";
    EXPECT_NEAR(p1.y(), 1.0 * 0.5, 1e-12) << "kg·m/s";
    EXPECT_EQ(p1.x(), 0.0);
}

// Force on two particles at time t, N.
Vec3Array forces_at(const ControlForces& c, double t) {
    Vec3Array x(2), v(2), f(2);
    const double mass[2] = {1, 1}, inv[2] = {1, 1};
    accumulate(c, {t, 0, x.span(), v.span(), mass, inv}, f.span());
    return f;
}

TEST(ControlForces, OnDuringStartToEndAndSummedWhereKeysOverlap) {
    const ControlForces c{{{1.0, 2.0, {0}, Vec3(3, 0, 0)}, {1.5, 3.0, {0, 1}, Vec3(0, -2, 0.5)}}};
    EXPECT_EQ(forces_at(c, 0.999).get(0), Vec3::Zero()) << "before the first key";
    EXPECT_EQ(forces_at(c, 1.0).get(0), Vec3(3, 0, 0)) << "on at start";
    EXPECT_EQ(forces_at(c, 1.0).get(1), Vec3::Zero()) << "particle 1 is not in the first key";
    EXPECT_EQ(forces_at(c, 1.7).get(0), Vec3(3, -2, 0.5)) << "both keys: summed";
    EXPECT_EQ(forces_at(c, 1.7).get(1), Vec3(0, -2, 0.5));
    EXPECT_EQ(forces_at(c, 2.0).get(0), Vec3(0, -2, 0.5)) << "the first key is off at its end";
    EXPECT_EQ(forces_at(c, 3.0).get(1), Vec3::Zero()) << "off at end";
    // A particle listed twice in one key is pushed twice.
    const ControlForces twice{{{0.0, 1.0, {1, 1}, Vec3(1, 0, 0)}}};
    EXPECT_EQ(forces_at(twice, 0.5).get(1), Vec3(2, 0, 0));
}

TEST(ControlForces, ValidationNamesTheKey) {
    ControlForces c{{{1.0, 0.5, {0}, Vec3::UnitX()}}};
    try {
        validate(c, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "control.keys[0] must have start < end, finite, in s (got 1 .. 0.5)");
    }
    c.keys[0].end = 1.0;  // empty interval
    EXPECT_THROW(validate(c, 1), InputError);
    c.keys[0] = {0.0, 1.0, {0}, Vec3(0, NAN, 0)};
    try {
        validate(c, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "control.keys[0].force must be finite, in N (got 0, nan, 0)");
    }
    c.keys[0] = {0.0, 1.0, {4}, Vec3::UnitX()};
    try {
        validate(c, 2);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "control.keys[0] pushes particle 4, but there are only 2");
    }
}

}  // namespace
}  // namespace sim::test
