// Integrators over flat particle arrays. Contents:
//   1. array helpers
//   2. explicit one-stage methods: forward Euler, symplectic Euler
//   3. Verlet family: leapfrog, velocity Verlet, Störmer (position) Verlet
//   4. explicit Runge-Kutta from a Butcher tableau: RK4
//   5. backward Euler (one Newton step on the linearised forces)
//   6. the table's look-ups
//
// Notation: h is the step, x and v the state at t, a = M⁻¹ f(t, x, v).
// "Order" is the global order of the position error at a fixed end time.
#include "sim/integrators.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace sim {

// 1. Array helpers ---------------------------------------------------------

namespace {

// y += alpha x, for every component of every point.
void axpy(Vec3Span y, double alpha, ConstVec3Span x) {
    for (int k = 0; k < 3; ++k) {
        double* yk = y.c[k];
        const double* xk = x.c[k];
        for (std::size_t i = 0; i < y.n; ++i) {
            yk[i] += alpha * xk[i];
        }
    }
}

// y = x
void copy(Vec3Span y, ConstVec3Span x) {
    for (int k = 0; k < 3; ++k) {
        std::copy(x.c[k], x.c[k] + x.n, y.c[k]);
    }
}

// y = x + alpha z
void assign_sum(Vec3Span y, ConstVec3Span x, double alpha, ConstVec3Span z) {
    for (int k = 0; k < 3; ++k) {
        double* yk = y.c[k];
        const double* xk = x.c[k];
        const double* zk = z.c[k];
        for (std::size_t i = 0; i < y.n; ++i) {
            yk[i] = xk[i] + alpha * zk[i];
        }
    }
}

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

// One pass over a block of a uniform field: a = field_force / m and the
// Euler update together, so no acceleration array is written or read.
// Plain pointers and scalars only, so that the compiler sees every one of
// them loop-invariant and vectorises; __restrict because the six coordinate
// arrays and the two mass arrays never overlap.
template <Euler kKind, bool kQuadratic>
void euler_field_pass(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                      double* __restrict v1, double* __restrict v2, const double* __restrict mass,
                      const double* __restrict inv_mass, std::size_t n, double gx, double gy, double gz, double c,
                      double c2, double h) {
    for (std::size_t i = 0; i < n; ++i) {
        const FieldForce f = field_force<kQuadratic>(mass[i], v0[i], v1[i], v2[i], gx, gy, gz, c, c2);
        euler_update<kKind>(x0[i], v0[i], f.x * inv_mass[i], h);
        euler_update<kKind>(x1[i], v1[i], f.y * inv_mass[i], h);
        euler_update<kKind>(x2[i], v2[i], f.z * inv_mass[i], h);
    }
}

template <Euler kKind>
void euler_step(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    if (const UniformField* field = dynamics.uniform_field()) {
        const double* m = dynamics.mass() + s.first;
        const double* inv_m = dynamics.inv_mass() + s.first;
        auto* pass = field->c2 != 0.0 ? &euler_field_pass<kKind, true> : &euler_field_pass<kKind, false>;
        pass(s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], m, inv_m, s.x.n, field->g.x(), field->g.y(),
             field->g.z(), field->c, field->c2, h);
        dynamics.count_evaluations(s.x.n);
        return;
    }
    const Vec3Span a = s.scratch[0].block(0, s.x.n);
    dynamics.acceleration(t, s.first, s.x, s.v, a);
    const std::size_t n = s.x.n;
    for (int k = 0; k < 3; ++k) {
        double* xk = s.x.c[k];
        double* vk = s.v.c[k];
        const double* ak = a.c[k];
        for (std::size_t i = 0; i < n; ++i) {
            euler_update<kKind>(xk[i], vk[i], ak[i], h);
        }
    }
}

// Fills s.a with a(t, x, v) unless it still holds it from the last step.
void ensure_acceleration(Dynamics& dynamics, const StepArrays& s, double t) {
    if (!s.memory_valid) {
        dynamics.acceleration(t, s.first, s.x, s.v, s.a);
    }
}

}  // namespace

// 2. Explicit one-stage methods ----------------------------------------------

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

// Leapfrog, kick-drift-kick, order 2:
//   v½ = v + (h/2) a(t, x, v)           kick
//   x' = x + h v½                        drift
//   v' = v½ + (h/2) a(t + h, x', v½)     kick
// The last acceleration is the next step's first (kept in s.a), so it costs
// one force evaluation per step. Exact for a constant force.
void leapfrog(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    ensure_acceleration(dynamics, s, t);
    axpy(s.v, 0.5 * h, s.a);
    axpy(s.x, h, s.v);
    dynamics.acceleration(t + h, s.first, s.x, s.v, s.a);
    axpy(s.v, 0.5 * h, s.a);
}

// Velocity Verlet, order 2:
//   x' = x + h v + (h²/2) a
//   a' = a(t + h, x', v + h a)
//   v' = v + (h/2)(a + a')
// Same positions as leapfrog; velocity-dependent forces see a full Euler
// prediction of v', which keeps them second order too. One force evaluation
// per step (a' is the next step's a). Exact for a constant force.
void velocity_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    ensure_acceleration(dynamics, s, t);
    const Vec3Span v_predicted = s.scratch[0].block(0, s.x.n);
    assign_sum(v_predicted, s.v, h, s.a);
    for (int k = 0; k < 3; ++k) {
        double* xk = s.x.c[k];
        const double* vk = s.v.c[k];
        const double* ak = s.a.c[k];
        for (std::size_t i = 0; i < s.x.n; ++i) {
            xk[i] += h * vk[i] + 0.5 * h * h * ak[i];
        }
    }
    axpy(s.v, 0.5 * h, s.a);
    dynamics.acceleration(t + h, s.first, s.x, v_predicted, s.a);
    axpy(s.v, 0.5 * h, s.a);
}

// Position (Störmer) Verlet, order 2:
//   x' = 2x - x_prev + h² a(t, x, v)
// Velocity is not part of the method; it is recovered from positions as
//   v' = (x' - x)/h + (h/2) a         (second order: the backward difference
//                                       (x' - x)/h is v' - (h/2) a' + O(h²))
// for velocity-dependent forces, energy and output. The first step (or the
// first after h or the method changed) starts from x_prev = x - h v + (h²/2) a,
// the Taylor expansion backwards. Pinned particles keep x_prev = x.
void position_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const Vec3Span a = s.scratch[0].block(0, s.x.n);
    dynamics.acceleration(t, s.first, s.x, s.v, a);
    for (int k = 0; k < 3; ++k) {
        double* xk = s.x.c[k];
        double* vk = s.v.c[k];
        double* pk = s.x_prev.c[k];
        const double* ak = a.c[k];
        if (!s.memory_valid) {
            for (std::size_t i = 0; i < s.x.n; ++i) {
                pk[i] = xk[i] - h * vk[i] + 0.5 * h * h * ak[i];
            }
        }
        for (std::size_t i = 0; i < s.x.n; ++i) {
            const double x_new = 2.0 * xk[i] - pk[i] + h * h * ak[i];
            vk[i] = (x_new - xk[i]) / h + 0.5 * h * ak[i];
            pk[i] = xk[i];
            xk[i] = x_new;
        }
    }
}

// 4. Explicit Runge-Kutta ----------------------------------------------------

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

// For y = (x, v) and y' = (v, a(t, x, v)), stage i is
//   X_i = x + h Σ_j a_ij V_j,   V_i = v + h Σ_j a_ij A_j,   A_i = a(t + c_i h, X_i, V_i)
// and the step x' = x + h Σ b_i V_i, v' = v + h Σ b_i A_i.
// Scratch: X (1 array), V_i (S arrays), A_i (S arrays).
template <std::size_t S>
void explicit_runge_kutta(const ButcherTableau<S>& tableau, Dynamics& dynamics, const StepArrays& s, double t,
                          double h) {
    static_assert(2 * S + 1 <= kMaxScratch);
    const std::size_t n = s.x.n;
    const Vec3Span stage_x = s.scratch[0].block(0, n);
    Vec3Span stage_v[S];
    Vec3Span stage_a[S];
    for (std::size_t i = 0; i < S; ++i) {
        stage_v[i] = s.scratch[1 + i].block(0, n);
        stage_a[i] = s.scratch[1 + S + i].block(0, n);
    }
    for (std::size_t i = 0; i < S; ++i) {
        copy(stage_x, s.x);
        copy(stage_v[i], s.v);
        for (std::size_t j = 0; j < i; ++j) {
            if (tableau.a[i][j] != 0.0) {
                axpy(stage_x, h * tableau.a[i][j], stage_v[j]);
                axpy(stage_v[i], h * tableau.a[i][j], stage_a[j]);
            }
        }
        dynamics.acceleration(t + tableau.c[i] * h, s.first, stage_x, stage_v[i], stage_a[i]);
    }
    for (std::size_t i = 0; i < S; ++i) {
        axpy(s.x, h * tableau.b[i], stage_v[i]);
        axpy(s.v, h * tableau.b[i], stage_a[i]);
    }
}

}  // namespace

// Classic RK4, order 4: four force evaluations per step at t, t + h/2,
// t + h/2, t + h; the accuracy reference (tableau kClassicRk4 above).
void rk4(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    explicit_runge_kutta(kClassicRk4, dynamics, s, t, h);
}

// 5. Backward Euler ------------------------------------------------------------

// Backward (implicit) Euler, order 1:
//   v' = v + h M⁻¹ f(t + h, x', v'),   x' = x + h v'
// linearised once around (x, v) (Baraff and Witkin 1998), one Newton step:
//   (M - h ∂f/∂v - h² ∂f/∂x) Δv = h (f + h ∂f/∂x v)
//   v' = v + Δv,   x' = x + h v'
// The 3n x 3n system (row 3i + k) is sparse and symmetric; a pinned particle's
// rows and columns become identity with Δv = 0. Solved by sparse LDLᵀ, with
// sparse LU as the fallback when LDLᵀ meets a zero pivot. Unconditionally
// stable for springs; it damps, so an oscillator loses energy.
void backward_euler(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const std::size_t n = s.x.n;
    const auto size = static_cast<Eigen::Index>(3 * n);
    Jacobians jac;
    const Vec3Span force = s.scratch[0].block(0, n);
    dynamics.force_and_jacobians(t, s.first, s.x, s.v, force, jac);
    const double* mass = dynamics.mass() + s.first;
    const double* inv_mass = dynamics.inv_mass() + s.first;
    auto pinned = [&](int row) { return inv_mass[row / 3] == 0.0; };

    Eigen::VectorXd rhs(size);
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            rhs[static_cast<Eigen::Index>(3 * i) + k] = h * force.c[k][i];
        }
    }
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(jac.dfdx.size() + jac.dfdv.size() + 3 * n);
    for (const auto& e : jac.dfdx) {
        // h² ∂f/∂x v on the right, -h² ∂f/∂x on the left
        rhs[e.row()] += h * h * e.value() * s.v.c[e.col() % 3][static_cast<std::size_t>(e.col() / 3)];
        if (!pinned(e.row()) && !pinned(e.col())) {
            entries.emplace_back(e.row(), e.col(), -h * h * e.value());
        }
    }
    for (const auto& e : jac.dfdv) {
        if (!pinned(e.row()) && !pinned(e.col())) {
            entries.emplace_back(e.row(), e.col(), -h * e.value());
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            const int row = static_cast<int>(3 * i) + k;
            entries.emplace_back(row, row, inv_mass[i] == 0.0 ? 1.0 : mass[i]);
            if (inv_mass[i] == 0.0) {
                rhs[row] = 0.0;
            }
        }
    }
    Eigen::SparseMatrix<double> system(size, size);
    system.setFromTriplets(entries.begin(), entries.end());

    Eigen::VectorXd dv;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(system);
    if (ldlt.info() == Eigen::Success) {
        dv = ldlt.solve(rhs);
    } else {
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(system);
        if (lu.info() != Eigen::Success) {
            throw std::runtime_error("backward_euler: the linearised system is singular");
        }
        dv = lu.solve(rhs);
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            s.v.c[k][i] += dv[static_cast<Eigen::Index>(3 * i) + k];
            s.x.c[k][i] += h * s.v.c[k][i];
        }
    }
}

// 6. Look-ups -------------------------------------------------------------------

const IntegratorInfo& integrator_info(Integrator id) {
    for (const IntegratorInfo& info : kIntegrators) {
        if (info.id == id) {
            return info;
        }
    }
    throw std::logic_error("integrator_info: integrator missing from kIntegrators");
}

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
