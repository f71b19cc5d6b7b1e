// Integrators over flat particle arrays. Contents:
//   1. array helpers
//   2. explicit one-stage methods: forward Euler, symplectic Euler
//   3. Verlet family: leapfrog, velocity Verlet, Störmer (position) Verlet
//   4. the table's look-ups
// (The fused pass for uniform fields, every method's update in one loop, is
// in fused_pass.h; explicit Runge-Kutta, RK4, in runge_kutta.cpp; backward
// Euler, one Newton step on the linearised forces, in backward_euler.cpp.)
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
#include "sim/fused_pass.h"
#include "sim/pair_forces.h"
#include "sim/watchdog.h"

#include <algorithm>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

namespace sim {

// 1. Array helpers ---------------------------------------------------------

namespace {

using fused::fused_field_pass;
using fused::given_acceleration_pass;
using fused::P3;

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
    std::size_t passed = 0;  // a count, not a bool: the loop stays vectorised
    for (std::size_t i = 0; i < n; ++i) {
        v0[i] += alpha * a0[i];
        v1[i] += alpha * a1[i];
        v2[i] += alpha * a2[i];
        if constexpr (kWatch) passed += passes_velocity(v0[i], v1[i], v2[i], max_speed2);
    }
    if constexpr (kWatch) watch->suspects += n - passed, watch->counted = true;
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
    std::size_t passed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        v0[i] += (0.5 * h) * a0[i], v1[i] += (0.5 * h) * a1[i], v2[i] += (0.5 * h) * a2[i];
        x0[i] += h * v0[i], x1[i] += h * v1[i], x2[i] += h * v2[i];
        if constexpr (kWatch) passed += passes_position(x0[i], x1[i], x2[i], box);
    }
    if constexpr (kWatch) watch->suspects += n - passed;
}

// Velocity Verlet's first half: the predicted velocity w = v + h a (when
// kPredict: a force that reads no velocity needs none), the drift
// x += h v + (h²/2) a, the kick v += (h/2) a where kKick; kWatch: the rules
// on x.
template <bool kPredict, bool kWatch, bool kKick>
void verlet_first_half_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                            double* __restrict v1, double* __restrict v2, const double* __restrict a0,
                            const double* __restrict a1, const double* __restrict a2, double* __restrict w0,
                            double* __restrict w1, double* __restrict w2, std::size_t n, double h,
                            StepArrays::Watch* __restrict watch) {
    const double box = kWatch ? watch->box : 0.0;
    std::size_t passed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if constexpr (kPredict) w0[i] = v0[i] + h * a0[i], w1[i] = v1[i] + h * a1[i], w2[i] = v2[i] + h * a2[i];
        x0[i] += h * v0[i] + 0.5 * h * h * a0[i];
        x1[i] += h * v1[i] + 0.5 * h * h * a1[i];
        x2[i] += h * v2[i] + 0.5 * h * h * a2[i];
        if constexpr (kKick) v0[i] += (0.5 * h) * a0[i], v1[i] += (0.5 * h) * a1[i], v2[i] += (0.5 * h) * a2[i];
        if constexpr (kWatch) passed += passes_position(x0[i], x1[i], x2[i], box);
    }
    if constexpr (kWatch) watch->suspects += n - passed;
}

// The same step with the new acceleration a' in an array of its own
// (StepArrays::a_next): the drift and the prediction first
// (verlet_first_half_loop without its kick, v untouched), then, after the
// force, v' = (v + (h/2) a) + (h/2) a' in one pass, the same operations in
// the same order as the two kicks (the same bits), v written once. kWatch:
// the rules on v'.
template <bool kWatch>
void verlet_kicks_loop(double* __restrict v0, double* __restrict v1, double* __restrict v2, const double* __restrict a0,
                       const double* __restrict a1, const double* __restrict a2, const double* __restrict b0,
                       const double* __restrict b1, const double* __restrict b2, std::size_t n, double h,
                       StepArrays::Watch* __restrict watch) {
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0;
    std::size_t passed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        v0[i] = (v0[i] + (0.5 * h) * a0[i]) + (0.5 * h) * b0[i];
        v1[i] = (v1[i] + (0.5 * h) * a1[i]) + (0.5 * h) * b1[i];
        v2[i] = (v2[i] + (0.5 * h) * a2[i]) + (0.5 * h) * b2[i];
        if constexpr (kWatch) passed += passes_velocity(v0[i], v1[i], v2[i], max_speed2);
    }
    if constexpr (kWatch) watch->suspects += n - passed, watch->counted = true;
}

// Fills s.a with a(t, x, v) unless it still holds it from the last step.
void ensure_acceleration(Dynamics& dynamics, const StepArrays& s, double t) {
    if (!s.memory_valid) {
        dynamics.acceleration(t, s.first, s.x, s.v, s.a);
    }
}

// A pair's values of one array (sim/pair_forces.h), component by component,
// in registers: the pair steps below read each array once and write each
// component's two values together, one 16-byte store, as the next step loads
// them (a load cannot take its bytes from two stores in flight: it waits for
// them to reach the cache).
using PairValues = double[3][2];
inline void load_pair(const Vec3Span& from, PairValues& to) {
    for (int k = 0; k < 3; ++k) to[k][0] = from.c[k][0], to[k][1] = from.c[k][1];
}
inline void store_pair(const PairValues& from, const Vec3Span& to) {
    for (int k = 0; k < 3; ++k) to.c[k][0] = from[k][0], to.c[k][1] = from[k][1];
}
// A pair's a (s.a) at the start of the step, the force inline, unless s.a
// still holds it from the last step (ensure_acceleration's pair form).
template <class Pair>
void ensure_pair_acceleration(Dynamics& dynamics, const StepArrays& s, const Pair& pair, const PairPath& path) {
    if (s.memory_valid) return;
    pair::acceleration<-1>(pair, s.x.c, s.v.c, path.mass + s.first, path.inv_mass + s.first, s.a.c);
    dynamics.count_evaluations(2);
}
// The watchdog's per-particle rules on a pair's new x and v, counted as the
// loops count them.
inline void watch_pair(const StepArrays& s, const PairValues& x, const PairValues& v) {
    if (s.watch == nullptr) return;
    std::size_t passed = 0;
    for (int p = 0; p < 2; ++p) {
        passed += passes(x[0][p], x[1][p], x[2][p], v[0][p], v[1][p], v[2][p], s.watch->max_speed2, s.watch->box);
    }
    s.watch->suspects += 2 - passed, s.watch->counted = true;
}

// 2. Explicit one-stage methods -------------------------------------------------

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

// An Euler step on a pair (a bead on its spring, a planet around its sun:
// Dynamics::pair_path), the force inline, the step in registers: the
// operations of the arrays' path below on each particle, the same bits, the
// watchdog's rules counted alike. On the bead the arrays' path cost half as
// much again as velocity Verlet's pair step: a virtual call for the force,
// and the spans it passes built on the stack and read back at another width,
// a load that waits for two stores to reach the cache.
template <Euler kKind, class Pair>
void pair_euler(Dynamics& dynamics, const StepArrays& s, const Pair& pair, const PairPath& path, double h) {
    PairValues x, v, a;
    load_pair(s.x, x), load_pair(s.v, v);
    pair::acceleration<-1>(pair, x, v, path.mass + s.first, path.inv_mass + s.first, a);
    dynamics.count_evaluations(2);
    for (int k = 0; k < 3; ++k) {
        for (int p = 0; p < 2; ++p) euler_update<kKind>(x[k][p], v[k][p], a[k][p], h);
    }
    store_pair(x, s.x), store_pair(v, s.v);
    watch_pair(s, x, v);
}

template <Euler kKind>
void euler_step(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    auto pair_step = [&](const auto& pair, const PairPath& path) { pair_euler<kKind>(dynamics, s, pair, path, h); };
    if (pair::step_pair(dynamics, s, pair_step)) return;
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

// 3. Verlet family -----------------------------------------------------------

namespace {

// Leapfrog on a pair (Dynamics::pair_path), the force inline, the step in
// registers: the operations of the loops below on each particle (the kick
// and the drift, the force at the new x and the half-kicked v, the last
// kick), the same bits; a' written over a as the loops write it, each
// array's pair stored together, the watchdog's rules counted alike.
template <class Pair>
void pair_leapfrog(Dynamics& dynamics, const StepArrays& s, const Pair& pair, const PairPath& path, double h) {
    ensure_pair_acceleration(dynamics, s, pair, path);
    PairValues x, v, a;
    load_pair(s.x, x), load_pair(s.v, v), load_pair(s.a, a);
    for (int k = 0; k < 3; ++k) {
        for (int p = 0; p < 2; ++p) v[k][p] += (0.5 * h) * a[k][p], x[k][p] += h * v[k][p];
    }
    pair::acceleration<-1>(pair, x, v, path.mass + s.first, path.inv_mass + s.first, a);
    dynamics.count_evaluations(2);
    for (int k = 0; k < 3; ++k) {
        for (int p = 0; p < 2; ++p) v[k][p] += (0.5 * h) * a[k][p];
    }
    store_pair(x, s.x), store_pair(v, s.v), store_pair(a, s.a);
    watch_pair(s, x, v);
}

}  // namespace

// Leapfrog, kick-drift-kick, order 2:
//   v½ = v + (h/2) a(t, x, v)           kick
//   x' = x + h v½                        drift
//   v' = v½ + (h/2) a(t + h, x', v½)     kick
// The last acceleration is the next step's first (kept in s.a), so it costs
// one force evaluation per step. Exact for a constant force.
void leapfrog(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    auto pair_step = [&](const auto& pair, const PairPath& path) { pair_leapfrog(dynamics, s, pair, path, h); };
    if (pair::step_pair(dynamics, s, pair_step)) return;
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

namespace {

// Velocity Verlet on a pair (a bead on its spring, a planet around its sun:
// Dynamics::pair_path), the force inline (sim/pair_forces.h) as RK4's pair
// step has it, the step in registers: on each of the two particles the
// operations of the loops above in their order (the drift and the
// prediction, then v' = (v + (h/2) a) + (h/2) a', the two kicks'), so the
// same bits; a' written over a (the general path leaves it in a_next where
// the World gives one, and the arrays trade places: the same values, kept
// here without the trade), the watchdog's rules counted alike. The force
// always sees the predicted velocity: one that reads none gives the same
// bits either way. (Leaving a pinned anchor at rest out, as RK4 does, saved
// nothing here: the two particles' arithmetic shares vector registers, and
// the tests cost more than the anchor's lanes; tried 2026-12-05, 447 -> 497
// instructions a step.)
//
// kPredict: the force reads velocities (pair::reads_velocity), so it is given
// the prediction w = v + h a; one that reads none is given v, the same bits
// without w (on the bead, six values fewer to hold in registers: 339 -> 329
// instructions a step).
template <bool kPredict, class Pair>
void pair_velocity_verlet(Dynamics& dynamics, const StepArrays& s, const Pair& pair, const PairPath& path, double h) {
    const double* mass = path.mass + s.first;
    const double* inv_mass = path.inv_mass + s.first;
    // (ensure_pair_acceleration's lines written out: through it, and through
    // load_pair, this step compiled to 406-408 instructions against 398.)
    if (!s.memory_valid) {
        pair::acceleration<-1>(pair, s.x.c, s.v.c, mass, inv_mass, s.a.c);
        dynamics.count_evaluations(2);
    }
    // Every value read first, every one written last: the stores cannot
    // alias the loads then, and the arithmetic stays in registers.
    PairValues x, v, a, w, b;  // x', v, a, the predicted velocity, a'
    for (int k = 0; k < 3; ++k) {
        for (int p = 0; p < 2; ++p) {
            x[k][p] = s.x.c[k][p], v[k][p] = s.v.c[k][p], a[k][p] = s.a.c[k][p];
            if constexpr (kPredict) w[k][p] = v[k][p] + h * a[k][p];
            x[k][p] += h * v[k][p] + 0.5 * h * h * a[k][p];
        }
    }
    pair::acceleration<-1>(pair, x, kPredict ? w : v, mass, inv_mass, b);
    dynamics.count_evaluations(2);
    for (int k = 0; k < 3; ++k) {
        for (int p = 0; p < 2; ++p) v[k][p] = (v[k][p] + (0.5 * h) * a[k][p]) + (0.5 * h) * b[k][p];
    }
    store_pair(x, s.x), store_pair(v, s.v), store_pair(b, s.a);
    watch_pair(s, x, v);
}

}  // namespace

namespace {

// Velocity Verlet on every system but a pair: the fused pass of a uniform
// field, or the loops. Out of line, so that a pair's step (velocity_verlet)
// saves and restores only the registers it uses.
[[gnu::noinline]] void velocity_verlet_arrays(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const bool fresh = !s.memory_valid;
    // A force that reads no velocity (gravity alone, undamped springs) is
    // given v as it is (kicked or not): no prediction to make or store (the
    // fused rule's is then unused, and compiled away).
    const bool predict = !dynamics.velocity_free();
    auto rule_of = [h](auto predict_constant) {
        return [h](P3& x, P3& v, P3& a, const auto& accel, auto rebuild) {
            if (rebuild) a = accel(v);
            const P3 v_predicted = v + h * a;
            x = x + (h * v + (0.5 * h * h) * a);
            v = v + (0.5 * h) * a;
            a = accel(decltype(predict_constant)::value ? v_predicted : v);
            v = v + (0.5 * h) * a;
        };
    };
    const int evaluations = fresh ? 2 : 1;
    if (predict ? fused_field_pass(dynamics, s, s.a, evaluations, rule_of(std::true_type{}))
                : fused_field_pass(dynamics, s, s.a, evaluations, rule_of(std::false_type{}))) {
        return;
    }
    ensure_acceleration(dynamics, s, t);
    const Vec3Span v_predicted = predict ? s.scratch(0) : s.v;
    // With a second acceleration array (the World's), v is written once: the
    // drift alone, then both kicks in one pass after the force (the same bits).
    const bool two = s.a_next.n == s.x.n && s.a_next_taken != nullptr;
    auto first_half = [&](auto predict_constant, auto watch_constant, auto kick_constant) {
        run_at_width(
            s.wide_loops(),
            [](auto... a) {
                verlet_first_half_loop<decltype(predict_constant)::value, decltype(watch_constant)::value,
                                       decltype(kick_constant)::value>(a...);
            },
            s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], s.a.c[0], s.a.c[1], s.a.c[2], v_predicted.c[0],
            v_predicted.c[1], v_predicted.c[2], s.x.n, h, s.watch);
    };
    auto with_kick = [&](auto predict_constant, auto watch_constant) {
        two ? first_half(predict_constant, watch_constant, std::false_type{})
            : first_half(predict_constant, watch_constant, std::true_type{});
    };
    if (s.watch != nullptr) {
        predict ? with_kick(std::true_type{}, std::true_type{}) : with_kick(std::false_type{}, std::true_type{});
    } else {
        predict ? with_kick(std::true_type{}, std::false_type{}) : with_kick(std::false_type{}, std::false_type{});
    }
    if (!two) {
        dynamics.acceleration(t + h, s.first, s.x, v_predicted, s.a);
        last_kick(s, 0.5 * h, s.a);
        return;
    }
    dynamics.acceleration(t + h, s.first, s.x, v_predicted, s.a_next);
    auto kicks = [&](auto watch_constant) {
        run_at_width(
            s.wide_loops(), [](auto... a) { verlet_kicks_loop<decltype(watch_constant)::value>(a...); }, s.v.c[0],
            s.v.c[1], s.v.c[2], s.a.c[0], s.a.c[1], s.a.c[2], s.a_next.c[0], s.a_next.c[1], s.a_next.c[2], s.x.n, h,
            s.watch);
    };
    s.watch != nullptr ? kicks(std::true_type{}) : kicks(std::false_type{});
    *s.a_next_taken = true;
}

}  // namespace

// Velocity Verlet, order 2:
//   x' = x + h v + (h²/2) a
//   a' = a(t + h, x', v + h a)
//   v' = v + (h/2)(a + a')
// Same positions as leapfrog; velocity-dependent forces see a full Euler
// prediction of v', which keeps them second order too. One force evaluation
// per step (a' is the next step's a). Exact for a constant force.
void velocity_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    auto pair_step = [&](const auto& pair, const PairPath& path) {
        pair::reads_velocity(pair) ? pair_velocity_verlet<true>(dynamics, s, pair, path, h)
                                   : pair_velocity_verlet<false>(dynamics, s, pair, path, h);
    };
    if (!pair::step_pair(dynamics, s, pair_step)) velocity_verlet_arrays(dynamics, s, t, h);
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

// 4. Look-ups -------------------------------------------------------------------

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
