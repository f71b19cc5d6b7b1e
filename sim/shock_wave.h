// A shock wave (an explosion): a spherical front leaves `center` at
// `start_time` and expands at `speed`, R(t) = speed (t - start_time). It is a
// shell of `thickness`: a particle at distance r is pushed radially outward
// while |r - R(t)| < thickness / 2, with a force that falls off with
// distance, strength (r_ref / max(r, r_ref))². So it acts once, as the front
// passes, for thickness / speed seconds: a particle held still gets the
// impulse strength (r_ref / r)² thickness / speed.
#pragma once

#include "sim/force.h"

namespace sim {

struct ShockWave {
    Vec3 center = Vec3::Zero();       // m
    double start_time = 0.0;          // s
    double speed = 20.0;              // m/s (> 0)
    double thickness = 0.5;           // m (> 0)
    double strength = 100.0;          // N at reference_distance (>= 0)
    double reference_distance = 1.0;  // m (> 0); closer particles get the same force
    double max_radius = 0.0;          // m: the front dies out beyond it (0: never)
};

void validate(const ShockWave& s, std::size_t particle_count);
constexpr bool is_local(const ShockWave&) { return true; }
void accumulate(const ShockWave& s, const ForceInput& in, Vec3Span f);
inline double potential_energy(const ShockWave&, const ForceInput&) { return 0.0; }  // driven
// None: a brief push, taken explicitly by implicit methods.
inline void accumulate_jacobians(const ShockWave&, const ForceInput&, Jacobians&) {}

}  // namespace sim
