// The pairs' paths: the force on a system of two particles (a bead on its
// anchor, a planet around a pinned sun) with one generator between them,
// the sums in registers and each acceleration written once. On the general
// path (ParticleForces' zero or field pass, the generators, M⁻¹) the sums
// pass through memory twice more, a store and a load on the critical path of
// every RK4 stage. The same operations in the same order as that path (the
// same bits, tested: PairPaths in tests/sim/forces_test.cpp).
//
// The component arrays are anything indexed [component][particle]: a span's
// pointers (ParticleForces) or RK4's stage arrays (sim/runge_kutta.cpp,
// which evaluates a spring pair inline so that its stages stay in
// registers). Particle indices are constants throughout, for that reason.
#pragma once

#include "sim/dynamics.h"
#include "sim/integrators.h"
#include "sim/newton_gravity.h"
#include "sim/spring.h"

#include <cmath>
#include <type_traits>

namespace sim {

namespace pair {

// kStill: a particle whose acceleration the caller does not need (RK4's
// pinned anchor at rest, sim/runge_kutta.cpp), left out; -1: none.

// The field's force on particles 0 and 1 (or 0), N: where each sum starts.
struct PairForce {
    FieldForce p0{0.0, 0.0, 0.0}, p1{0.0, 0.0, 0.0};
};
template <int kStill = -1, class Components>
[[gnu::always_inline]] inline PairForce field(const UniformField* field, const Components& v, const double* mass) {
    if (field == nullptr) return {};
    auto both = [&](auto quadratic) {
        constexpr bool kQuadratic = decltype(quadratic)::value;
        const UniformField& g = *field;
        auto one = [&](int p) {
            return field_force<kQuadratic>(mass[p], v[0][p], v[1][p], v[2][p], g.g.x(), g.g.y(), g.g.z(), g.c, g.c2);
        };
        PairForce f;
        if constexpr (kStill != 0) f.p0 = one(0);
        if constexpr (kStill != 1) f.p1 = one(1);
        return f;
    };
    return field->c2 != 0.0 ? both(std::true_type{}) : both(std::false_type{});
}

// a = M⁻¹ f, written once.
template <int kStill = -1, class Components>
[[gnu::always_inline]] inline void store(const PairForce& f, const double* inv_mass, Components& a) {
    if constexpr (kStill != 0) {
        a[0][0] = f.p0.x * inv_mass[0], a[1][0] = f.p0.y * inv_mass[0], a[2][0] = f.p0.z * inv_mass[0];
    }
    if constexpr (kStill != 1) {
        a[0][1] = f.p1.x * inv_mass[1], a[1][1] = f.p1.y * inv_mass[1], a[2][1] = f.p1.z * inv_mass[1];
    }
}

// Spring s's pull, listed from particle kI to the other: kI's sum gets + g,
// the other's - g.
template <int kI, class In>
[[gnu::always_inline]] inline void spring_pull_from(const Spring& s, const In& x, const In& v, FieldForce& fi,
                                                    FieldForce& fj) {
    constexpr int kJ = 1 - kI;
    double gx, gy, gz;
    auto dv = [&v](int k) { return v[k][kJ] - v[k][kI]; };
    if (spring_pull(s, x[0][kI], x[1][kI], x[2][kI], x[0][kJ], x[1][kJ], x[2][kJ], dv, gx, gy, gz)) {
        fi.x += gx, fi.y += gy, fi.z += gz;
        fj.x -= gx, fj.y -= gy, fj.z -= gz;
    }
}

// One spring (accumulate's reference loop on one spring), listed either way.
template <int kStill = -1, class In, class Out>
[[gnu::always_inline]] inline void spring_acceleration(const SpringPair& pair, const In& x, const In& v,
                                                       const double* mass, const double* inv_mass, Out& a) {
    PairForce f = field<kStill>(pair.field, v, mass);
    const Spring& s = *pair.spring;
    if (s.i == 0) {
        spring_pull_from<0>(s, x, v, f.p0, f.p1);
    } else {
        spring_pull_from<1>(s, x, v, f.p1, f.p0);
    }
    store<kStill>(f, inv_mass, a);
}

// Newton's gravity between the two (accumulate's loop on one pair): 0 gets
// + f01, 1 gets + (-f01).
template <int kStill = -1, class In, class Out>
[[gnu::always_inline]] inline void gravity_acceleration(const PairGravity& pair, const In& x, const In& v,
                                                        const double* mass, const double* inv_mass, Out& a) {
    PairForce f = field<kStill>(pair.field, v, mass);
    const NewtonGravity& gravity = *pair.gravity;
    const double eps2 = gravity.softening * gravity.softening;
    const Vec3 d = Vec3(x[0][1], x[1][1], x[2][1]) - Vec3(x[0][0], x[1][0], x[2][0]);
    const double s2 = d.squaredNorm() + eps2;
    if (s2 != 0.0) {  // else two unsoftened particles at one point: no direction
        const Vec3 f01 = (gravity.G * mass[0] * mass[1] / (s2 * std::sqrt(s2))) * d;
        const Vec3 f10 = -f01;
        f.p0.x += f01.x(), f.p0.y += f01.y(), f.p0.z += f01.z();
        f.p1.x += f10.x(), f.p1.y += f10.y(), f.p1.z += f10.z();
    }
    store<kStill>(f, inv_mass, a);
}

// Either pair's, by its type (RK4's stages, written once for both).
template <int kStill, class In, class Out>
[[gnu::always_inline]] inline void acceleration(const SpringPair& pair, const In& x, const In& v, const double* mass,
                                                const double* inv_mass, Out& a) {
    spring_acceleration<kStill>(pair, x, v, mass, inv_mass, a);
}
template <int kStill, class In, class Out>
[[gnu::always_inline]] inline void acceleration(const PairGravity& pair, const In& x, const In& v, const double* mass,
                                                const double* inv_mass, Out& a) {
    gravity_acceleration<kStill>(pair, x, v, mass, inv_mass, a);
}

// Whether the pair's force reads the particles' velocities: a field (which
// may hold drag), a spring's damper. Where it does not, a step may pass any
// velocity (velocity Verlet its prediction's inputs) and get the same bits.
inline bool reads_velocity(const SpringPair& pair) { return pair.field != nullptr || pair.spring->c != 0.0; }
inline bool reads_velocity(const PairGravity& pair) { return pair.field != nullptr; }

// A method's pair step: where the block is two particles that Dynamics
// gives as a pair (StepArrays::pair where the caller looked it up, else
// Dynamics::pair_path), calls step(pair, path) with its SpringPair or
// PairGravity and returns true; false otherwise (the method takes its
// arrays' path). Every explicit method but position Verlet looks here
// first.
template <class F>
[[gnu::always_inline]] inline bool step_pair(const Dynamics& dynamics, const StepArrays& s, F&& step) {
    if (s.x.n != 2) return false;
    const PairPath path = s.pair != nullptr ? *s.pair : dynamics.pair_path(2);
    if (path.spring != nullptr) {
        step(*path.spring, path);
        return true;
    }
    if (path.gravity != nullptr) {
        step(*path.gravity, path);
        return true;
    }
    return false;
}

}  // namespace pair
}  // namespace sim
