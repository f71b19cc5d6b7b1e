// The cosmetic emitter: births on its schedule, launch velocities inside the
// cone and the speed band, rebirth after count / rate seconds, same bits on a
// replay.
#include "sim/emitter.h"
#include "sim/error.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sim::test {
namespace {

Emitter nozzle() {
    Emitter e;
    e.first = 1;  // particle 0 is someone else's
    e.count = 50;
    e.position = Vec3(0, 1, 0);
    e.direction = Vec3(1, 1, 0).normalized();
    e.cone = 20.0;
    e.speed = 4.0;
    e.speed_jitter = 0.25;
    e.rate = 100.0;  // each lives 0.5 s
    return e;
}

ParticleModel model_of(const Emitter& e) {
    ParticleModel model;
    model.particles.push_back({Vec3(5, 5, 5), Vec3::Zero(), 1.0, false});
    for (std::uint32_t k = 0; k < e.count; ++k) {
        model.particles.push_back({parked_position(e), Vec3::Zero(), 0.01, true});
    }
    model.emitters.push_back(e);
    return model;
}

TEST(Emitter, LaunchesInsideTheConeAndTheSpeedBand) {
    const Emitter e = nozzle();
    ParticleState state = make_state(model_of(e).particles);
    ASSERT_EQ(emit(e, 0.0, 0.495, state), 50u) << "births at 0, 0.01, ..., 0.49 s";
    const double cos_cone = std::cos(20.0 * std::numbers::pi / 180.0);
    for (std::uint32_t k = 0; k < e.count; ++k) {
        const Vec3 v = state.v.get(e.first + k);
        EXPECT_GE(v.norm(), 4.0 * 0.75 - 1e-12) << "m/s, particle " << k;
        EXPECT_LE(v.norm(), 4.0 * 1.25 + 1e-12) << "m/s, particle " << k;
        EXPECT_GE(v.normalized().dot(e.direction), cos_cone - 1e-12) << "inside the 20 degree cone";
        EXPECT_EQ(state.x.get(e.first + k), e.position);
        EXPECT_EQ(state.inv_mass[e.first + k], 100.0) << "1/kg: free once born";
    }
    EXPECT_EQ(state.v.get(0), Vec3::Zero()) << "not the emitter's particle";
}

TEST(Emitter, BirthsFollowTheRateAndRebirthsTheLifetime) {
    World world(model_of(nozzle()));
    const double h = 1.0 / 60.0;
    int previous = 0;
    for (int frame = 1; frame <= 24; ++frame) {  // 0.4 s: 41 births (t = 0 .. 0.40), none reborn yet
        world.step({Integrator::symplectic_euler, h, 1});
        int free = 0;
        for (std::uint32_t k = 0; k < 50; ++k) free += world.state().inv_mass[1 + k] != 0.0;
        // Emission for a step covers (t, t + h]: after frame n, births up to
        // n h, one fewer when n h is a birth time the accumulated t has not
        // quite reached (t is a sum of n rounded steps).
        const int expected = std::min(50, static_cast<int>(std::floor(frame * h * 100.0 + 1e-9)) + 1);
        EXPECT_LE(free, expected) << "frame " << frame;
        EXPECT_GE(free, expected - 1) << "frame " << frame;
        EXPECT_GE(free, previous);
        previous = free;
    }
    // Particle 0 of the emitter is reborn at t = 0.5 s (count / rate): back at the nozzle.
    for (int frame = 25; frame <= 31; ++frame) world.step({Integrator::symplectic_euler, h, 1});
    EXPECT_LT((world.state().x.get(1) - nozzle().position).norm(), 2 * h * 5.0)
        << "m: reborn at 0.5 s, at most 2 frames ago";
}

// A particle born twice within one call keeps only its last birth, so a
// call over many lifetimes makes only the last lifetime's births, with the
// same bits as the schedule made in calls of one lifetime each (where no
// particle is born twice). 1e14 births in one call (1e12 s at 100/s) then
// cost 50: made one by one they took days. Beyond 2^53 births a double no
// longer tells one from the next: refused.
TEST(Emitter, ACallOverManyLifetimesMakesOnlyTheLastWithTheSameBits) {
    const Emitter e = nozzle();  // 50 particles at 100/s: a lifetime of 0.5 s
    ParticleState chunked = make_state(model_of(e).particles), whole = chunked;
    for (int w = 0; w < 200; ++w) emit(e, 0.5 * w, 0.5 * (w + 1), chunked);
    EXPECT_EQ(emit(e, 0.0, 100.0, whole), 10'000u) << "births in 100 s at 100/s";
    EXPECT_EQ(whole.x.flat(), chunked.x.flat());
    EXPECT_EQ(whole.v.flat(), chunked.v.flat());
    EXPECT_EQ(whole.inv_mass, chunked.inv_mass);

    ParticleState far = make_state(model_of(e).particles), last = far;
    EXPECT_EQ(emit(e, 0.0, 1e12, far), 100'000'000'000'000u);
    EXPECT_EQ(emit(e, 1e12 - 0.5, 1e12, last), 50u) << "the last lifetime";
    EXPECT_EQ(far.v.flat(), last.v.flat());
    EXPECT_THROW(emit(e, 0.0, 1e14, far), InputError) << "1e16 births: beyond 2^53";
}

TEST(Emitter, AReplayGivesTheSameBits) {
    World a(model_of(nozzle())), b(model_of(nozzle()));
    const World::Snapshot start = b.snapshot();
    for (int i = 0; i < 90; ++i) a.step({Integrator::symplectic_euler, 1.0 / 60.0, 2});
    for (int i = 0; i < 30; ++i) b.step({Integrator::symplectic_euler, 1.0 / 60.0, 2});
    b.restore(start);
    for (int i = 0; i < 90; ++i) b.step({Integrator::symplectic_euler, 1.0 / 60.0, 2});
    EXPECT_EQ(a.state().x.flat(), b.state().x.flat());
    EXPECT_EQ(a.state().v.flat(), b.state().v.flat());
}

}  // namespace
}  // namespace sim::test
