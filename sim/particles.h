// Particles: what a particle system is (ParticleDef, fixed once built) and the
// state that steps (ParticleState: flat arrays, changed every step).
#pragma once

#include "sim/vec3_array.h"

#include <cstddef>
#include <vector>

namespace sim {

// One particle as a scene describes it.
struct ParticleDef {
    Vec3 position = Vec3::Zero();  // m
    Vec3 velocity = Vec3::Zero();  // m/s (ignored and zero when pinned)
    double mass = 1.0;             // kg, > 0 and finite (pinned ones too: forces read it)
    bool pinned = false;           // a pinned particle never moves (inverse mass 0)
    double radius = 0.0;           // m, >= 0: its sphere for collisions (0: a point)
};

// The mutable state of n particles. Everything here is plain arrays indexed by
// particle; nothing points at anything.
struct ParticleState {
    double t = 0.0;                // simulated time, s
    Vec3Array x;                   // position (n x 3), m
    Vec3Array v;                   // velocity (n x 3), m/s
    std::vector<double> mass;      // (n), kg
    std::vector<double> inv_mass;  // (n), 1/kg; 0 means pinned

    std::size_t size() const { return mass.size(); }
};

// Checks every particle (finite position and velocity, mass > 0 and finite) and
// throws InputError naming the first bad one, e.g. "particles[3].mass must be
// > 0 (got -1)".
void validate_particles(const std::vector<ParticleDef>& particles);

// The state at t = 0 for validated particles. Pinned particles get inverse
// mass 0 and velocity 0.
ParticleState make_state(const std::vector<ParticleDef>& particles);

}  // namespace sim
