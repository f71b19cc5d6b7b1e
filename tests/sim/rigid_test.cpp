// Rigid bodies through ODE: mass and inertia against the closed forms of
// the shapes, free fall against symplectic Euler's exact sequence, rest on
// the ground, stale ids, and the same bits from two worlds stepped in turn.
#include "sim/rigid.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sim::test {
namespace {

TEST(Rigid, MassAndInertiaOfABoxAndASphere) {
    RigidWorld world({.ground = false});
    BodyDef box;
    box.size = Vec3(0.2, 0.4, 0.6);
    box.mass = 0.0;
    box.density = 500.0;
    const BodyId b = world.add_body(box);
    const double m = 500.0 * 0.2 * 0.4 * 0.6;  // kg
    EXPECT_NEAR(world.mass(b), m, 1e-12) << "kg";
    const Eigen::Matrix3d I = world.inertia(b);
    EXPECT_NEAR(I(0, 0), m / 12 * (0.16 + 0.36), 1e-12) << "kg·m², m (b² + c²) / 12";
    EXPECT_NEAR(I(1, 1), m / 12 * (0.04 + 0.36), 1e-12);
    EXPECT_NEAR(I(2, 2), m / 12 * (0.04 + 0.16), 1e-12);
    EXPECT_NEAR(I(0, 1), 0.0, 1e-15);

    BodyDef ball;
    ball.shape = RigidShape::sphere;
    ball.size = Vec3(0.3, 0, 0);
    ball.mass = 2.0;
    const BodyId s = world.add_body(ball);
    EXPECT_NEAR(world.mass(s), 2.0, 1e-12);
    EXPECT_NEAR(world.inertia(s)(1, 1), 0.4 * 2.0 * 0.09, 1e-12) << "kg·m², 2/5 m r²";
}

TEST(Rigid, FreeFallIsSymplecticEulersExactSequence) {
    // ODE integrates v += h g, then x += h v: after n steps
    // y = y0 + v0 n h + g h² n (n + 1) / 2, exactly up to rounding.
    RigidWorld world({.ground = false});
    BodyDef ball;
    ball.shape = RigidShape::sphere;
    ball.size = Vec3(0.1, 0, 0);
    ball.position = Vec3(0, 10, 0);
    ball.velocity = Vec3(1, 2, 0);
    const BodyId id = world.add_body(ball);
    const double h = 1.0 / 60.0;
    const int n = 90;
    for (int i = 0; i < n; ++i) world.step(h);
    const BodyState s = world.state(id);
    EXPECT_NEAR(s.position.y(), 10.0 + 2.0 * n * h - 9.81 * h * h * n * (n + 1) / 2.0, 1e-9) << "m";
    EXPECT_NEAR(s.position.x(), 1.0 * n * h, 1e-12) << "m";
}

TEST(Rigid, ABoxDroppedOnTheGroundComesToRestOnIt) {
    RigidWorld world;
    BodyDef box;
    box.size = Vec3(0.4, 0.2, 0.4);
    box.position = Vec3(0, 1, 0);
    box.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec3(1, 0, 1).normalized()));
    const BodyId id = world.add_body(box);
    for (int i = 0; i < 300; ++i) world.step(1.0 / 60.0);
    const BodyState s = world.state(id);
    // Resting on its largest face: its centre 0.1 m up, within ODE's soft contact.
    EXPECT_NEAR(s.position.y(), 0.1, 0.01) << "m";
    EXPECT_LT(s.velocity.norm(), 0.01) << "m/s";
    EXPECT_GT(world.contacts(), 0u);
}

TEST(Rigid, AStaleIdIsRefusedNotDereferenced) {
    RigidWorld world;
    const BodyId a = world.add_body({});
    world.remove_body(a);
    EXPECT_FALSE(world.alive(a));
    EXPECT_THROW(world.state(a), InputError);
    EXPECT_THROW(world.remove_body(a), InputError);
    const BodyId b = world.add_body({});
    EXPECT_EQ(b.index, a.index) << "the slot is reused";
    EXPECT_NE(b.generation, a.generation) << "with a new generation";
    EXPECT_TRUE(world.alive(b));
    EXPECT_EQ(world.body_count(), 1u);
}

// A small pile: five boxes dropped onto each other, quickstep.
void pile(RigidWorld& world) {
    for (int i = 0; i < 5; ++i) {
        BodyDef box;
        box.size = Vec3(0.3, 0.3, 0.3);
        box.position = Vec3(0.05 * i, 0.3 + 0.4 * i, 0.03 * i);
        box.angular_velocity = Vec3(0.5 * i, 0.2, -0.3 * i);
        world.add_body(box);
    }
}

TEST(Rigid, TwoWorldsSteppedInTurnGiveTheBitsOfEachAlone) {
    RigidWorld alone;
    pile(alone);
    for (int i = 0; i < 200; ++i) alone.step(1.0 / 60.0);

    RigidWorld a, b;
    pile(a);
    pile(b);
    for (int i = 0; i < 200; ++i) {
        a.step(1.0 / 60.0);
        b.step(1.0 / 60.0);
    }
    EXPECT_EQ(a.hash(), alone.hash());
    EXPECT_EQ(b.hash(), alone.hash());
}

TEST(Rigid, BadInputIsRefused) {
    RigidWorld world;
    BodyDef bad;
    bad.size = Vec3(0.1, -1, 0.1);
    EXPECT_THROW(world.add_body(bad), InputError);
    bad = {};
    bad.mass = -2.0;
    try {
        world.add_body(bad);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "body.mass must be > 0 and finite, in kg (got -2)");
    }
    EXPECT_THROW(world.step(0.0), InputError);
    EXPECT_THROW(RigidWorld({.iterations = 0}), InputError);
}

}  // namespace
}  // namespace sim::test
