// Distance constraints solved by XPBD (Macklin, Müller and Chentanez 2016,
// "XPBD: position-based simulation of compliant constrained dynamics"): the
// lecture's answer to "k -> infinity does not work; how, then?". Instead of a
// stiff spring force (stable only for dt < 2 / ω), each constraint moves the
// particles' positions straight back to its rest length after the
// integrator's step, and the velocity follows the correction.
//
// For C(x) = |x_i - x_j| - rest, compliance α (m/N, the inverse stiffness;
// 0 is inextensible), substep h and α̃ = α / h², one Gauss-Seidel update is
//   Δλ = (-C - α̃ λ) / (w_i + w_j + α̃),   x_i += w_i Δλ n,   x_j -= w_j Δλ n
// with n = (x_i - x_j) / |x_i - x_j| and w the inverse masses (0 = pinned),
// λ the accumulated Lagrange multiplier of the substep (its force is λ / h²).
// With α = 1/k this is an implicit spring whose stiffness does not depend on
// the step or the iteration count.
#pragma once

#include "sim/vec3_array.h"

#include <cstdint>
#include <vector>

namespace sim {

// One constraint: an index record, nothing points at anything.
struct DistanceConstraint {
    std::uint32_t i = 0;      // first particle
    std::uint32_t j = 0;      // second particle (!= i)
    double rest = 1.0;        // rest length, m (>= 0)
    double compliance = 0.0;  // m/N: 1 / stiffness; 0 is inextensible
};

// A long-range attachment (Kim, Chentanez and Müller 2012, "Long range
// attachments: a method to simulate inextensible clothing in computer
// games"): particle `particle` may be at most max_distance (its rest distance
// along the body) from `anchor`, a pinned particle. One-sided, inextensible.
// Gauss-Seidel spreads a correction one link per sweep, so a chain or cloth
// hanging from pins stretches under load when iterations are few; a tether
// takes each particle straight back within reach of its pin, whatever the
// mass ratio. Jolt (its "LRA" constraints) and NvCloth (tethers) do the same.
struct Tether {
    std::uint32_t particle = 0;
    std::uint32_t anchor = 0;   // a pinned particle
    double max_distance = 1.0;  // m (>= 0)
};

struct Constraints {
    std::vector<DistanceConstraint> distance;
    std::vector<Tether> tethers;  // projected after each sweep of the distance constraints
    // Gauss-Seidel sweeps over every constraint per substep (>= 1). More
    // substeps usually beat more iterations (Macklin et al. 2019, "Small
    // steps in physics simulation"); the report measures it.
    int iterations = 1;

    bool empty() const { return distance.empty() && tethers.empty(); }
};

// Throws InputError naming the first bad constraint, e.g.
// "constraints.distance[4].compliance must be >= 0 and finite, in m/N (got -1)".
void validate(const Constraints& constraints, std::size_t particle_count);

// Solves every constraint on positions x (in place) for a substep of h > 0,
// with the particles' inverse masses. lambda is scratch (resized here).
void project(const Constraints& constraints, Vec3Span x, const double* inv_mass, double h, std::vector<double>& lambda);

// Σ C² / (2 α) over compliant constraints, J: the energy a compliant
// constraint stores, like a spring of stiffness 1/α. Inextensible ones store none.
double potential_energy(const Constraints& constraints, ConstVec3Span x);

// The largest |C| / rest over constraints with rest > 0: how far from
// inextensible the solution is (0.01 is 1% stretch).
double max_strain(const Constraints& constraints, ConstVec3Span x);

}  // namespace sim
