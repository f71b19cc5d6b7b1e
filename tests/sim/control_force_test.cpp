// Scripted control forces: on during [start, end), the impulse of a key is
// force x duration (momentum change of a symplectic Euler run).
#include "sim/control_force.h"
#include "sim/error.h"
#include "sim/world.h"

#include <gtest/gtest.h>

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

TEST(ControlForces, ValidationNamesTheKey) {
    ControlForces c{{{1.0, 0.5, {0}, Vec3::UnitX()}}};
    EXPECT_THROW(validate(c, 1), InputError);
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
