// Explicit Runge-Kutta from a Butcher tableau: RK4. Three paths with the
// same arithmetic, so the same bits (tested): the fused pass for a uniform
// field (fused_pass.h), the array path (one pass per stage over the
// particles, component by component, any force), and a few particles' path
// (the stages on the stack). Notation as in integrators.cpp.
#include "sim/integrators.h"

#include "sim/cpu.h"
#include "sim/fused_pass.h"
#include "sim/pair_forces.h"
#include "sim/watchdog.h"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <type_traits>
#include <utility>

namespace sim {

namespace {

using fused::fused_field_pass;
using fused::P3;

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

// Stage I's pass and the step's, at the block's width (more than
// StepArrays::kFewParticles particles: fewer take few_runge_kutta). The
// lambdas take their data as arguments, not captures: read through a
// closure, the loops are not vectorised.
template <const auto& kTableau, std::size_t I>
void run_stage_pass(const StepArrays& s, Vec3Span stage_x, const Vec3Span* stage_v, const Vec3Span* stage_a, double h) {
    run_at_width(
        s.wide_loops(),
        [](const StepArrays* block, Vec3Span x, const Vec3Span* v, const Vec3Span* a, double step) {
            array_stage<kTableau, I>(*block, x, v, a, step, std::make_index_sequence<I>{});
        },
        &s, stage_x, stage_v, stage_a, h);
}
template <const auto& kTableau>
void run_step_pass(const StepArrays& s, const Vec3Span* stage_v, const Vec3Span* stage_a, double h) {
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

// A few particles (StepArrays::kFewParticles at most): the stages live on
// the stack, not in the World's scratch, and each stage (and the step) is one
// pass over the particles with the three components together, the tableau's
// coefficients constants: on one bead on one spring the general path's
// twelve component loops and nine scratch spans cost more than the four
// force evaluations. Every value gets the same operations in the same order
// as on the array path (the same bits, tested); the step pass applies the
// watchdog's per-particle rules (s.watch).
constexpr std::size_t kFew = StepArrays::kFewParticles;
template <std::size_t kN>                        // kN particles (0: up to kFew)
using FewArray = double[3][kN > 0 ? kN : kFew];  // one stage's values, component by component

// Stage I's X_I and V_I (stage J's velocity is the state's where J is),
// but for particle kStill (-1: none), which stays where still_particle says.
template <const auto& kTableau, std::size_t kN, std::size_t I, int kStill = -1, std::size_t... J>
void few_stage(const StepArrays& s, FewArray<kN>& X, FewArray<kN>* V, const FewArray<kN>* A, double h,
               std::index_sequence<J...>) {
    const std::size_t n = kN > 0 ? kN : s.x.n;
    for (std::size_t p = 0; p < n; ++p) {
        if (static_cast<int>(p) == kStill) continue;
        for (int k = 0; k < 3; ++k) {
            double Xp = s.x.c[k][p], Vp = s.v.c[k][p];
            ((kTableau.a[I][J] != 0.0
                  ? void((Xp += (h * kTableau.a[I][J]) * (stage_is_state<kTableau>(J) ? s.v.c[k][p] : V[J][k][p]),
                          Vp += (h * kTableau.a[I][J]) * A[J][k][p]))
                  : void()),
             ...);
            X[k][p] = Xp;
            V[I][k][p] = Vp;
        }
    }
}

inline bool all_finite(const double (&values)[2][3]) {
    bool finite = true;
    for (const auto& row : values)
        for (double d : row) finite = finite && std::isfinite(d);
    return finite;
}

// The step, x' = x + Σ_i (h b_i) V_i and v' = v + Σ_i (h b_i) A_i, with the
// watchdog's per-particle rules on each particle it leaves (particle kStill
// as it is). With a still particle, nothing is written unless the other's
// x' and v' are finite (false: see still_particle).
template <const auto& kTableau, std::size_t kN, int kStill = -1, std::size_t... I>
bool few_step(const StepArrays& s, const FewArray<kN>* V, const FewArray<kN>* A, double h, std::index_sequence<I...>) {
    std::size_t suspects = 0;
    const std::size_t n = kN > 0 ? kN : s.x.n;
    for (std::size_t p = 0; p < n; ++p) {
        double next[2][3];  // x', v'
        for (int k = 0; k < 3; ++k) {
            double Xp = s.x.c[k][p], Vp = s.v.c[k][p];
            if (static_cast<int>(p) != kStill) {
                ((Xp += (h * kTableau.b[I]) * (stage_is_state<kTableau>(I) ? s.v.c[k][p] : V[I][k][p]),
                  Vp += (h * kTableau.b[I]) * A[I][k][p]),
                 ...);
            }
            next[0][k] = Xp, next[1][k] = Vp;
        }
        if constexpr (kStill >= 0) {
            if (static_cast<int>(p) != kStill && !all_finite(next)) return false;
        }
        for (int k = 0; k < 3; ++k) s.x.c[k][p] = next[0][k], s.v.c[k][p] = next[1][k];
        if (s.watch != nullptr) {
            suspects += is_suspect(next[0][0], next[0][1], next[0][2], next[1][0], next[1][1], next[1][2],
                                   s.watch->max_speed2, s.watch->box);
        }
    }
    if (s.watch != nullptr) s.watch->suspects += suspects, s.watch->counted = true;
    return true;
}

// A particle of the pair that every stage and the step leave exactly where
// it is, so that RK4 need not compute it (a bead's pinned anchor: a quarter
// of the pair's arithmetic; kLeavesStillOut says which pairs ask); -1 where
// neither is. Pinned (inverse mass 0), at rest (each velocity component +0),
// no position component -0 (x + (+0) is +0 there), and the field's force on
// it finite. Its stage accelerations are then f 0 = ±0, so its stage
// velocities stay +0 and its positions x, for any tableau, as long as the
// pair's pull is finite in every stage. Where a pull is not, the other
// particle's acceleration is not finite either (field - pull, times an
// inverse mass >= 0), nor its v' (every b_i is non-zero): few_step writes
// nothing and the step is taken again with both particles, whose still one
// goes NaN as it does on the general few-particle path (sampled frames take
// that one).
template <const auto& kTableau, class Pair>
int still_particle(const StepArrays& s, const Pair& pair, const double* mass, const double* inv_mass) {
    constexpr bool kEveryB = [] {
        for (double b : kTableau.b)
            if (b == 0.0) return false;
        return true;
    }();
    if constexpr (!kEveryB) return -1;
    constexpr std::uint64_t kMinusZero = std::uint64_t{1} << 63;
    for (int p = 0; p < 2; ++p) {
        if (inv_mass[p] != 0.0) continue;
        auto bits = [](double d) { return std::bit_cast<std::uint64_t>(d); };
        // One test of the three velocities' bits, three of the positions'.
        bool still = (bits(s.v.c[0][p]) | bits(s.v.c[1][p]) | bits(s.v.c[2][p])) == 0 &&
                     bits(s.x.c[0][p]) != kMinusZero && bits(s.x.c[1][p]) != kMinusZero &&
                     bits(s.x.c[2][p]) != kMinusZero;
        if (still && pair.field != nullptr) {
            const UniformField& g = *pair.field;
            const FieldForce f = field_force<false>(mass[p], 0.0, 0.0, 0.0, g.g.x(), g.g.y(), g.g.z(), g.c, 0.0);
            still = std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z);
        }
        if (still) return p;
    }
    return -1;
}

// A pair's stage I: X_I and V_I, then the force inline.
template <const auto& kTableau, std::size_t I, int kStill, class Pair>
[[gnu::always_inline]] inline void pair_stage(const StepArrays& s, const Pair& pair, const double* mass,
                                              const double* inv_mass, FewArray<2>& X, FewArray<2>* V, FewArray<2>* A,
                                              double h) {
    if constexpr (stage_is_state<kTableau>(I)) {
        pair::acceleration<kStill>(pair, s.x.c, s.v.c, mass, inv_mass, A[I]);
    } else {
        few_stage<kTableau, 2, I, kStill>(s, X, V, A, h, std::make_index_sequence<I>{});
        pair::acceleration<kStill>(pair, X, V[I], mass, inv_mass, A[I]);
    }
}

// A step of a pair (one spring between two particles, or Newton's gravity
// between them), the stages on the stack and the force inline, so that no
// stage leaves the registers (sim/pair_forces.h), with particle kStill (-1:
// none) left where it is (still_particle). False: nothing was written
// (few_step).
template <const auto& kTableau, int kStill, class Pair, std::size_t... I>
[[gnu::always_inline]] inline bool pair_step(const StepArrays& s, const Pair& pair, const double* mass,
                                             const double* inv_mass, double h, std::index_sequence<I...>) {
    constexpr std::size_t S = sizeof...(I);
    FewArray<2> X, V[S], A[S];  // stage positions, velocities, accelerations, as few_runge_kutta's
    if constexpr (kStill >= 0) {
        for (int k = 0; k < 3; ++k) {
            X[k][kStill] = s.x.c[k][kStill];
            for (std::size_t i = 0; i < S; ++i) V[i][k][kStill] = 0.0;
        }
    }
    (pair_stage<kTableau, I, kStill>(s, pair, mass, inv_mass, X, V, A, h), ...);
    return few_step<kTableau, 2, kStill>(s, V, A, h, std::index_sequence<I...>{});
}

// Whether a pair's step leaves a still particle out. Measured (4000-step
// runs, the median of 50, six processes each, 2026-12-05): the spring pair
// gains (the damped bead 33-36 ns a step against 46-65), gravity loses
// (Kepler e = 0.5 91-116 against 67-88; e = 0.9 97-107 against 71-75).
template <class Pair>
constexpr bool kLeavesStillOut = std::is_same_v<Pair, SpringPair>;

// A pair's step, with a still particle left out where kLeavesStillOut and
// there is one.
template <const auto& kTableau, class Pair, std::size_t... I>
void pair_runge_kutta(const StepArrays& s, const Pair& pair, const PairPath& path, double h,
                      std::index_sequence<I...> stages) {
    const double* mass = path.mass + s.first;
    const double* inv_mass = path.inv_mass + s.first;
    if constexpr (kLeavesStillOut<Pair>) {  // (else those builds are not compiled at all)
        const int still = still_particle<kTableau>(s, pair, mass, inv_mass);
        if (still == 0 && pair_step<kTableau, 0>(s, pair, mass, inv_mass, h, stages)) return;
        if (still == 1 && pair_step<kTableau, 1>(s, pair, mass, inv_mass, h, stages)) return;
    }
    pair_step<kTableau, -1>(s, pair, mass, inv_mass, h, stages);
}

template <const auto& kTableau, std::size_t kN, std::size_t... I>
void few_runge_kutta(Dynamics& dynamics, const StepArrays& s, double t, double h, std::index_sequence<I...>) {
    constexpr std::size_t S = sizeof...(I);
    const std::size_t n = kN > 0 ? kN : s.x.n;
    FewArray<kN> X, V[S], A[S];  // stage positions, velocities (V[i] unused where stage i is the state), accelerations
    auto span = [&](FewArray<kN>& c) { return Vec3Span(c[0], c[1], c[2], n); };
    auto read = [&](const FewArray<kN>& c) { return ConstVec3Span(c[0], c[1], c[2], n); };
    auto stage = [&](auto i_constant) {
        constexpr std::size_t i = decltype(i_constant)::value;
        if constexpr (stage_is_state<kTableau>(i)) {
            dynamics.acceleration(t + kTableau.c[i] * h, s.first, s.x, s.v, span(A[i]));
        } else {
            few_stage<kTableau, kN, i>(s, X, V, A, h, std::make_index_sequence<i>{});
            dynamics.acceleration(t + kTableau.c[i] * h, s.first, read(X), read(V[i]), span(A[i]));
        }
    };
    (stage(std::integral_constant<std::size_t, I>{}), ...);
    few_step<kTableau, kN>(s, V, A, h, std::index_sequence<I...>{});
}

// For y = (x, v) and y' = (v, a(t, x, v)), stage i is
//   X_i = x + h Σ_j a_ij V_j,   V_i = v + h Σ_j a_ij A_j,   A_i = a(t + c_i h, X_i, V_i)
// and the step x' = x + h Σ b_i V_i, v' = v + h Σ b_i A_i. Sums run in j
// (and i) order, skipping zero coefficients, on both paths.
// Scratch: X (1 array), V_i (S arrays), A_i (S arrays).
template <const auto& kTableau>
[[gnu::noinline]] void arrays_runge_kutta(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    constexpr std::size_t S = std::size(kTableau.b);
    static_assert(2 * S + 1 <= kMaxScratch);
    auto rule = [h](P3& x, P3& v, P3&, const auto& accel, auto) {
        field_runge_kutta<kTableau>(x, v, accel, h, std::make_index_sequence<S>{});
    };
    if (fused_field_pass(dynamics, s, {}, static_cast<int>(S), rule)) return;
    if (s.x.n <= StepArrays::kFewParticles) {
        // Two particles that are not a pair (explicit_runge_kutta), or a
        // pair on a frame whose spring pass is timed, get their own build:
        // the loops unrolled.
        if (s.x.n == 2) {
            few_runge_kutta<kTableau, 2>(dynamics, s, t, h, std::make_index_sequence<S>{});
        } else {
            few_runge_kutta<kTableau, 0>(dynamics, s, t, h, std::make_index_sequence<S>{});
        }
        return;
    }
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

// A pair (a bead on its spring, a planet around its sun) is looked for
// first and stepped with its force inline (pair_runge_kutta); every other
// system goes out of line (arrays_runge_kutta: the fused pass of a uniform
// field, which is never a pair, the few-particle build, the passes), so
// that a pair's step saves only the registers it uses.
template <const auto& kTableau>
void explicit_runge_kutta(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    constexpr std::size_t S = std::size(kTableau.b);
    auto pair_step = [&](const auto& pair, const PairPath& path) {
        pair_runge_kutta<kTableau>(s, pair, path, h, std::make_index_sequence<S>{});
        dynamics.count_evaluations(S * 2);
    };
    if (!pair::step_pair(dynamics, s, pair_step)) arrays_runge_kutta<kTableau>(dynamics, s, t, h);
}

}  // namespace

// Classic RK4, order 4: four force evaluations per step at t, t + h/2,
// t + h/2, t + h; the accuracy reference (tableau kClassicRk4 above).
void rk4(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    explicit_runge_kutta<kClassicRk4>(dynamics, s, t, h);
}

}  // namespace sim
