// The fused pass for uniform fields, which every explicit method shares
// (integrators.cpp, runge_kutta.cpp): when the whole force is a uniform
// field (gravity and drag, the particle-effect case), one loop keeps each
// particle in registers for the whole step and evaluates the field inline.
// A method gives its update of one particle as a rule (P3 values and an
// acceleration functor); fused_field_pass runs it over the block, at the
// block's width, with the watchdog's per-particle rules inside where the
// World asks for them. given_acceleration_pass runs the same rule over an
// acceleration evaluated before (the array path of the methods that
// evaluate once, at the start of the step): the same operations, the same
// bits. Internal to the integrators: not part of sim's interface.
#pragma once

#include "sim/cpu.h"
#include "sim/dynamics.h"
#include "sim/integrators.h"
#include "sim/watchdog.h"

#include <cstddef>
#include <type_traits>

// In an unnamed namespace, as when it was part of integrators.cpp: each file
// that includes it gets its own copy, and GCC inlines and vectorises these
// loops as it did there (with external linkage, the fused symplectic Euler
// step on 1e5 particles measured about a sixth slower, in one comparison).
namespace sim::fused {
namespace {

// One particle's vector as three scalars: the fused loops' working values.
struct P3 {
    double x, y, z;
};
inline P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline P3 operator*(double s, P3 a) { return {s * a.x, s * a.y, s * a.z}; }

// The field's acceleration on one particle at velocity v: field_force / m,
// the same products as ParticleForces' field pass (0 for a pinned particle).
// kVertical: is_vertical(field), the two products m 0 left out.
template <bool kQuadratic, bool kVertical>
struct FieldAcceleration {
    double gx, gy, gz, c, c2;  // UniformField's g (m/s²), c (N·s/m), c2 (N·s²/m²)
    double m, inv_m;           // this particle's mass, kg, and inverse, 1/kg
    P3 operator()(P3 v) const {
        const FieldForce f = field_force<kQuadratic, kVertical>(m, v.x, v.y, v.z, gx, gy, gz, c, c2);
        return {f.x * inv_m, f.y * inv_m, f.z * inv_m};
    }
};

// The loop itself: plain pointers and scalars only (a struct of arrays passed
// in makes GCC reload its members every iteration and give up vectorising),
// __restrict because no two arrays overlap. `memory` is the method's
// per-particle memory (s.a or s.x_prev), read and written back; unused when
// kMemory is false. rule(x, v, memory, accel, rebuild) advances one particle;
// rebuild (a std::bool_constant, so that no branch is left in the loop) says
// that the memory is not valid and must be rebuilt first. kWatch: the
// watchdog's per-particle rules on each particle's new x and v, counted into
// `watch` (StepArrays::watch; they only compare: no bit of the state changes).
template <bool kQuadratic, bool kVertical, bool kMemory, bool kFresh, bool kWatch, class Rule>
void field_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                double* __restrict v1, double* __restrict v2, double* __restrict m0, double* __restrict m1,
                double* __restrict m2, const double* __restrict mass, const double* __restrict inv_mass, std::size_t n,
                const UniformField& field, Rule rule, StepArrays::Watch* __restrict watch) {
    const double gx = field.g.x(), gy = field.g.y(), gz = field.g.z(), c = field.c, c2 = field.c2;
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0, box = kWatch ? watch->box : 0.0;
    std::size_t passed = 0;  // a count, not a bool, as in the watchdog's own loop: it stays vectorised
    for (std::size_t i = 0; i < n; ++i) {
        P3 x{x0[i], x1[i], x2[i]};
        P3 v{v0[i], v1[i], v2[i]};
        P3 memory{0.0, 0.0, 0.0};
        if constexpr (kMemory) memory = {m0[i], m1[i], m2[i]};
        rule(x, v, memory, FieldAcceleration<kQuadratic, kVertical>{gx, gy, gz, c, c2, mass[i], inv_mass[i]},
             std::bool_constant<kFresh>{});
        x0[i] = x.x, x1[i] = x.y, x2[i] = x.z;
        v0[i] = v.x, v1[i] = v.y, v2[i] = v.z;
        if constexpr (kMemory) m0[i] = memory.x, m1[i] = memory.y, m2[i] = memory.z;
        if constexpr (kWatch) passed += passes(x.x, x.y, x.z, v.x, v.y, v.z, max_speed2, box);
    }
    if constexpr (kWatch) watch->suspects += n - passed, watch->counted = true;
}

// Runs `rule` on every particle of the block when the force is a uniform
// field, counting `evaluations` force evaluations per particle; false (and
// nothing done) otherwise. `memory`: the method's memory span, or an empty one
// (then no rule reads `rebuild`, and one build serves fresh steps and later).
template <bool kQuadratic, bool kMemory, class Rule>
void field_loop_for(bool fresh, const StepArrays& s, Vec3Span memory, const double* mass, const double* inv_mass,
                    const UniformField& field, Rule rule) {
    auto run = [&](auto vertical, auto fresh_constant, auto watch_constant) {
        run_at_width(
            s.wide_loops(),
            [](auto... a) {
                field_loop<kQuadratic, decltype(vertical)::value, kMemory, decltype(fresh_constant)::value,
                           decltype(watch_constant)::value, Rule>(a...);
            },
            s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], memory.c[0], memory.c[1], memory.c[2], mass,
            inv_mass, s.x.n, field, rule, s.watch);
    };
    auto with_fresh = [&](auto vertical, auto watch) {
        if constexpr (kMemory) {
            fresh ? run(vertical, std::true_type{}, watch) : run(vertical, std::false_type{}, watch);
        } else {
            run(vertical, std::false_type{}, watch);
        }
    };
    auto with_watch = [&](auto vertical) {
        s.watch != nullptr ? with_fresh(vertical, std::true_type{}) : with_fresh(vertical, std::false_type{});
    };
    is_vertical(field) ? with_watch(std::true_type{}) : with_watch(std::false_type{});
}

// The acceleration a force evaluation left in an array, for one particle.
// The methods that evaluate forces once, at the start of the step (Euler,
// Störmer), run their fused rule over it on the array path too: one loop, the
// same operations.
struct GivenAcceleration {
    P3 a;  // m/s²
    P3 operator()(P3) const { return a; }
};

template <bool kMemory, bool kFresh, bool kWatch, class Rule>
void given_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                double* __restrict v1, double* __restrict v2, double* __restrict m0, double* __restrict m1,
                double* __restrict m2, const double* __restrict a0, const double* __restrict a1,
                const double* __restrict a2, std::size_t n, Rule rule, StepArrays::Watch* __restrict watch) {
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0, box = kWatch ? watch->box : 0.0;
    std::size_t passed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        P3 x{x0[i], x1[i], x2[i]};
        P3 v{v0[i], v1[i], v2[i]};
        P3 memory{0.0, 0.0, 0.0};
        if constexpr (kMemory) memory = {m0[i], m1[i], m2[i]};
        rule(x, v, memory, GivenAcceleration{{a0[i], a1[i], a2[i]}}, std::bool_constant<kFresh>{});
        x0[i] = x.x, x1[i] = x.y, x2[i] = x.z;
        v0[i] = v.x, v1[i] = v.y, v2[i] = v.z;
        if constexpr (kMemory) m0[i] = memory.x, m1[i] = memory.y, m2[i] = memory.z;
        if constexpr (kWatch) passed += passes(x.x, x.y, x.z, v.x, v.y, v.z, max_speed2, box);
    }
    if constexpr (kWatch) watch->suspects += n - passed, watch->counted = true;
}

// Runs `rule` on every particle of the block with the acceleration `a`
// evaluated before, the watchdog's rules inside where s.watch is set.
// `memory`: the method's memory span, or an empty one.
template <class Rule>
void given_acceleration_pass(const StepArrays& s, Vec3Span memory, ConstVec3Span a, Rule rule) {
    auto run = [&](auto has_memory, auto fresh, auto watch) {
        run_at_width(
            s.wide_loops(),
            [](auto... p) {
                given_loop<decltype(has_memory)::value, decltype(fresh)::value, decltype(watch)::value, Rule>(p...);
            },
            s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], memory.c[0], memory.c[1], memory.c[2], a.c[0],
            a.c[1], a.c[2], s.x.n, rule, s.watch);
    };
    auto with_memory = [&](auto has_memory) {
        const bool fresh = !s.memory_valid, watch = s.watch != nullptr;
        if (fresh) {
            watch ? run(has_memory, std::true_type{}, std::true_type{})
                  : run(has_memory, std::true_type{}, std::false_type{});
        } else {
            watch ? run(has_memory, std::false_type{}, std::true_type{})
                  : run(has_memory, std::false_type{}, std::false_type{});
        }
    };
    memory.n == 0 ? with_memory(std::false_type{}) : with_memory(std::true_type{});
}

template <class Rule>
bool fused_field_pass(Dynamics& dynamics, const StepArrays& s, Vec3Span memory, int evaluations, Rule rule) {
    const UniformField* field = dynamics.uniform_field();
    if (field == nullptr) return false;
    const double* mass = dynamics.mass() + s.first;
    const double* inv_mass = dynamics.inv_mass() + s.first;
    const bool fresh = !s.memory_valid;
    const bool quadratic = field->c2 != 0.0;
    if (memory.n == 0) {
        (quadratic ? field_loop_for<true, false, Rule> : field_loop_for<false, false, Rule>)(fresh, s, memory, mass,
                                                                                             inv_mass, *field, rule);
    } else {
        (quadratic ? field_loop_for<true, true, Rule> : field_loop_for<false, true, Rule>)(fresh, s, memory, mass,
                                                                                           inv_mass, *field, rule);
    }
    dynamics.count_evaluations(static_cast<std::size_t>(evaluations) * s.x.n);
    return true;
}

}  // namespace
}  // namespace sim::fused
