// A cosmetic particle emitter: the lecture's particle effects (sparks, water,
// debris) that look physical but feed nothing back into the game.
//
// The emitter owns `count` particles of the model and gives birth to them in
// turn at `rate` per second, so each lives count / rate seconds and is then
// reborn at the nozzle: particle k's n-th birth is at t = (k + n count) / rate.
// A newborn leaves the nozzle at speed (1 ± jitter) inside a cone around
// `direction`, drawn from the project PRNG seeded by (seed, k, n): a pure
// function of the birth, so a rewound or replayed run is reborn identically.
// Before its first birth a particle is parked, pinned, far below the nozzle
// (it collides with nothing and is not drawn).
#pragma once

#include "sim/particles.h"

#include <cstdint>
#include <vector>

namespace sim {

struct Emitter {
    std::uint32_t first = 0;  // particles [first, first + count) are the emitter's
    std::uint32_t count = 0;
    Vec3 position = Vec3::Zero();    // m, the nozzle
    Vec3 direction = Vec3::UnitY();  // unit
    double cone = 10.0;              // degrees, half-angle of the spray cone
    double speed = 5.0;              // m/s
    double speed_jitter = 0.1;       // fraction of speed, uniform ±
    double rate = 100.0;             // particles/s (> 0)
    std::uint64_t seed = 1;

    double lifetime() const { return count / rate; }  // s
};

// Throws InputError naming the field, e.g. "emitters[0].rate must be > 0 ...".
void validate(const Emitter& emitter, std::size_t particle_count, std::size_t index);

// Where particle k waits before its first birth.
Vec3 parked_position(const Emitter& emitter);

// True once particle k (0-based within the emitter) has been born before
// time t, i.e. emitted by a step that ended at or before t.
bool born(const Emitter& emitter, std::uint32_t k, double t);

// Births in [t0, t1): each reborn particle goes back to the nozzle with its
// new velocity and its inverse mass. Returns how many were born. Throws
// InputError once t1 · rate passes 2^53 births (where a double no longer
// counts them one by one: 28 years at 10 million a second).
std::size_t emit(const Emitter& emitter, double t0, double t1, ParticleState& state);

}  // namespace sim
