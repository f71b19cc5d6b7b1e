#include "scenes/catalog.h"

#include <cmath>

namespace scenes {

namespace {

// A planet on an e = 0.5 ellipse around a pinned sun with μ = G M = 1 m³/s²,
// released at perihelion: semi-major axis 1 m, period 2π s.
Scene orbit() {
    constexpr double kMu = 1.0;  // G M, m³/s²
    constexpr double kE = 0.5;
    const sim::Vec3 r0(1.0 - kE, 0.0, 0.0);
    const sim::Vec3 v0(0.0, std::sqrt(kMu * (1.0 + kE) / (1.0 - kE)), 0.0);
    Scene scene;
    scene.model.particles.push_back({sim::Vec3::Zero(), sim::Vec3::Zero(), 1.0, true});
    scene.model.particles.push_back({r0, v0, 1e-3, false});
    scene.model.forces.push_back(sim::NewtonGravity{kMu, 0.0});  // G = μ for a unit-mass sun
    scene.step = {sim::Integrator::symplectic_euler, 1.0 / 60.0, 1};
    scene.frames = 600;  // 10 s, about 1.6 revolutions
    scene.reference = Reference{1, [=](double t) { return sim::analytic::kepler(kMu, r0, v0, t); }};
    return scene;
}

Scene projectile() {
    const sim::Vec3 v0(6.0, 8.0, 0.0);
    const sim::Vec3 g(0.0, -9.81, 0.0);
    Scene scene;
    scene.model.particles.push_back({sim::Vec3::Zero(), v0, 0.2, false});
    scene.model.forces.push_back(sim::UniformGravity{g});
    scene.step = {sim::Integrator::symplectic_euler, 1.0 / 60.0, 1};
    scene.frames = 98;  // until it is back near the ground (t ≈ 1.63 s)
    scene.reference = Reference{0, [=](double t) { return sim::analytic::ballistic(sim::Vec3::Zero(), v0, g, t); }};
    return scene;
}

Scene oscillator() {
    const sim::analytic::Oscillator o{0.5, 20.0, 0.0};  // ω = sqrt(40) rad/s, period ≈ 1 s
    const sim::Vec3 x0(0.3, 0.0, 0.0);
    Scene scene;
    scene.model.particles.push_back({sim::Vec3::Zero(), sim::Vec3::Zero(), 1.0, true});
    scene.model.particles.push_back({x0, sim::Vec3::Zero(), o.mass, false});
    scene.model.forces.push_back(sim::Springs{{{0, 1, 0.0, o.stiffness, o.damping}}});
    scene.step = {sim::Integrator::symplectic_euler, 1.0 / 60.0, 1};
    scene.frames = 600;
    scene.reference = Reference{1, [=](double t) { return sim::analytic::oscillator(o, x0, sim::Vec3::Zero(), t); }};
    return scene;
}

}  // namespace

const std::vector<SceneInfo>& catalog() {
    static const std::vector<SceneInfo> table = {
        {"orbit", "A planet on an e = 0.5 Kepler ellipse around a pinned sun, against the exact orbit.", &orbit},
        {"projectile", "A ball shot at 10 m/s under gravity, against the exact parabola.", &projectile},
        {"oscillator", "A mass on a spring to a pinned anchor, against the exact cosine.", &oscillator},
    };
    return table;
}

const SceneInfo* find_scene(std::string_view name) {
    for (const SceneInfo& info : catalog()) {
        if (info.name == name) {
            return &info;
        }
    }
    return nullptr;
}

}  // namespace scenes
