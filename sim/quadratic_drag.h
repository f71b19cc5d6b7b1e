// Quadratic (aerodynamic) drag: f_i = -c |v_i| v_i, with c = ½ ρ C_d A folded
// into one coefficient. Dissipative, no potential.
#pragma once

#include "sim/force.h"

namespace sim {

struct QuadraticDrag {
    double c = 0.01;  // drag coefficient, N·s²/m² (>= 0)
};

void validate(const QuadraticDrag& drag, std::size_t particle_count);
constexpr bool is_local(const QuadraticDrag&) { return true; }
void accumulate(const QuadraticDrag& drag, const ForceInput& in, Vec3Span f);
inline double potential_energy(const QuadraticDrag&, const ForceInput&) { return 0.0; }
// ∂f/∂v = -c (|v| I + v vᵀ / |v|) per particle (0 at rest); ∂f/∂x = 0.
void accumulate_jacobians(const QuadraticDrag& drag, const ForceInput& in, Jacobians& jac);

}  // namespace sim
