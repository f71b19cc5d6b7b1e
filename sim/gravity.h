// Uniform gravity near a planet's surface: f_i = m_i g.
#pragma once

#include "sim/force.h"

namespace sim {

struct UniformGravity {
    Vec3 g = Vec3(0.0, -9.81, 0.0);  // acceleration of free fall, m/s² (Y is up)
};

void validate(const UniformGravity& gravity, std::size_t particle_count);
constexpr bool is_local(const UniformGravity&) { return true; }
void accumulate(const UniformGravity& gravity, const ForceInput& in, Vec3Span f);
// U = -Σ m_i g · x_i over moving particles (a pinned one's is constant: left out).
double potential_energy(const UniformGravity& gravity, const ForceInput& in);
// Constant force: both Jacobians are zero.
inline void accumulate_jacobians(const UniformGravity&, const ForceInput&, Jacobians&) {}

}  // namespace sim
