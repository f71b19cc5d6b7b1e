// Newtonian gravity between every pair of particles (space scenes):
//   f_i = Σ_j G m_i m_j d_ij / (|d_ij|² + ε²)^{3/2},   d_ij = x_j - x_i
// with an optional softening length ε (Plummer) against close encounters.
// O(n²): meant for a handful of bodies, not for a particle cloud.
#pragma once

#include "sim/force.h"

namespace sim {

struct NewtonGravity {
    double G = 6.674e-11;    // gravitational constant, m³/(kg·s²) (> 0)
    double softening = 0.0;  // ε, m (>= 0); 0 is exact Newton
};

void validate(const NewtonGravity& gravity, std::size_t particle_count);
constexpr bool is_local(const NewtonGravity&) { return false; }
void accumulate(const NewtonGravity& gravity, const ForceInput& in, Vec3Span f);
// U = -Σ_{i<j} G m_i m_j / sqrt(|d_ij|² + ε²), pairs of two pinned particles left out.
double potential_energy(const NewtonGravity& gravity, const ForceInput& in);
// ∂f_i/∂x_j = G m_i m_j (I/s³ - 3 d dᵀ/s⁵), s² = |d|² + ε²; ∂f/∂v = 0.
void accumulate_jacobians(const NewtonGravity& gravity, const ForceInput& in, Jacobians& jac);

}  // namespace sim
