// Backward Euler's diagonal solve (sim/backward_euler.cpp) where pinned
// particles change during a run. Its bits against the sparse solve, with
// pins and without, are World-level: tests/sim/world_test.cpp
// (BackwardEuler.DiagonalSolveEqualsTheSparseSolve).
#include "sim/integrators.h"
#include "sim/watchdog.h"
#include "sim/world.h"

#include <gtest/gtest.h>

namespace sim::test {
namespace {

// A particle pinned after the World was built (through edit_state, or by
// the watchdog containing its range) stays where it is under backward
// Euler's diagonal solve, which leaves pinned particles' factor out only
// where none is pinned: the World looks again whenever it may have changed.
TEST(BackwardEuler, AParticlePinnedLaterStaysStill) {
    ParticleModel model;
    model.particles.push_back({Vec3(0, 100, 0), Vec3(0, -499, 0), 1.0, false});  // 1 m/s under the speed cap
    model.particles.push_back({Vec3(5, 100, 0), Vec3::Zero(), 1.0, false});
    model.forces = {UniformGravity{Vec3(0, -9.81, 0)}, LinearDrag{0.001}};
    const StepSettings step{Integrator::backward_euler, 1.0 / 60.0, 1};

    World edited(model);
    edited.step(step);
    ParticleState& s = edited.edit_state();
    s.inv_mass[1] = 0.0;
    s.v.set(1, Vec3::Zero());
    const Vec3 where = edited.state().x.get(1);
    for (int i = 0; i < 10; ++i) edited.step(step);
    EXPECT_EQ(edited.state().x.get(1), where) << "pinned through edit_state, bit-exact";

    World contained(model);
    WatchdogLimits limits;
    limits.contain.push_back({"the fast one", 0, 1});
    contained.set_watchdog(limits);
    for (int i = 0; i < 30; ++i) contained.step(step);
    ASSERT_EQ(contained.contained().size(), 1u) << "gravity takes it over 500 m/s";
    EXPECT_EQ(contained.contained()[0].verdict.quantity, "speed");
    EXPECT_EQ(contained.state().v.get(0), Vec3::Zero()) << "frozen";
    const Vec3 frozen = contained.state().x.get(0);
    for (int i = 0; i < 10; ++i) contained.step(step);
    EXPECT_EQ(contained.state().x.get(0), frozen) << "contained: pinned, bit-exact";
    EXPECT_EQ(contained.state().v.get(0), Vec3::Zero());
    EXPECT_NE(contained.state().x.get(1), model.particles[1].position) << "the other one falls";
}

}  // namespace
}  // namespace sim::test
