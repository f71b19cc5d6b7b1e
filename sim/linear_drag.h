// Linear (viscous, Stokes) drag: f_i = -c v_i. Dissipative, no potential.
#pragma once

#include "sim/force.h"

namespace sim {

struct LinearDrag {
    double c = 0.1;  // drag coefficient, N·s/m (>= 0)
};

void validate(const LinearDrag& drag, std::size_t particle_count);
constexpr bool is_local(const LinearDrag&) { return true; }
void accumulate(const LinearDrag& drag, const ForceInput& in, Vec3Span f);
inline double potential_energy(const LinearDrag&, const ForceInput&) { return 0.0; }
// ∂f/∂v = -c I per particle; ∂f/∂x = 0.
void accumulate_jacobians(const LinearDrag& drag, const ForceInput& in, Jacobians& jac);

}  // namespace sim
