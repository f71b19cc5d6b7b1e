// sim::check (the explosion watchdog) on hand-made states: each rule, its
// order, the limits' validation and the verdict's message.
#include "sim/watchdog.h"
#include "sim/error.h"
#include "sim/rigid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace sim::test {
namespace {

// n particles of 1 kg at rest at the origin.
ParticleState resting(std::size_t n) { return make_state(std::vector<ParticleDef>(n, ParticleDef{})); }

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Watchdog, AQuietStateIsOk) {
    const Verdict v = check(WatchdogLimits{}, resting(4), 0.0, 0.0, 1);
    EXPECT_FALSE(v.exploded());
    EXPECT_EQ(v.message("calm"), "calm: ok");
}

TEST(Watchdog, SpeedAboveTheCapNamesTheParticle) {
    ParticleState s = resting(20);
    s.v.set(12, Vec3(3.0e6, 4.0e6, 0.0));  // |v| = 5e6 m/s
    const Verdict v = check(WatchdogLimits{}, s, 0.0, 0.0, 37);
    ASSERT_TRUE(v.exploded());
    EXPECT_EQ(v.quantity, "speed");
    EXPECT_EQ(v.index, 12u);
    EXPECT_DOUBLE_EQ(v.value, 5.0e6);
    EXPECT_EQ(v.limit, 500.0);
    EXPECT_EQ(v.message("rope"), "rope: exploded at frame 37: particle 12 speed 5e+06 m/s > 500 m/s");
}

TEST(Watchdog, SpeedExactlyAtTheCapIsAllowed) {
    ParticleState s = resting(1);
    s.v.set(0, Vec3(0.0, -500.0, 0.0));
    EXPECT_FALSE(check(WatchdogLimits{}, s, 0.0, 0.0, 1).exploded());
}

TEST(Watchdog, LeavingTheWorldBoxOnAnyAxis) {
    for (int axis = 0; axis < 3; ++axis) {
        ParticleState s = resting(3);
        Vec3 x = Vec3::Zero();
        x[axis] = -2.0e4;  // m, beyond the default 1e4 m
        s.x.set(2, x);
        const Verdict v = check(WatchdogLimits{}, s, 0.0, 0.0, 5);
        ASSERT_TRUE(v.exploded()) << "axis " << axis;
        EXPECT_EQ(v.quantity, "bounds");
        EXPECT_EQ(v.index, 2u);
        EXPECT_EQ(v.value, 2.0e4);
    }
}

TEST(Watchdog, NonFiniteComesFirstThenSpeedThenBounds) {
    // Particle 1 too fast, particle 2 out of the box, particle 3 NaN velocity
    // and infinite position, particle 4 infinite position: non-finite before
    // speed and bounds whatever the indices, the lowest such particle first,
    // its position before its velocity.
    ParticleState s = resting(5);
    s.v.set(1, Vec3(1e4, 0, 0));
    s.x.set(2, Vec3(0, 1e5, 0));
    s.v.set(3, Vec3(0, kNaN, 0));
    s.x.set(3, Vec3(0, 0, INFINITY));
    s.x.set(4, Vec3(0, 0, INFINITY));
    Verdict v = check(WatchdogLimits{}, s, 0.0, 0.0, 9);
    EXPECT_EQ(v.quantity, "position");
    EXPECT_EQ(v.index, 3u);
    EXPECT_EQ(v.message("s"), "s: exploded at frame 9: particle 3 position is inf");

    s.x.set(3, Vec3::Zero());
    v = check(WatchdogLimits{}, s, 0.0, 0.0, 9);
    EXPECT_EQ(v.quantity, "velocity");
    EXPECT_EQ(v.index, 3u);
    EXPECT_TRUE(std::isnan(v.value));

    s.v.set(3, Vec3::Zero());
    v = check(WatchdogLimits{}, s, 0.0, 0.0, 9);
    EXPECT_EQ(v.quantity, "position");
    EXPECT_EQ(v.index, 4u);

    s.x.set(4, Vec3::Zero());
    v = check(WatchdogLimits{}, s, 0.0, 0.0, 9);
    EXPECT_EQ(v.quantity, "speed");
    EXPECT_EQ(v.index, 1u);

    s.v.set(1, Vec3::Zero());
    v = check(WatchdogLimits{}, s, 0.0, 0.0, 9);
    EXPECT_EQ(v.quantity, "bounds");
    EXPECT_EQ(v.index, 2u);
}

TEST(Watchdog, EnergyGrowthAgainstE0) {
    // Growth factor 2 on E0 = 10 J: exploded above 20 J, not at 20 J.
    WatchdogLimits limits;
    limits.energy_growth = 2.0;
    const ParticleState s = resting(1);
    EXPECT_FALSE(check(limits, s, 20.0, 10.0, 3).exploded());
    const Verdict v = check(limits, s, 20.5, 10.0, 3);
    ASSERT_TRUE(v.exploded());
    EXPECT_EQ(v.quantity, "energy");
    EXPECT_EQ(v.limit, 20.0);
    EXPECT_EQ(v.message("oscillator"), "oscillator: exploded at frame 3: energy 20.5 J > 20 J (E0 = 10 J)");
    // A negative E0 (a bound orbit, E0 = -0.5 J) grows by the same margin: |E0|.
    EXPECT_FALSE(check(limits, s, -0.01, -0.5, 3).exploded());
    EXPECT_TRUE(check(limits, s, 0.01, -0.5, 3).exploded());
    // Non-finite energy is an explosion.
    EXPECT_TRUE(check(limits, s, kNaN, 10.0, 3).exploded());
    // Off by default: any energy passes.
    EXPECT_FALSE(check(WatchdogLimits{}, s, 1e30, 10.0, 3).exploded());
}

TEST(Watchdog, EnergyFloorKeepsAZeroE0Meaningful) {
    // E0 = 0 J: the allowed growth is (2 - 1) x floor = 1e-6 J.
    WatchdogLimits limits;
    limits.energy_growth = 2.0;
    EXPECT_FALSE(check(limits, resting(1), 0.5e-6, 0.0, 1).exploded());
    EXPECT_TRUE(check(limits, resting(1), 2e-6, 0.0, 1).exploded());
}

TEST(Watchdog, DisabledSeesNothing) {
    WatchdogLimits limits;
    limits.enabled = false;
    ParticleState s = resting(1);
    s.x.set(0, Vec3(kNaN, 0, 0));
    EXPECT_FALSE(check(limits, s, kNaN, 0.0, 1).exploded());
}

std::string error_of(const WatchdogLimits& limits) {
    try {
        validate(limits);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Watchdog, BodiesNonFiniteThenSpeedThenBoundsNamingTheBody) {
    const WatchdogLimits limits{.max_speed = 100.0, .world_half_extent = 50.0};
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<Vec3> x = {Vec3(0, 1, 0), Vec3(60, 0, 0), Vec3(0, 0, 0)};
    std::vector<Vec3> v = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, -150, 0)};
    Verdict speed = check_bodies(limits, x, v, 7);
    ASSERT_TRUE(speed.exploded());
    EXPECT_EQ(speed.subject, "body");
    EXPECT_EQ(speed.quantity, "speed") << "speed before bounds";
    EXPECT_EQ(speed.index, 2u);
    EXPECT_DOUBLE_EQ(speed.value, 150.0) << "m/s";
    EXPECT_EQ(speed.frame, 7u);
    EXPECT_EQ(speed.message("stack"), "stack: exploded at frame 7: body 2 speed 150 m/s > 100 m/s");
    v[2] = Vec3::Zero();
    const Verdict bounds = check_bodies(limits, x, v, 8);
    EXPECT_EQ(bounds.quantity, "bounds");
    EXPECT_EQ(bounds.index, 1u);
    x[2] = Vec3(nan, 0, 0);
    const Verdict non_finite = check_bodies(limits, x, v, 9);
    EXPECT_EQ(non_finite.quantity, "position") << "non-finite first";
    EXPECT_EQ(non_finite.index, 2u);
    EXPECT_FALSE(check_bodies(limits, {Vec3(0, 1, 0)}, {Vec3(3, 0, 0)}, 1).exploded());
}

// What ODE can step holds whatever the limits (issue 51): past kMaxBodyReach
// its hash space aborts, and a spin past kMaxBodySpin overflows to NaN.
TEST(Watchdog, BodiesPastWhatOdeCanStepExplodeWatchdogOrNot) {
    WatchdogLimits off;
    off.enabled = false;
    const std::vector<Vec3> still = {Vec3::Zero(), Vec3::Zero()};
    EXPECT_FALSE(check_bodies(off, {Vec3(0, 1, 0), Vec3(9e7, 0, 0)}, still, 1).exploded());
    const Verdict far = check_bodies(off, {Vec3(0, 1, 0), Vec3(0, 0, -1.5e8)}, still, 2);
    ASSERT_TRUE(far.exploded());
    EXPECT_EQ(far.quantity, "bounds");
    EXPECT_EQ(far.index, 1u);
    EXPECT_EQ(far.limit, kMaxBodyReach);
    const WatchdogLimits wide{.world_half_extent = 1e300};
    EXPECT_EQ(check_bodies(wide, {Vec3(2e8, 0, 0)}, {Vec3::Zero()}, 3).quantity, "bounds");

    const Verdict spin = check_bodies(off, {Vec3::Zero(), Vec3::Zero()}, still, 4, {Vec3(0, 9e3, 0), Vec3(0, 0, 2e4)});
    ASSERT_TRUE(spin.exploded());
    EXPECT_EQ(spin.index, 1u);
    EXPECT_EQ(spin.message("inertia"),
              "inertia: exploded at frame 4: body 1 spins at 2e+04 rad/s > 1e+04 rad/s, past what ODE can step");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(check_bodies(off, {Vec3::Zero()}, {Vec3::Zero()}, 5, {Vec3(nan, 0, 0)}).quantity, "spin");
}

TEST(Watchdog, LimitsAreValidated) {
    WatchdogLimits l;
    EXPECT_EQ(error_of(l), "");
    l.max_speed = -3;
    EXPECT_EQ(error_of(l), "watchdog.max_speed must be > 0 and finite, in m/s (got -3)");
    l = {};
    l.world_half_extent = INFINITY;
    EXPECT_EQ(error_of(l), "watchdog.world_half_extent must be > 0 and finite, in m (got inf)");
    l = {};
    l.energy_floor = 0.0;
    EXPECT_EQ(error_of(l), "watchdog.energy_floor must be > 0 and finite, in J (got 0)");
    l = {};
    l.energy_growth = 0.5;
    EXPECT_EQ(error_of(l), "watchdog.energy_growth must be 0 (off) or >= 1 (got 0.5)");
    l.energy_growth = kNaN;
    EXPECT_EQ(error_of(l), "watchdog.energy_growth must be 0 (off) or >= 1 (got nan)");
}

}  // namespace
}  // namespace sim::test
