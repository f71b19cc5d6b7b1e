// The loader's ghost reader: [[ghosts]], the closed-form trajectory of one
// particle (or a rigid body's centre of mass) drawn beside the simulation and
// measured against. Each closed form is derived from the scene's own
// parameters, and refused when the scene breaks its assumptions.
#include "scenes/model/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace scenes::loader {
namespace {

using Exact = std::function<sim::analytic::PointState(double t)>;

// A particle's ghost: the particle, its start and what the scene's forces are.
struct ParticleGhost {
    const SceneBuilder& b;
    const Section& s;
    std::size_t particle;
    const sim::ParticleDef& p;
    sim::Vec3 x0, v0;                    // m, m/s: the particle's start
    const sim::UniformGravity* gravity;  // none when the scene has no uniform gravity
    std::size_t coupled;                 // springs in the scene
    bool drag;                           // linear or quadratic drag

    // A pinned particle the key names (an anchor, a centre).
    std::size_t pinned_ref(std::string_view key) const {
        const std::size_t a = b.particle_ref(s, key);
        if (!b.scene.model.particles[a].pinned) s.fail(key, "must name a pinned particle");
        return a;
    }
    // The spring joining the particle and `other`, or none.
    const sim::Spring* spring_to(std::size_t other) const {
        if (const sim::Springs* springs = b.find_force<sim::Springs>()) {
            for (const sim::Spring& sp : springs->list) {
                if ((sp.i == particle && sp.j == other) || (sp.i == other && sp.j == particle)) return &sp;
            }
        }
        return nullptr;
    }
};

Exact ballistic(const ParticleGhost& g) {
    if (g.gravity == nullptr || g.drag || g.coupled > 0 || g.b.find_force<sim::NewtonGravity>() != nullptr) {
        g.s.fail("solution", "'ballistic' needs uniform gravity and no drag, springs or Newtonian gravity");
    }
    const sim::Vec3 x0 = g.x0, v0 = g.v0, gv = g.gravity->g;
    return [=](double t) { return sim::analytic::ballistic(x0, v0, gv, t); };
}

Exact oscillator(const ParticleGhost& g) {
    const std::size_t a = g.pinned_ref("anchor");
    const sim::Spring* sp = g.spring_to(a);
    if (sp == nullptr || sp->rest != 0.0 || g.coupled != 1 || g.gravity != nullptr || g.drag) {
        g.s.fail("solution",
                 "'oscillator' needs exactly one zero-rest-length spring to the anchor, and no gravity or drag");
    }
    const sim::analytic::Oscillator o{g.p.mass, sp->k, sp->c};
    const sim::Vec3 anchor = g.b.scene.model.particles[a].position, x0 = g.x0, v0 = g.v0;
    return [=](double t) {
        sim::analytic::PointState st = sim::analytic::oscillator(o, x0 - anchor, v0, t);
        st.x += anchor;
        return st;
    };
}

Exact kepler(const ParticleGhost& g) {
    const std::vector<sim::ParticleDef>& particles = g.b.scene.model.particles;
    const std::size_t c = g.pinned_ref("center");
    const sim::NewtonGravity* ng = g.b.find_force<sim::NewtonGravity>();
    if (ng == nullptr || ng->softening != 0.0 || g.gravity != nullptr || g.drag || g.coupled > 0 ||
        particles.size() != 2) {
        g.s.fail("solution", "'kepler' needs two particles, Newtonian gravity without softening, and no other force");
    }
    const double mu = ng->G * particles[c].mass;
    const sim::Vec3 centre = particles[c].position, x0 = g.x0, v0 = g.v0;
    if ((v0.squaredNorm() / 2 - mu / (x0 - centre).norm()) >= 0)
        g.s.fail("particle", "is not on a bound orbit (energy >= 0)");
    // The closed form's own test too, which `run` meets at the first frame
    // (exit 1 if it failed there): a particle on the centre (r = 0, which
    // the energy above takes for -inf, bound), or an energy that rounds to
    // bound above and not in the vis-viva form 2 / r - v² / μ.
    try {
        sim::analytic::orbit_elements(mu, x0 - centre, v0);
    } catch (const std::domain_error& e) {
        g.s.fail("particle", "has no closed-form orbit about the centre (" + std::string(e.what()) + ")");
    }
    return [=](double t) {
        sim::analytic::PointState st = sim::analytic::kepler(mu, x0 - centre, v0, t);
        st.x += centre;
        return st;
    };
}

// The small-angle closed form about a pinned anchor.
Exact pendulum(const ParticleGhost& g) {
    const std::size_t a = g.pinned_ref("anchor");
    const sim::Spring* sp = g.spring_to(a);
    if (sp == nullptr || g.gravity == nullptr || g.coupled != 1 || g.drag || !(sp->k > 0)) {
        g.s.fail("solution", "'pendulum' needs gravity and one spring (the rod) to the anchor, and no drag");
    }
    const sim::Vec3 anchor = g.b.scene.model.particles[a].position;
    const double gn = g.gravity->g.norm();
    const sim::Vec3 down = g.gravity->g / gn;
    // The spring rod stretches by m g / k under the bob's weight: that is the length that swings.
    const double length = sp->rest + g.p.mass * gn / sp->k;
    const sim::Vec3 d = g.x0 - anchor;
    sim::Vec3 side = d - d.dot(down) * down;
    const double theta0 = std::atan2(side.norm(), d.dot(down));
    side = side.norm() > 0 ? sim::Vec3(side.normalized()) : sim::Vec3::UnitX();
    const double theta_dot0 = g.v0.dot(side) / length;
    if (std::abs(theta0) > 30.0 * std::numbers::pi / 180.0) {
        g.s.fail("particle",
                 "starts more than 30 degrees from the vertical: the small-angle closed form does not hold");
    }
    return [=](double t) {
        const auto ang = sim::analytic::small_angle_pendulum(length, gn, theta0, theta_dot0, t);
        const sim::Vec3 radial = std::sin(ang.theta) * side + std::cos(ang.theta) * down;
        const sim::Vec3 tangent = std::cos(ang.theta) * side - std::sin(ang.theta) * down;
        return sim::analytic::PointState{anchor + length * radial, length * ang.omega * tangent};
    };
}

// A rigid body's centre of mass in free flight: a parabola, whatever the body spins.
Ghost body_ghost(const SceneBuilder& b, const Section& s) {
    Ghost g;
    const std::string name = s.string("body", "");
    const auto& names = b.scene.body_names;
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) s.fail("body", "names no body (got " + quote(name) + ")");
    if (s.node("particle") != nullptr) s.fail("particle", "and body cannot both be given");
    g.body = static_cast<int>(it - names.begin());
    g.solution = s.word("solution", "", {"ballistic"});
    const sim::BodyDef& body = b.scene.model.rigid.bodies[static_cast<std::size_t>(g.body)];
    const sim::Vec3 x0 = body.position, v0 = body.velocity, gv = b.scene.model.rigid.settings.gravity;
    g.exact = [=](double t) { return sim::analytic::ballistic(x0, v0, gv, t); };
    return g;
}

Ghost particle_ghost(const SceneBuilder& b, const Section& s) {
    Ghost g;
    g.particle = b.particle_ref(s, "particle");
    g.solution = s.word("solution", "", {"ballistic", "oscillator", "kepler", "pendulum"});
    const sim::ParticleDef& p = b.scene.model.particles[g.particle];
    if (p.pinned) s.fail("particle", "is pinned: it has no trajectory to compare");
    const sim::Springs* springs = b.find_force<sim::Springs>();
    const bool drag = b.find_force<sim::LinearDrag>() != nullptr || b.find_force<sim::QuadraticDrag>() != nullptr;
    const ParticleGhost pg{.b = b,
                           .s = s,
                           .particle = g.particle,
                           .p = p,
                           .x0 = p.position,
                           .v0 = p.velocity,
                           .gravity = b.find_force<sim::UniformGravity>(),
                           .coupled = springs != nullptr ? springs->list.size() : 0,
                           .drag = drag};
    g.exact = g.solution == "ballistic"    ? ballistic(pg)
              : g.solution == "oscillator" ? oscillator(pg)
              : g.solution == "kepler"     ? kepler(pg)
                                           : pendulum(pg);
    return g;
}

}  // namespace

void read_ghosts(SceneBuilder& b, const Section& top) {
    for (const Section& s : top.entries("ghosts", 64)) {
        s.only(keys::ghost);
        b.scene.ghosts.push_back(s.node("body") != nullptr ? body_ghost(b, s) : particle_ghost(b, s));
    }
}

}  // namespace scenes::loader
