// Rigid bodies through ODE: mass and inertia against the closed forms of
// the shapes, free fall against symplectic Euler's exact sequence, rest on
// the ground, stale ids, and the same bits from two worlds stepped in turn.
#include "sim/rigid.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

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
    RigidSettings awake;
    awake.sleep = false;  // resting contact is what this test looks at
    RigidWorld world(awake);
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

TEST(RigidJoints, ErpAndCfmFromASpringAndADamper) {
    const ErpCfm e = erp_cfm(0.01, 1000.0, 10.0);  // h kp = 10 N·s/m... = kd
    EXPECT_DOUBLE_EQ(e.erp, 0.5);
    EXPECT_DOUBLE_EQ(e.cfm, 0.05);
}

// A 1 m rod (0.04 m square section, 1 kg) hanging from a hinge at its top end.
struct HingedRod {
    // No sleep: a 3° swing moves slower than the sleep speed (its RMS speed
    // is about 0.05 m/s) and would fall asleep, by design.
    RigidWorld world{{.ground = false, .sleep = false}};
    BodyId rod;
    JointId hinge;
    static constexpr double kLength = 1.0, kWidth = 0.04, kMass = 1.0;

    explicit HingedRod(double theta0, JointDef joint = {}) {
        BodyDef def;
        def.size = Vec3(kWidth, kLength, kWidth);
        def.mass = kMass;
        const Eigen::Quaterniond q(Eigen::AngleAxisd(theta0, Vec3::UnitZ()));
        def.orientation = q;
        def.position = Vec3(0, 2, 0) + q * Vec3(0, -kLength / 2, 0);  // the top end at the pivot (0, 2, 0)
        rod = world.add_body(def);
        joint.type = JointType::hinge;
        joint.a = rod;
        joint.anchor = Vec3(0, 2, 0);
        joint.axis = Vec3::UnitZ();
        hinge = world.add_joint(joint);
    }
};

TEST(RigidJoints, AHingedRodSwingsWithThePhysicalPendulumsPeriod) {
    // Small angles: T = 2π sqrt(I_pivot / (m g d)), I_pivot = m (L² + w²) / 12 + m (L / 2)², d = L / 2.
    const double theta0 = 3.0 * std::numbers::pi / 180.0;  // rad, released from rest
    HingedRod r(theta0);
    // ODE's hinge angle is 0 where the joint was made: the rod's angle from
    // the vertical is that plus theta0.
    auto theta = [&] { return r.world.joint_position(r.hinge) + theta0; };
    const double L = HingedRod::kLength, w = HingedRod::kWidth, m = HingedRod::kMass;
    const double pivot_inertia = m * (L * L + w * w) / 12.0 + m * L * L / 4.0;
    const double period = 2 * std::numbers::pi * std::sqrt(pivot_inertia / (m * 9.81 * L / 2));
    const double h = 1.0 / 480.0;
    double previous = theta(), worst_separation = 0.0;
    std::vector<double> crossings;  // times the rod crosses the vertical going down
    for (int i = 1; i <= 2400; ++i) {
        r.world.step(h);
        const double angle = theta();
        if (previous > 0.0 && angle <= 0.0) crossings.push_back((i - 1 + previous / (previous - angle)) * h);
        previous = angle;
        worst_separation = std::max(worst_separation, r.world.joint_separation(r.hinge));
    }
    ASSERT_GE(crossings.size(), 3u);
    const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
    std::printf("[ measured ] hinged rod period %.5f s (closed form %.5f s), worst joint separation %.2e m\n", measured,
                period, worst_separation);
    EXPECT_NEAR(measured, period, 0.005 * period) << "s, 0.5%";
    EXPECT_LT(worst_separation, 1e-3) << "m";
}

TEST(RigidJoints, HingeLimitsHoldTheSwing) {
    JointDef limited;
    limited.lo = -std::numbers::pi / 6;  // ±30°
    limited.hi = std::numbers::pi / 6;
    HingedRod r(-std::numbers::pi / 6, limited);  // released at one stop: it swings to the other
    double widest = 0.0;
    for (int i = 0; i < 600; ++i) {
        r.world.step(1.0 / 120.0);
        widest = std::max(widest, std::abs(r.world.joint_position(r.hinge)));
    }
    EXPECT_LT(widest, std::numbers::pi / 6 + 2.0 * std::numbers::pi / 180) << "rad: within 2 degrees of the stop";
}

TEST(RigidJoints, AMotorTurnsAtItsVelocity) {
    RigidWorld world({.gravity = Vec3::Zero(), .ground = false});
    BodyDef wheel;
    wheel.shape = RigidShape::cylinder;
    wheel.size = Vec3(0.3, 0.1, 0);
    const BodyId id = world.add_body(wheel);
    JointDef motor;
    motor.type = JointType::hinge;
    motor.a = id;
    motor.axis = Vec3::UnitZ();
    motor.motor_velocity = 2.0;  // rad/s
    motor.motor_max_force = 100.0;
    const JointId j = world.add_joint(motor);
    for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
    EXPECT_NEAR(world.joint_position(j), 2.0, 0.05) << "rad after 1 s";
    EXPECT_NEAR(world.state(id).angular_velocity.z(), 2.0, 1e-6) << "rad/s";
}

TEST(Rigid, ACompoundBodysMassCentreAndInertiaAreThePartsClosedForms) {
    // A 0.2 m wooden cube and a steel ball of radius 0.1 m, 0.5 m apart on z.
    RigidWorld world({.ground = false});
    BodyDef hammer;
    hammer.position = Vec3(1, 2, 3);  // of the centre of mass
    hammer.parts = {{RigidShape::box, Vec3(0.2, 0.2, 0.2), Vec3::Zero(), Eigen::Quaterniond::Identity(), 1000.0},
                    {RigidShape::sphere, Vec3(0.1, 0, 0), Vec3(0, 0, 0.5), Eigen::Quaterniond::Identity(), 8000.0}};
    hammer.mass = 0.0;  // from the densities
    const BodyId id = world.add_body(hammer);
    const double m_box = 1000.0 * 0.008, m_ball = 8000.0 * 4.0 / 3.0 * std::numbers::pi * 0.001;  // kg
    const double m = m_box + m_ball;
    const double zc = m_ball * 0.5 / m;  // m, the centre of mass from the cube's centre
    EXPECT_NEAR(world.mass(id), m, 1e-9) << "kg";
    const Eigen::Matrix3d I = world.inertia(id);
    const double box_i = m_box * (0.04 + 0.04) / 12.0, ball_i = 0.4 * m_ball * 0.01;  // kg·m², own centres
    EXPECT_NEAR(I(0, 0), box_i + m_box * zc * zc + ball_i + m_ball * (0.5 - zc) * (0.5 - zc), 1e-9)
        << "kg·m², parallel axis theorem";
    EXPECT_NEAR(I(2, 2), box_i + ball_i, 1e-9) << "kg·m², about the line through both centres";
    EXPECT_NEAR(I(0, 2), 0.0, 1e-12);
    // The parts sit around the centre of mass, which is the body's position.
    const auto parts = world.placed_parts();
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_LT((parts[0].center - Vec3(1, 2, 3 - zc)).norm(), 1e-12) << "m";
    EXPECT_LT((parts[1].center - Vec3(1, 2, 3.5 - zc)).norm(), 1e-12) << "m";
}

TEST(Rigid, ABodyAtRestSleepsAndABlowWakesIt) {
    RigidWorld world;
    BodyDef box;
    box.size = Vec3(0.4, 0.4, 0.4);
    box.position = Vec3(0, 0.25, 0);
    const BodyId target = world.add_body(box);
    int asleep_at = -1;
    for (int i = 1; i <= 120 && asleep_at < 0; ++i) {
        world.step(1.0 / 60.0);
        if (!world.awake(target)) asleep_at = i;
    }
    ASSERT_GT(asleep_at, 0) << "asleep within 2 s";
    EXPECT_GE(asleep_at, 30) << "not before sleep_time (0.5 s) of rest";
    EXPECT_EQ(world.state(target).velocity.norm(), 0.0) << "m/s: a sleeping body is still";
    const Vec3 rest = world.state(target).position;
    for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
    EXPECT_EQ(world.state(target).position, rest) << "asleep: not stepped";

    BodyDef ball;
    ball.shape = RigidShape::sphere;
    ball.size = Vec3(0.15, 0, 0);
    ball.mass = 5.0;
    ball.position = Vec3(-1.5, 0.3, 0);
    ball.velocity = Vec3(6, 0, 0);
    world.add_body(ball);
    bool woken = false;
    for (int i = 0; i < 30; ++i) {
        world.step(1.0 / 60.0);
        woken = woken || world.awake(target);
    }
    EXPECT_TRUE(woken) << "the blow woke it";
    EXPECT_GT(world.state(target).position.x() - rest.x(), 0.05) << "m: and it was pushed";
}

// A pendulum is slow only near its turns, and touches nothing: a 1° swing
// (3.3 cm/s at the bottom) stays awake, one hanging still sleeps.
TEST(Rigid, AGentleSwingStaysAwakeAndAStillPendulumSleeps) {
    for (const double theta0 : {0.0, 1.0}) {  // deg
        RigidWorld world({.ground = false});
        const double th = theta0 * std::numbers::pi / 180.0;
        BodyDef rod;
        rod.size = Vec3(0.1, 1.0, 0.1);
        rod.position = 0.5 * Vec3(std::sin(th), -std::cos(th), 0.0);
        rod.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(th, Vec3::UnitZ()));
        const BodyId b = world.add_body(rod);
        world.add_joint({.type = JointType::hinge, .a = b, .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()});
        int asleep_at = -1;
        for (int i = 1; i <= 1200 && asleep_at < 0; ++i) {
            world.step(1.0 / 120.0);
            if (!world.awake(b)) asleep_at = i;
        }
        if (theta0 == 0.0) {
            EXPECT_GT(asleep_at, 0) << "hanging still: asleep within 10 s";
        } else {
            EXPECT_EQ(asleep_at, -1) << "a 1° swing: awake for 10 s (asleep at step " << asleep_at << " of 1/120 s)";
        }
    }
}

// A sleep_time no step counter reaches (1e300 s is 6e301 steps of 1/60 s):
// the body never sleeps, as asked. The count was converted to a uint32,
// undefined beyond 2^32 (here it came out 0), and a body dropped at rest fell
// asleep at its first step, hanging in the air. It falls as ODE's symplectic
// Euler says: y = y0 - g h² n (n + 1) / 2 after n steps.
TEST(Rigid, ASleepTimeBeyondAnyStepCountNeverSleeps) {
    RigidWorld world({.ground = false, .sleep_time = 1e300});
    BodyDef box;
    box.position = Vec3(0, 10, 0);
    const BodyId id = world.add_body(box);
    const double h = 1.0 / 60.0;
    const int n = 60;
    for (int i = 0; i < n; ++i) world.step(h);
    EXPECT_TRUE(world.awake(id)) << "never asleep";
    EXPECT_NEAR(world.state(id).position.y(), 10.0 - 9.81 * h * h * n * (n + 1) / 2.0, 1e-9) << "m: falling";
}

TEST(Rigid, ABodyRestsOnAStaticCollider) {
    RigidWorld world({.ground = false, .sleep = false});
    world.add_static(BoxCollider{Vec3(0, 1, 0), Vec3(1, 0.5, 1)});  // a table top at y = 1.5
    BodyDef ball;
    ball.shape = RigidShape::sphere;
    ball.size = Vec3(0.2, 0, 0);
    ball.position = Vec3(0.1, 3, 0);
    const BodyId id = world.add_body(ball);
    for (int i = 0; i < 180; ++i) world.step(1.0 / 60.0);
    EXPECT_NEAR(world.state(id).position.y(), 1.7, 0.005) << "m: on the box, its centre a radius above the top";
}

// A rod hung from the world swings in reduced coordinates (its energy kept to
// rounding) until it meets a wall, where ODE's contacts take it; it stops at
// the wall, loses energy to the impact, and its hinge stays together.
TEST(RigidJoints, AHungRodHandsOverToTheContactsAtAWallAndBack) {
    RigidWorld world({.ground = false});
    world.add_static(BoxCollider{Vec3(-0.8, -0.4, 0.0), Vec3(0.05, 0.3, 0.5)});  // its face at x = -0.75 m
    BodyDef rod;
    rod.size = Vec3(0.1, 1.0, 0.1);
    rod.position = Vec3(0.5, 0.0, 0.0);  // released horizontal
    rod.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2.0, Vec3::UnitZ()));
    const BodyId b = world.add_body(rod);
    const JointId hinge =
        world.add_joint({.type = JointType::hinge, .a = b, .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()});
    const double e0 = world.kinetic_energy() + world.potential_energy();
    const double swing = 1.0 * 9.81 * 0.5;  // J, m g d: what the fall to hanging releases
    bool touched = false;
    double least_x = 0.0, worst_gap = 0.0;  // m, m
    for (int i = 0; i < 360; ++i) {
        world.step(1.0 / 120.0);
        touched = touched || world.contacts() > 0;
        if (!touched) {
            const double e = world.kinetic_energy() + world.potential_energy();
            EXPECT_NEAR(e, e0, 1e-6 * swing) << "J: free, the swing keeps its energy (ODE: 1e-2) (step " << i << ")";
        }
        least_x = std::min(least_x, world.state(b).position.x());
        worst_gap = std::max(worst_gap, world.joint_separation(hinge));
    }
    ASSERT_TRUE(touched) << "the rod reached the wall";
    EXPECT_GT(least_x, -0.75 * 0.5 - 0.01) << "m: its centre stops at the wall (half way out along the rod)";
    EXPECT_LT(world.kinetic_energy() + world.potential_energy(), e0) << "J: the impact took energy";
    EXPECT_LT(worst_gap, 2e-3) << "m: the hinge held through the handovers";
}

TEST(RigidJoints, SwingLimitsOfABallJointHoldAPushedRod) {
    // A rod hanging from a base held by a fixed joint, pushed about x in zero
    // gravity: free, it turns all the way round; limited to ±0.5 rad of swing
    // on each axis it stops within the limit box (corner 0.66 rad from straight down).
    auto widest_swing = [](bool limited) {
        RigidWorld world({.gravity = Vec3::Zero(), .ground = false, .sleep = false});
        BodyDef base;
        base.position = Vec3(0, 2, 0);
        base.size = Vec3(0.3, 0.1, 0.3);
        const BodyId b = world.add_body(base);
        JointDef fixed;
        fixed.type = JointType::fixed;
        fixed.a = b;
        world.add_joint(fixed);
        BodyDef rod;
        rod.size = Vec3(0.05, 0.6, 0.05);
        rod.position = Vec3(0, 1.65, 0);
        rod.angular_velocity = Vec3(6, 0, 0);  // rad/s about the anchor:
        rod.velocity = Vec3(0, 0, -1.8);       // m/s, ω × (x - anchor)
        const BodyId r = world.add_body(rod);
        JointDef ball;
        ball.a = b;
        ball.b = r;
        ball.anchor = Vec3(0, 1.95, 0);
        ball.axis = Vec3::UnitX();
        ball.axis2 = -Vec3::UnitY();  // along the rod
        if (limited) {
            ball.lo = ball.lo2 = -0.5;
            ball.hi = ball.hi2 = 0.5;
            ball.lo3 = -0.3;
            ball.hi3 = 0.3;
        }
        world.add_joint(ball);
        double widest = 0.0;
        for (int i = 0; i < 120; ++i) {
            world.step(1.0 / 120.0);
            const Vec3 along = world.state(r).orientation * -Vec3::UnitY();
            widest = std::max(widest, std::acos(std::clamp(along.dot(-Vec3::UnitY()), -1.0, 1.0)));
        }
        return widest;
    };
    const double free = widest_swing(false), limited = widest_swing(true);
    std::printf("[ measured ] widest swing from straight down: free %.3f rad, limited %.3f rad\n", free, limited);
    EXPECT_GT(free, 2.5) << "rad: unlimited, the push turns it over";
    EXPECT_LT(limited, 0.66 + 0.05) << "rad: the limit holds (ODE's stops are soft by ERP)";
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

// Issue 51: what ODE's assertions abort on is refused with the range.
TEST(Rigid, WhatOdeCannotTakeIsRefusedWithItsRange) {
    RigidWorld world;
    auto error = [&](const BodyDef& def) -> std::string {
        try {
            world.add_body(def);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    BodyDef def;
    def.size = Vec3(1e4, 0.3, 0.3);
    EXPECT_EQ(error(def), "body.size must be within 0.001 .. 1000, in m (got 10000)");
    def = {};
    def.mass = 1e300;
    EXPECT_EQ(error(def), "body mass must be within 0.001 .. 1e+06, in kg (got 1e+300)");
    def = {};
    def.mass = 0.0;
    def.density = 1e-300;
    EXPECT_EQ(error(def), "body mass must be within 0.001 .. 1e+06, in kg (got 1.25e-301)");
    def = {};
    def.position = Vec3(1e9, 0, 0);
    EXPECT_EQ(error(def), "body.position must be within +-1e+08, in m");
    def = {};
    def.mass = 1e6;
    def.position = Vec3(1e8, 0, 0);
    EXPECT_EQ(error(def), "") << "the edges are taken";
}

// A spin about the intermediate axis at |ω| h = 3000: one RK4 step of the
// gyroscopic term overflowed (and ODE aborted on the NaN quaternion); in
// steps of |ω| h <= 0.25 the spin stays finite and within a few percent of
// its energy, which the torque-free equations keep.
TEST(Rigid, AFastSpinAtALargeStepStaysFinite) {
    RigidWorld world({.gravity = Vec3::Zero(), .ground = false, .sleep = false});
    BodyDef def;
    def.size = Vec3(0.1, 0.4, 0.7);
    def.angular_velocity = Vec3(1, 3000, 1);  // rad/s
    const BodyId id = world.add_body(def);
    const double e0 = world.kinetic_energy();
    for (int i = 0; i < 10; ++i) world.step(1.0);
    const BodyState s = world.state(id);
    EXPECT_TRUE(s.angular_velocity.allFinite());
    EXPECT_TRUE(s.orientation.coeffs().allFinite());
    EXPECT_NEAR(world.kinetic_energy() / e0, 1.0, 0.05);
}

}  // namespace
}  // namespace sim::test
