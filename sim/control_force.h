// Control forces (the lecture's "fake / magic" forces: the player presses
// forward, a forward force is applied to the avatar, no physical reason
// asked): a scripted time table. Each key pushes its particles with a
// constant force during [start, end). Driven, not conservative: no potential.
// The viewer's mouse drag is the interactive kind: World::set_drag.
#pragma once

#include "sim/force.h"

#include <cstdint>
#include <vector>

namespace sim {

struct ControlKey {
    double start = 0.0;                    // s
    double end = 1.0;                      // s (> start); the key acts during [start, end)
    std::vector<std::uint32_t> particles;  // who is pushed (global indices)
    Vec3 force = Vec3::Zero();             // N, on each of them
};

struct ControlForces {
    std::vector<ControlKey> keys;
};

void validate(const ControlForces& c, std::size_t particle_count);
// Each listed particle's push depends on nothing else (a block picks out the
// particles it holds).
constexpr bool is_local(const ControlForces&) { return true; }
void accumulate(const ControlForces& c, const ForceInput& in, Vec3Span f);
inline double potential_energy(const ControlForces&, const ForceInput&) { return 0.0; }
// Independent of x and v: both Jacobians are zero.
inline void accumulate_jacobians(const ControlForces&, const ForceInput&, Jacobians&) {}

}  // namespace sim
