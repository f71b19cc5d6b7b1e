// Buoyancy (the lecture's "forza di Archimede"): a particle is a sphere of
// radius r; under a horizontal water surface at height s (Y is up) its
// submerged part is a spherical cap of depth h = clamp(s - (y - r), 0, 2r)
// and volume V(h) = π h² (3r - h) / 3. The fluid pushes it up with the
// weight of that volume, ρ g V(h), and drags it with a linear drag scaled by
// the submerged fraction V / (4/3 π r³). A particle of density ρ_p < ρ floats
// where V(h) / V_sphere = ρ_p / ρ; a denser one sinks.
#pragma once

#include "sim/force.h"

#include <cstdint>
#include <vector>

namespace sim {

struct Buoyancy {
    double surface_height = 0.0;           // m, the water plane's y
    double fluid_density = 1000.0;         // kg/m³ (> 0)
    double gravity = 9.81;                 // m/s², the magnitude of g (acting along -y)
    double radius = 0.1;                   // m, each particle's sphere (> 0)
    double drag = 0.0;                     // N·s/m, linear drag when fully submerged (>= 0)
    std::vector<std::uint32_t> particles;  // the ones that float (global indices); empty: all
};

// Submerged cap volume of a sphere of radius r at submerged depth h in [0, 2r], m³.
double cap_volume(double r, double h);

void validate(const Buoyancy& b, std::size_t particle_count);
constexpr bool is_local(const Buoyancy&) { return true; }  // each particle alone
void accumulate(const Buoyancy& b, const ForceInput& in, Vec3Span f);
// U = ρ g ∫₀^u V(s) ds over the unclamped depth u = s - (y - r), so that
// f_y = -dU/dy: π ρ g (r u³ - u⁴/4) / 3 while partly submerged, then growing
// by ρ g V_sphere per metre deeper.
double potential_energy(const Buoyancy& b, const ForceInput& in);
// ∂f_y/∂y = -ρ g π h (2r - h) from the cap, and the drag's ∂/∂v and ∂/∂y.
void accumulate_jacobians(const Buoyancy& b, const ForceInput& in, Jacobians& jac);

}  // namespace sim
