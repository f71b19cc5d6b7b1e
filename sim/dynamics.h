// The force evaluation an integrator calls. Integrators know nothing else of
// the system they advance: not which forces exist, not the scene.
#pragma once

#include "sim/force.h"
#include "sim/vec3_array.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace sim {

// A force that is, on every particle, f_i = m_i g - (c + c₂ |v_i|) v_i:
// uniform gravity with linear and quadratic drag, the particle-effect case.
struct UniformField {
    Vec3 g = Vec3::Zero();  // m/s²
    double c = 0.0;         // N·s/m
    double c2 = 0.0;        // N·s²/m²
    int linear_drags = 0;   // LinearDrag generators summed into c (each has its own Jacobian entries)
};

// The field's force on one particle of mass m moving at v, N: the one formula
// every loop over a field calls. Plain scalars in and out, so that the loops
// that inline it see nothing that could alias their arrays and vectorise.
// kQuadratic: c2 may be non-zero (otherwise the square root is skipped).
// kVertical: the field is along y alone (is_vertical below): m g's x and z
// are then +0 for every mass (> 0 and finite, as validate_particles asks),
// and the loop leaves out their two products with the same bits.
struct FieldForce {
    double x, y, z;  // N
};
template <bool kQuadratic, bool kVertical = false>
inline FieldForce field_force(double m, double vx, double vy, double vz, double gx, double gy, double gz, double c,
                              double c2) {
    double drag = c;  // N·s/m along -v
    if constexpr (kQuadratic) {
        drag += c2 * std::sqrt(vx * vx + vy * vy + vz * vz);
    }
    if constexpr (kVertical) {
        return {0.0 - drag * vx, m * gy - drag * vy, 0.0 - drag * vz};
    } else {
        return {m * gx - drag * vx, m * gy - drag * vy, m * gz - drag * vz};
    }
}

// Whether field_force<kQuadratic, true> gives the field's bits: g's x and z
// are +0 (not -0, whose m g would be -0), the usual gravity straight down.
inline bool is_vertical(const UniformField& field) {
    return !std::signbit(field.g.x()) && field.g.x() == 0.0 && !std::signbit(field.g.z()) && field.g.z() == 0.0;
}

struct Spring;         // sim/spring.h
struct NewtonGravity;  // sim/newton_gravity.h

// A force that is, on a system of two particles, one spring between them,
// with a uniform field or without (a bead on its anchor).
struct SpringPair {
    const Spring* spring = nullptr;
    const UniformField* field = nullptr;  // nullptr: none
};

// A force that is, on a system of two particles, Newton's gravity alone,
// with a uniform field or without (a planet around a pinned sun).
struct PairGravity {
    const NewtonGravity* gravity = nullptr;
    const UniformField* field = nullptr;  // nullptr: none
};

// The whole force on a system of two particles when it is one of the pairs
// above (at most one of spring and gravity is set), with the masses, kg, and
// inverse masses, 1/kg, of the whole system: what the explicit methods (all
// but position Verlet) need to evaluate the force inline
// (sim/pair_forces.h, pair::step_pair), in one call.
struct PairPath {
    const SpringPair* spring = nullptr;
    const PairGravity* gravity = nullptr;
    const double* mass = nullptr;
    const double* inv_mass = nullptr;
};

class Dynamics {
public:
    virtual ~Dynamics() = default;

    // The whole force as a UniformField, when it is one (else nullptr). The
    // one-stage explicit methods then evaluate it inside their update loop, so
    // a step is one pass over memory; they report those evaluations through
    // count_evaluations.
    virtual const UniformField* uniform_field() const { return nullptr; }

    // Force evaluations made outside acceleration(), per particle. Not
    // virtual: on a small step an indirect call is a cost of its own.
    void count_evaluations(std::size_t particles) { particle_evaluations_ += particles; }
    // Particle-evaluations of the force so far; divided by n it is the number
    // of whole-system force evaluations (the machine-independent cost).
    std::uint64_t particle_evaluations() const { return particle_evaluations_; }

    // The whole force on `particles` particles as a pair (PairPath; both
    // pointers nullptr where it is not one): the explicit methods (all but
    // position Verlet) then evaluate it inline (sim/pair_forces.h), their
    // stages in registers, and report the evaluations through
    // count_evaluations.
    virtual PairPath pair_path(std::size_t /*particles*/) const { return {}; }

    // True when no force reads a particle's velocity (no drag, no damper):
    // an integrator may then skip predicting the velocity a force would see.
    virtual bool velocity_free() const { return false; }

    // a = M⁻¹ f(t, x, v) for the particles [first, first + x.n); a pinned
    // particle (inverse mass 0) gets a = 0.
    virtual void acceleration(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                              const Vec3Span& a) = 0;

    // f(t, x, v) and its Jacobians for the same block, for implicit methods.
    // jac arrives empty; its indices are local to the block.
    virtual void force_and_jacobians(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                                     const Vec3Span& f, Jacobians& jac) = 0;

    // Masses of the whole system, kg, and inverse masses, 1/kg (0 = pinned).
    virtual const double* mass() const = 0;
    virtual const double* inv_mass() const = 0;

protected:
    std::uint64_t particle_evaluations_ = 0;
};

}  // namespace sim
