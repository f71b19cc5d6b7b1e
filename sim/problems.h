// Problems with closed-form answers, built as particle models: shared by the
// accuracy and stability tests and by `plausible report`.
#pragma once

#include "sim/analytic.h"
#include "sim/world.h"

#include <numbers>

namespace sim::problems {

// A ball shot from the origin at (3, 4, 0) m/s under g = (0, -9.81, 0) m/s².
inline const Vec3 kShotVelocity{3.0, 4.0, 0.0};
inline const Vec3 kShotGravity{0.0, -9.81, 0.0};

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

// A test particle around a pinned central mass, μ = G M = 1 m³/s², released at
// perihelion of an orbit with semi-major axis 1 m and eccentricity e
// (period 2π s).
inline constexpr double kKeplerMu = 1.0;
inline Vec3 kepler_r0(double e) { return {1.0 - e, 0.0, 0.0}; }
inline Vec3 kepler_v0(double e) { return {0.0, std::sqrt(kKeplerMu * (1.0 + e) / (1.0 - e)), 0.0}; }

inline ParticleModel kepler_model(double e) {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    model.particles.push_back({kepler_r0(e), kepler_v0(e), 1e-3, false});
    model.forces.push_back(NewtonGravity{kKeplerMu, 0.0});
    return model;
}

// Runs `world` to end_time with n = round(end_time / dt) steps of dt.
inline void run_to(World& world, Integrator integrator, double end_time, double dt) {
    const auto steps = static_cast<long>(std::llround(end_time / dt));
    for (long i = 0; i < steps; ++i) {
        world.step({integrator, dt, 1});
    }
}

}  // namespace sim::problems
