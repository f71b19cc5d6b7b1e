// Integrators over flat particle arrays. Contents:
//   1. array helpers
//   2. the fused pass for uniform fields (every method's update in one loop)
//   3. explicit one-stage methods: forward Euler, symplectic Euler
//   4. Verlet family: leapfrog, velocity Verlet, Störmer (position) Verlet
//   5. explicit Runge-Kutta from a Butcher tableau: RK4
//   6. the table's look-ups
// (Backward Euler, one Newton step on the linearised forces, is in
// backward_euler.cpp.)
//
// Notation: h is the step, x and v the state at t, a = M⁻¹ f(t, x, v).
// "Order" is the global order of the position error at a fixed end time.
//
// Each explicit method has two paths with the same arithmetic: over arrays
// (one pass per line of the update, any force) and, when the whole force is
// a uniform field (gravity and drag, the particle-effect case), one fused
// loop that keeps each particle in registers for the whole step and
// evaluates the field inline. Every particle sees the same operations in the
// same order on both paths, so they give the same bits (tested); the fused
// one is as fast as a hand-written loop of the method.
#include "sim/integrators.h"

#include "sim/cpu.h"
#include "sim/watchdog.h"

#include <algorithm>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

namespace sim {

// 1. Array helpers ---------------------------------------------------------

namespace {

// The array paths' loops take __restrict parameters (the arrays never
// overlap), so that each is one vectorised loop over the particles with no
// run-time overlap checks; every point gets the same operations in the same
// order as the fused rules. Each loop is built twice (sim/cpu.h's
// run_at_width): for the pinned instruction set and, on a block of more than
// a few particles where the CPU has it, for AVX2, four doubles a register
// instead of two. Products and sums are correctly rounded at any width and
// nothing is fused (-ffp-contract=off), so both give the same bits (tested).

// The watchdog's per-particle rules in leapfrog's and velocity Verlet's
// passes (when kWatch, counted into `watch`, as the fused loops do: the World
// then needs no pass of its own over the block): the first pass leaves each
// particle's x final and checks it, the last kick its v. Each pass reads only
// what it writes anyway.

// The last kick, v += alpha a; kWatch: the rules on v.
template <bool kWatch>
void kick_loop(double* __restrict v0, double* __restrict v1, double* __restrict v2, const double* __restrict a0,
               const double* __restrict a1, const double* __restrict a2, std::size_t n, double alpha,
               StepArrays::Watch* __restrict watch) {
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0;
    std::size_t count = 0;  // a count, not a bool: the loop stays vectorised
    for (std::size_t i = 0; i < n; ++i) {
        v0[i] += alpha * a0[i];
        v1[i] += alpha * a1[i];
        v2[i] += alpha * a2[i];
        if constexpr (kWatch) count += is_suspect_velocity(v0[i], v1[i], v2[i], max_speed2);
    }
    if constexpr (kWatch) watch->suspects += count, watch->counted = true;
}
void last_kick(const StepArrays& s, double alpha, const Vec3Span& a) {
    auto run = [&](auto watch_constant) {
        run_at_width(
            s.wide_loops(), [](auto... p) { kick_loop<decltype(watch_constant)::value>(p...); }, s.v.c[0], s.v.c[1],
            s.v.c[2], a.c[0], a.c[1], a.c[2], s.x.n, alpha, s.watch);
    };
    s.watch != nullptr ? run(std::true_type{}) : run(std::false_type{});
}

// Leapfrog's kick and drift: v += (h/2) a, then x += h v; kWatch: the rules
// on x.
template <bool kWatch>
void kick_drift_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                     double* __restrict v1, double* __restrict v2, const double* __restrict a0,
                     const double* __restrict a1, const double* __restrict a2, std::size_t n, double h,
                     StepArrays::Watch* __restrict watch) {
    const double box = kWatch ? watch->box : 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        v0[i] += (0.5 * h) * a0[i], v1[i] += (0.5 * h) * a1[i], v2[i] += (0.5 * h) * a2[i];
        x0[i] += h * v0[i], x1[i] += h * v1[i], x2[i] += h * v2[i];
        if constexpr (kWatch) count += is_suspect_position(x0[i], x1[i], x2[i], box);
    }
    if constexpr (kWatch) watch->suspects += count;
}

// Velocity Verlet's first half: the predicted velocity w = v + h a (when
// kPredict: a force that reads no velocity needs none), the drift
// x += h v + (h²/2) a, the kick v += (h/2) a; kWatch: the rules on x.
template <bool kPredict, bool kWatch>
void verlet_first_half_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                            double* __restrict v1, double* __restrict v2, const double* __restrict a0,
                            const double* __restrict a1, const double* __restrict a2, double* __restrict w0,
                            double* __restrict w1, double* __restrict w2, std::size_t n, double h,
                            StepArrays::Watch* __restrict watch) {
    const double box = kWatch ? watch->box : 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if constexpr (kPredict) w0[i] = v0[i] + h * a0[i], w1[i] = v1[i] + h * a1[i], w2[i] = v2[i] + h * a2[i];
        x0[i] += h * v0[i] + 0.5 * h * h * a0[i];
        x1[i] += h * v1[i] + 0.5 * h * h * a1[i];
        x2[i] += h * v2[i] + 0.5 * h * h * a2[i];
        v0[i] += (0.5 * h) * a0[i], v1[i] += (0.5 * h) * a1[i], v2[i] += (0.5 * h) * a2[i];
        if constexpr (kWatch) count += is_suspect_position(x0[i], x1[i], x2[i], box);
    }
    if constexpr (kWatch) watch->suspects += count;
}

// Fills s.a with a(t, x, v) unless it still holds it from the last step.
void ensure_acceleration(Dynamics& dynamics, const StepArrays& s, double t) {
    if (!s.memory_valid) {
        dynamics.acceleration(t, s.first, s.x, s.v, s.a);
    }
}

// 2. The fused pass for uniform fields ----------------------------------------

// One particle's vector as three scalars: the fused loops' working values.
struct P3 {
    double x, y, z;
};
inline P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline P3 operator*(double s, P3 a) { return {s * a.x, s * a.y, s * a.z}; }

// The field's acceleration on one particle at velocity v: field_force / m,
// the same products as ParticleForces' field pass (0 for a pinned particle).
template <bool kQuadratic>
struct FieldAcceleration {
    double gx, gy, gz, c, c2;  // UniformField's g (m/s²), c (N·s/m), c2 (N·s²/m²)
    double m, inv_m;           // this particle's mass, kg, and inverse, 1/kg
    P3 operator()(P3 v) const {
        const FieldForce f = field_force<kQuadratic>(m, v.x, v.y, v.z, gx, gy, gz, c, c2);
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
template <bool kQuadratic, bool kMemory, bool kFresh, bool kWatch, class Rule>
void field_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                double* __restrict v1, double* __restrict v2, double* __restrict m0, double* __restrict m1,
                double* __restrict m2, const double* __restrict mass, const double* __restrict inv_mass, std::size_t n,
                const UniformField& field, Rule rule, StepArrays::Watch* __restrict watch) {
    const double gx = field.g.x(), gy = field.g.y(), gz = field.g.z(), c = field.c, c2 = field.c2;
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0, box = kWatch ? watch->box : 0.0;
    std::size_t count = 0;  // a count, not a bool, as in the watchdog's own loop: it stays vectorised
    for (std::size_t i = 0; i < n; ++i) {
        P3 x{x0[i], x1[i], x2[i]};
        P3 v{v0[i], v1[i], v2[i]};
        P3 memory{0.0, 0.0, 0.0};
        if constexpr (kMemory) memory = {m0[i], m1[i], m2[i]};
        rule(x, v, memory, FieldAcceleration<kQuadratic>{gx, gy, gz, c, c2, mass[i], inv_mass[i]},
             std::bool_constant<kFresh>{});
        x0[i] = x.x, x1[i] = x.y, x2[i] = x.z;
        v0[i] = v.x, v1[i] = v.y, v2[i] = v.z;
        if constexpr (kMemory) m0[i] = memory.x, m1[i] = memory.y, m2[i] = memory.z;
        if constexpr (kWatch) count += is_suspect(x.x, x.y, x.z, v.x, v.y, v.z, max_speed2, box);
    }
    if constexpr (kWatch) watch->suspects += count, watch->counted = true;
}

// Runs `rule` on every particle of the block when the force is a uniform
// field, counting `evaluations` force evaluations per particle; false (and
// nothing done) otherwise. `memory`: the method's memory span, or an empty one.
template <bool kQuadratic, bool kMemory, class Rule>
void field_loop_for(bool fresh, const StepArrays& s, Vec3Span memory, const double* mass, const double* inv_mass,
                    const UniformField& field, Rule rule) {
    auto run = [&](auto fresh_constant, auto watch_constant) {
        run_at_width(
            s.wide_loops(),
            [](auto... a) {
                field_loop<kQuadratic, kMemory, decltype(fresh_constant)::value, decltype(watch_constant)::value, Rule>(
                    a...);
            },
            s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], memory.c[0], memory.c[1], memory.c[2], mass,
            inv_mass, s.x.n, field, rule, s.watch);
    };
    if (s.watch != nullptr) {
        fresh ? run(std::true_type{}, std::true_type{}) : run(std::false_type{}, std::true_type{});
    } else {
        fresh ? run(std::true_type{}, std::false_type{}) : run(std::false_type{}, std::false_type{});
    }
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
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        P3 x{x0[i], x1[i], x2[i]};
        P3 v{v0[i], v1[i], v2[i]};
        P3 memory{0.0, 0.0, 0.0};
        if constexpr (kMemory) memory = {m0[i], m1[i], m2[i]};
        rule(x, v, memory, GivenAcceleration{{a0[i], a1[i], a2[i]}}, std::bool_constant<kFresh>{});
        x0[i] = x.x, x1[i] = x.y, x2[i] = x.z;
        v0[i] = v.x, v1[i] = v.y, v2[i] = v.z;
        if constexpr (kMemory) m0[i] = memory.x, m1[i] = memory.y, m2[i] = memory.z;
        if constexpr (kWatch) count += is_suspect(x.x, x.y, x.z, v.x, v.y, v.z, max_speed2, box);
    }
    if constexpr (kWatch) watch->suspects += count, watch->counted = true;
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

// 3. Explicit one-stage methods -------------------------------------------------

// The two Euler updates of one particle's component, given its acceleration.
enum class Euler { forward, symplectic };

template <Euler kKind>
inline void euler_update(double& x, double& v, double a, double h) {
    if constexpr (kKind == Euler::forward) {
        x += h * v;  // old velocity
        v += h * a;
    } else {
        v += h * a;
        x += h * v;  // new velocity
    }
}

template <Euler kKind>
void euler_step(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    auto rule = [h](P3& x, P3& v, P3&, const auto& accel, auto) {
        const P3 a = accel(v);
        euler_update<kKind>(x.x, v.x, a.x, h);
        euler_update<kKind>(x.y, v.y, a.y, h);
        euler_update<kKind>(x.z, v.z, a.z, h);
    };
    if (fused_field_pass(dynamics, s, {}, 1, rule)) return;
    const Vec3Span a = s.scratch(0);
    dynamics.acceleration(t, s.first, s.x, s.v, a);
    given_acceleration_pass(s, {}, a, rule);
}

}  // namespace

// Forward (explicit) Euler, order 1:
//   x' = x + h v
//   v' = v + h a(t, x, v)
// Position moves with the old velocity. On an undamped oscillator the energy
// grows by a factor (1 + ω²h²) per step: the pendulum swings wider and wider.
void forward_euler(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    euler_step<Euler::forward>(dynamics, s, t, h);
}

// Symplectic (semi-implicit) Euler, order 1:
//   v' = v + h a(t, x, v)
//   x' = x + h v'
// The same two lines with the order flipped: position moves with the new
// velocity. Symplectic, so the energy of an oscillator stays in a band.
void symplectic_euler(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    euler_step<Euler::symplectic>(dynamics, s, t, h);
}

// 4. Verlet family -----------------------------------------------------------

// Leapfrog, kick-drift-kick, order 2:
//   v½ = v + (h/2) a(t, x, v)           kick
//   x' = x + h v½                        drift
//   v' = v½ + (h/2) a(t + h, x', v½)     kick
// The last acceleration is the next step's first (kept in s.a), so it costs
// one force evaluation per step. Exact for a constant force.
void leapfrog(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const bool fresh = !s.memory_valid;  // s.a must be evaluated first
    auto rule = [h](P3& x, P3& v, P3& a, const auto& accel, auto rebuild) {
        if (rebuild) a = accel(v);
        v = v + (0.5 * h) * a;
        x = x + h * v;
        a = accel(v);
        v = v + (0.5 * h) * a;
    };
    if (fused_field_pass(dynamics, s, s.a, fresh ? 2 : 1, rule)) return;
    ensure_acceleration(dynamics, s, t);
    auto run = [&](auto watch_constant) {
        run_at_width(
            s.wide_loops(), [](auto... a) { kick_drift_loop<decltype(watch_constant)::value>(a...); }, s.x.c[0],
            s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], s.a.c[0], s.a.c[1], s.a.c[2], s.x.n, h, s.watch);
    };
    s.watch != nullptr ? run(std::true_type{}) : run(std::false_type{});
    dynamics.acceleration(t + h, s.first, s.x, s.v, s.a);
    last_kick(s, 0.5 * h, s.a);
}

// Velocity Verlet, order 2:
//   x' = x + h v + (h²/2) a
//   a' = a(t + h, x', v + h a)
//   v' = v + (h/2)(a + a')
// Same positions as leapfrog; velocity-dependent forces see a full Euler
// prediction of v', which keeps them second order too. One force evaluation
// per step (a' is the next step's a). Exact for a constant force.
void velocity_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const bool fresh = !s.memory_valid;
    auto rule = [h](P3& x, P3& v, P3& a, const auto& accel, auto rebuild) {
        if (rebuild) a = accel(v);
        const P3 v_predicted = v + h * a;
        x = x + (h * v + (0.5 * h * h) * a);
        v = v + (0.5 * h) * a;
        a = accel(v_predicted);
        v = v + (0.5 * h) * a;
    };
    if (fused_field_pass(dynamics, s, s.a, fresh ? 2 : 1, rule)) return;
    ensure_acceleration(dynamics, s, t);
    // A force that reads no velocity is given the half-kicked one: no
    // prediction to store.
    const bool predict = !dynamics.velocity_free();
    const Vec3Span v_predicted = predict ? s.scratch(0) : s.v;
    auto run = [&](auto predict_constant, auto watch_constant) {
        run_at_width(
            s.wide_loops(),
            [](auto... a) {
                verlet_first_half_loop<decltype(predict_constant)::value, decltype(watch_constant)::value>(a...);
            },
            s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], s.a.c[0], s.a.c[1], s.a.c[2], v_predicted.c[0],
            v_predicted.c[1], v_predicted.c[2], s.x.n, h, s.watch);
    };
    if (s.watch != nullptr) {
        predict ? run(std::true_type{}, std::true_type{}) : run(std::false_type{}, std::true_type{});
    } else {
        predict ? run(std::true_type{}, std::false_type{}) : run(std::false_type{}, std::false_type{});
    }
    dynamics.acceleration(t + h, s.first, s.x, v_predicted, s.a);
    last_kick(s, 0.5 * h, s.a);
}

// Position (Störmer) Verlet, order 2:
//   x' = 2x - x_prev + h² a(t, x, v)
// Velocity is not part of the method; it is recovered from positions as
//   v' = (x' - x)/h + (h/2) a         (second order: the backward difference
//                                       (x' - x)/h is v' - (h/2) a' + O(h²))
// for velocity-dependent forces, energy and output. The first step (or the
// first after h or the method changed) starts from x_prev = x - h v + (h²/2) a,
// the Taylor expansion backwards. Pinned particles keep x_prev = x.
namespace {

// One component of the update above; x_prev is replaced by x.
inline void stormer_update(double& x, double& v, double& x_prev, double a, double h) {
    const double x_new = 2.0 * x - x_prev + h * h * a;
    v = (x_new - x) / h + 0.5 * h * a;
    x_prev = x;
    x = x_new;
}

// The first step's x_prev, from the Taylor expansion backwards.
inline double taylor_previous(double x, double v, double a, double h) { return x - h * v + 0.5 * h * h * a; }

}  // namespace

void position_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    auto rule = [h](P3& x, P3& v, P3& x_prev, const auto& accel, auto rebuild) {
        const P3 a = accel(v);
        if (rebuild) {
            x_prev = {taylor_previous(x.x, v.x, a.x, h), taylor_previous(x.y, v.y, a.y, h),
                      taylor_previous(x.z, v.z, a.z, h)};
        }
        stormer_update(x.x, v.x, x_prev.x, a.x, h);
        stormer_update(x.y, v.y, x_prev.y, a.y, h);
        stormer_update(x.z, v.z, x_prev.z, a.z, h);
    };
    if (fused_field_pass(dynamics, s, s.x_prev, 1, rule)) return;
    const Vec3Span a = s.scratch(0);
    dynamics.acceleration(t, s.first, s.x, s.v, a);
    given_acceleration_pass(s, s.x_prev, a, rule);
}

// 5. Explicit Runge-Kutta ----------------------------------------------------

namespace {

// An explicit method's Butcher tableau: stage i evaluates the derivative at
// t + c_i h and y + h Σ_{j<i} a_ij k_j; the step is y' = y + h Σ b_i k_i.
template <std::size_t S>
struct ButcherTableau {
    double a[S][S];
    double b[S];
    double c[S];
};

// Classic RK4 (Kutta 1901), order 4.
constexpr ButcherTableau<4> kClassicRk4{
    {{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.0, 0.0}, {0.0, 0.5, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}},
    {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0},
    {0.0, 0.5, 0.5, 1.0},
};

// The fused pass's per-particle Runge-Kutta step for a uniform field (which
// does not depend on x, so X_i is not formed). The tableau is a template
// argument and the stages are expanded at compile time (fold expressions, i
// and j ascending), so that the stages stay in registers and the loop has no
// branch: V_i = v + Σ_j (h a_ij) A_j over the non-zero a_ij.
template <const auto& kTableau, std::size_t I, std::size_t... J>
inline P3 stage_velocity(P3 v, const P3* stage_a, [[maybe_unused]] double h, std::index_sequence<J...>) {
    ((kTableau.a[I][J] != 0.0 ? void(v = v + (h * kTableau.a[I][J]) * stage_a[J]) : void()), ...);
    return v;
}

template <const auto& kTableau, class Accel, std::size_t... I>
inline void field_runge_kutta(P3& x, P3& v, const Accel& accel, double h, std::index_sequence<I...>) {
    P3 stage_v[sizeof...(I)], stage_a[sizeof...(I)];
    ((stage_v[I] = stage_velocity<kTableau, I>(v, stage_a, h, std::make_index_sequence<I>{}),
      stage_a[I] = accel(stage_v[I])),
     ...);
    ((x = x + (h * kTableau.b[I]) * stage_v[I]), ...);
    ((v = v + (h * kTableau.b[I]) * stage_a[I]), ...);
}

// The array path's stage I: X_I = x + Σ_J (h a_IJ) V_J and V_I = v + Σ_J
// (h a_IJ) A_J over the non-zero a_IJ, J ascending, in one pass over the
// particles per component. The arrays' pointers are held in locals (read
// through the spans, they are reloaded every iteration: most of a
// few-particle stage, and the loop is not vectorised); ivdep: the stage
// arrays never overlap x or v (scratch, or v itself for a stage that is the
// state, only read).
#if defined(__clang__)
#define PLAUSIBLE_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#else
#define PLAUSIBLE_IVDEP _Pragma("GCC ivdep")
#endif

template <const auto& kTableau, std::size_t I, std::size_t... J>
void array_stage(const StepArrays& s, Vec3Span stage_x, const Vec3Span* stage_v, const Vec3Span* stage_a,
                 [[maybe_unused]] double h, std::index_sequence<J...>) {
    for (int k = 0; k < 3; ++k) {
        const double* x = s.x.c[k];
        const double* v = s.v.c[k];
        double* X = stage_x.c[k];
        double* V = stage_v[I].c[k];
        [[maybe_unused]] const double* sv[] = {stage_v[J].c[k]..., nullptr};
        [[maybe_unused]] const double* sa[] = {stage_a[J].c[k]..., nullptr};
        PLAUSIBLE_IVDEP
        for (std::size_t p = 0; p < s.x.n; ++p) {
            double Xp = x[p], Vp = v[p];
            ((kTableau.a[I][J] != 0.0
                  ? void((Xp += (h * kTableau.a[I][J]) * sv[J][p], Vp += (h * kTableau.a[I][J]) * sa[J][p]))
                  : void()),
             ...);
            X[p] = Xp;
            V[p] = Vp;
        }
    }
}

// The step's pass: x' = x + Σ_i (h b_i) V_i, v' = v + Σ_i (h b_i) A_i, i
// ascending, component by component, pointers in locals as above.
template <const auto& kTableau>
void step_pass(const StepArrays& s, const Vec3Span* stage_v, const Vec3Span* stage_a, double h) {
    constexpr std::size_t S = std::size(kTableau.b);
    double hb[S];  // h b_i, once
    for (std::size_t i = 0; i < S; ++i) hb[i] = h * kTableau.b[i];
    auto sum = [&hb]<std::size_t... I>(double& X, double& V, const double* const* sv, const double* const* sa,
                                       std::size_t p, std::index_sequence<I...>) {
        ((X += hb[I] * sv[I][p], V += hb[I] * sa[I][p]), ...);
    };
    for (int k = 0; k < 3; ++k) {
        double* x = s.x.c[k];
        double* v = s.v.c[k];
        const double* sv[S];
        const double* sa[S];
        for (std::size_t i = 0; i < S; ++i) sv[i] = stage_v[i].c[k], sa[i] = stage_a[i].c[k];
        PLAUSIBLE_IVDEP
        for (std::size_t p = 0; p < s.x.n; ++p) {
            double X = x[p], V = v[p];
            sum(X, V, sv, sa, p, std::make_index_sequence<S>{});
            x[p] = X, v[p] = V;
        }
    }
}
#undef PLAUSIBLE_IVDEP

// Stage I's pass and the step's, at the block's width. The lambdas take
// their data as arguments, not captures: read through a closure, the loops
// are not vectorised. A few particles (StepArrays::kFewParticles) go straight
// to the pinned build: on one bead on one spring the call through
// run_at_width cost more than the arithmetic; the step pass then applies the
// watchdog's per-particle rules to them (s.watch), so that the World needs no
// pass of its own.
template <const auto& kTableau, std::size_t I>
void run_stage_pass(const StepArrays& s, Vec3Span stage_x, const Vec3Span* stage_v, const Vec3Span* stage_a, double h) {
    if (s.x.n <= StepArrays::kFewParticles) {
        array_stage<kTableau, I>(s, stage_x, stage_v, stage_a, h, std::make_index_sequence<I>{});
        return;
    }
    run_at_width(
        s.wide_loops(),
        [](const StepArrays* block, Vec3Span x, const Vec3Span* v, const Vec3Span* a, double step) {
            array_stage<kTableau, I>(*block, x, v, a, step, std::make_index_sequence<I>{});
        },
        &s, stage_x, stage_v, stage_a, h);
}
template <const auto& kTableau>
void run_step_pass(const StepArrays& s, const Vec3Span* stage_v, const Vec3Span* stage_a, double h) {
    if (s.x.n <= StepArrays::kFewParticles) {
        step_pass<kTableau>(s, stage_v, stage_a, h);
        if (s.watch == nullptr) return;
        for (std::size_t p = 0; p < s.x.n; ++p) {
            s.watch->suspects += is_suspect(s.x.c[0][p], s.x.c[1][p], s.x.c[2][p], s.v.c[0][p], s.v.c[1][p],
                                            s.v.c[2][p], s.watch->max_speed2, s.watch->box);
        }
        s.watch->counted = true;
        return;
    }
    run_at_width(
        s.wide_loops(),
        [](const StepArrays* block, const Vec3Span* v, const Vec3Span* a, double step) {
            step_pass<kTableau>(*block, v, a, step);
        },
        &s, stage_v, stage_a, h);
}

// Stage i's row of a is all zeros: X_i = x, V_i = v.
template <const auto& kTableau>
constexpr bool stage_is_state(std::size_t i) {
    for (std::size_t j = 0; j < i; ++j) {
        if (kTableau.a[i][j] != 0.0) return false;
    }
    return true;
}

// For y = (x, v) and y' = (v, a(t, x, v)), stage i is
//   X_i = x + h Σ_j a_ij V_j,   V_i = v + h Σ_j a_ij A_j,   A_i = a(t + c_i h, X_i, V_i)
// and the step x' = x + h Σ b_i V_i, v' = v + h Σ b_i A_i. Sums run in j
// (and i) order, skipping zero coefficients, on both paths.
// Scratch: X (1 array), V_i (S arrays), A_i (S arrays).
template <const auto& kTableau>
void explicit_runge_kutta(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    constexpr std::size_t S = std::size(kTableau.b);
    static_assert(2 * S + 1 <= kMaxScratch);
    auto rule = [h](P3& x, P3& v, P3&, const auto& accel, auto) {
        field_runge_kutta<kTableau>(x, v, accel, h, std::make_index_sequence<S>{});
    };
    if (fused_field_pass(dynamics, s, {}, static_cast<int>(S), rule)) return;
    const Vec3Span stage_x = s.scratch(0);
    Vec3Span stage_v[S];
    Vec3Span stage_a[S];
    for (std::size_t i = 0; i < S; ++i) {
        // A stage whose row of a is all zeros (the first) is the state itself:
        // it is read where it is, not copied (a shorter chain of stores and
        // loads, most of a few-particle step).
        stage_v[i] = stage_is_state<kTableau>(i) ? s.v : s.scratch(1 + i);
        stage_a[i] = s.scratch(1 + S + i);
    }
    // Each stage, then the step, in one pass over the particles (the
    // tableau's zeros known at compile time).
    [&]<std::size_t... I>(std::index_sequence<I...>) {
        (((stage_is_state<kTableau>(I) ? void() : run_stage_pass<kTableau, I>(s, stage_x, stage_v, stage_a, h)),
          dynamics.acceleration(t + kTableau.c[I] * h, s.first, stage_is_state<kTableau>(I) ? s.x : stage_x, stage_v[I],
                                stage_a[I])),
         ...);
    }
    (std::make_index_sequence<S>{});
    run_step_pass<kTableau>(s, stage_v, stage_a, h);
}

}  // namespace

// Classic RK4, order 4: four force evaluations per step at t, t + h/2,
// t + h/2, t + h; the accuracy reference (tableau kClassicRk4 above).
void rk4(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    explicit_runge_kutta<kClassicRk4>(dynamics, s, t, h);
}

// 6. Look-ups -------------------------------------------------------------------

std::optional<Integrator> integrator_from_name(std::string_view name) {
    for (const IntegratorInfo& info : kIntegrators) {
        if (info.name == name) {
            return info.id;
        }
    }
    return std::nullopt;
}

std::string integrator_names() {
    std::string names;
    for (const IntegratorInfo& info : kIntegrators) {
        names += names.empty() ? "" : ", ";
        names += info.name;
    }
    return names;
}

}  // namespace sim
