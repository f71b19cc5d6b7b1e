// Problems with closed-form answers, built as particle models: shared by the
// accuracy and stability tests and by `plausible report`. Each problem's
// constants live here once; the report names the problems and sweeps them.
#pragma once

#include "sim/analytic.h"
#include "sim/world.h"

#include <cmath>
#include <numbers>

namespace sim::problems {

// Standard gravity, m/s²: the shot's, the pendulum's, and the report's cloths and ropes.
inline constexpr double kGravity = 9.81;

// A ball shot from the origin at (3, 4, 0) m/s under g = (0, -9.81, 0) m/s².
inline const Vec3 kShotVelocity{3.0, 4.0, 0.0};
inline const Vec3 kShotGravity{0.0, -kGravity, 0.0};

inline ParticleModel ballistic_model() {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), kShotVelocity, 1.0, false});
    model.forces.push_back(UniformGravity{kShotGravity});
    return model;
}

// Particle 1 (mass m, released at x0 with v0) on a zero-rest-length spring of
// stiffness k (and damper c) to particle 0, pinned at the origin.
inline ParticleModel oscillator_model(const analytic::Oscillator& o, const Vec3& x0, const Vec3& v0) {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    model.particles.push_back({x0, v0, o.mass, false});
    model.forces.push_back(Springs{{{0, 1, 0.0, o.stiffness, o.damping}}});
    return model;
}

// The harmonic oscillator of the accuracy tests and the report: m = 1 kg,
// k = 1 N/m (ω = 1 rad/s), released at kOscX0 with kOscV0 (an ellipse in the
// xy plane), run for kOscEnd.
inline constexpr analytic::Oscillator kOscillator{1.0, 1.0, 0.0};
inline const Vec3 kOscX0{1.0, 0.0, 0.0};  // m
inline const Vec3 kOscV0{0.0, 0.5, 0.0};  // m/s
inline constexpr double kOscEnd = 10.0;   // s

// The same oscillator with a damper of c = 0.2 N·s/m (ζ = 0.1). The damper is
// linear drag on the bob (-c v, every direction), as the closed form has it.
inline constexpr analytic::Oscillator kDamped{1.0, 1.0, 0.2};
inline ParticleModel damped_model() {
    ParticleModel model = oscillator_model(kOscillator, kOscX0, kOscV0);
    model.forces.push_back(LinearDrag{kDamped.damping});
    return model;
}

// A test particle of kKeplerMass around a pinned central mass, μ = G M = 1
// m³/s², released at perihelion of an orbit with semi-major axis 1 m and
// eccentricity e (period 2π s), run for kKeplerEnd.
inline constexpr double kKeplerMu = 1.0;
inline constexpr double kKeplerMass = 1e-3;  // kg
inline constexpr double kKeplerEnd = 5.0;    // s, 0.8 of the 2π s period (not a symmetric point of the orbit)
inline Vec3 kepler_r0(double e) { return {1.0 - e, 0.0, 0.0}; }
inline Vec3 kepler_v0(double e) { return {0.0, std::sqrt(kKeplerMu * (1.0 + e) / (1.0 - e)), 0.0}; }

inline ParticleModel kepler_model(double e) {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    model.particles.push_back({kepler_r0(e), kepler_v0(e), kKeplerMass, false});
    model.forces.push_back(NewtonGravity{kKeplerMu, 0.0});
    return model;
}

// A 1 kg bob on an inextensible XPBD rod of length kPendulumLength from a
// pinned pivot at the origin (particle 0), released at rest kPendulumAmplitude
// from the downward vertical. Its period is analytic::pendulum_period's.
inline constexpr double kPendulumLength = 1.0;                                  // m
inline constexpr double kPendulumAmplitude = 120.0 * std::numbers::pi / 180.0;  // rad

inline ParticleModel pendulum_model() {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    const Vec3 bob(kPendulumLength * std::sin(kPendulumAmplitude), -kPendulumLength * std::cos(kPendulumAmplitude), 0);
    model.particles.push_back({bob, Vec3::Zero(), 1.0, false});
    model.forces.push_back(UniformGravity{Vec3(0, -kGravity, 0)});
    model.constraints.distance.push_back({0, 1, kPendulumLength, 0.0});
    return model;
}

// The stiff spring: a 1 kg bob on a zero-rest-length spring of k N/m to a
// pinned anchor, released kStiffX0 out at rest. At kStiffK, ω = 1000 rad/s:
// ω h = 16.7 at a game's 1/60 s.
inline constexpr double kStiffK = 1e6;    // N/m
inline constexpr double kStiffX0 = 0.01;  // m
inline ParticleModel stiff_spring_model(double k) {
    return oscillator_model({1.0, k, 0.0}, Vec3(kStiffX0, 0, 0), Vec3::Zero());
}

// Runs `world` to end_time with n = round(end_time / dt) steps of dt.
inline void run_to(World& world, Integrator integrator, double end_time, double dt) {
    const auto steps = static_cast<long>(std::llround(end_time / dt));
    for (long i = 0; i < steps; ++i) {
        world.step({integrator, dt, 1});
    }
}

}  // namespace sim::problems
