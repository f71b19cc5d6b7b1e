// Backward (implicit) Euler, the integrator that solves a linear system each
// step (integrators.h): the particle-by-particle solve for a uniform field
// with at most one linear drag, and the sparse LDLᵀ (LU as the fallback)
// otherwise. Its own file: the explicit methods' loops are in
// integrators.cpp, what its factorization costs in backward_euler_cost.cpp.
#include "sim/cpu.h"
#include "sim/integrators.h"
#include "sim/watchdog.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <stdexcept>
#include <type_traits>
#include <vector>

namespace sim {

// Backward (implicit) Euler, order 1:
//   v' = v + h M⁻¹ f(t + h, x', v'),   x' = x + h v'
// linearised once around (x, v) (Baraff and Witkin 1998), one Newton step:
//   (M - h ∂f/∂v - h² ∂f/∂x) Δv = h (f + h ∂f/∂x v)
//   v' = v + Δv,   x' = x + h v'
// The 3n x 3n system (row 3i + k) is sparse and symmetric; a pinned particle's
// rows and columns become identity with Δv = 0. Solved by sparse LDLᵀ, with
// sparse LU as the fallback when LDLᵀ meets a zero pivot. Unconditionally
// stable for springs; it damps, so an oscillator loses energy.
namespace {

// Backward Euler when the force is gravity and at most one linear drag: the
// system is diagonal, (m + h c) Δv = h f for each coordinate, and solved
// particle by particle with the arithmetic the sparse solve does on it
// (its diagonal is the triplets' sum h c + m; LDLᵀ of a diagonal matrix
// solves by the inverse, Δv = (1/d) · h f), so with the same bits (tested)
// and without assembling and factoring a 3n x 3n matrix. kWatch: the
// watchdog's per-particle rules on each particle it leaves, counted into
// `watch` (as the explicit methods' passes do: no second pass over the
// particles). kPinned: the block may hold pinned particles (else their
// factor is left out, and inv_mass unread: the same bits, x · 1 being x).
// kVertical: is_vertical(field) (dynamics.h).
template <bool kWatch, bool kPinned, bool kVertical>
void backward_euler_diagonal(double* __restrict x0, double* __restrict x1, double* __restrict x2, double* __restrict v0,
                             double* __restrict v1, double* __restrict v2, const double* __restrict mass,
                             const double* __restrict inv_mass, std::size_t n, const UniformField& field, double h,
                             StepArrays::Watch* __restrict watch) {
    const double gx = field.g.x(), gy = field.g.y(), gz = field.g.z(), c = field.c;
    const double max_speed2 = kWatch ? watch->max_speed2 : 0.0, box = kWatch ? watch->box : 0.0;
    std::size_t passed = 0;  // a count, not a bool: the loop stays vectorised
    for (std::size_t i = 0; i < n; ++i) {
        // kVertical: gravity straight down, the force's x and z without m 0
        // (field_force; the same bits).
        const FieldForce f = field_force<false, kVertical>(mass[i], v0[i], v1[i], v2[i], gx, gy, gz, c, 0.0);
        // A pinned particle's right-hand side is zero (its row the identity
        // in the sparse system: any d > 0 gives the same zero); the factor
        // 1 or 0 keeps the loop free of branches.
        const double free = kPinned ? static_cast<double>(inv_mass[i] != 0.0) : 1.0;
        const double inverse = 1.0 / (h * c + mass[i]);
        v0[i] += inverse * ((h * f.x) * free);
        v1[i] += inverse * ((h * f.y) * free);
        v2[i] += inverse * ((h * f.z) * free);
        x0[i] += h * v0[i];
        x1[i] += h * v1[i];
        x2[i] += h * v2[i];
        if constexpr (kWatch) passed += passes(x0[i], x1[i], x2[i], v0[i], v1[i], v2[i], max_speed2, box);
    }
    if constexpr (kWatch) watch->suspects += n - passed, watch->counted = true;
}

}  // namespace

bool steps_in_one_pass(Integrator method, const UniformField& field) {
    return method != Integrator::backward_euler || (field.c2 == 0.0 && field.linear_drags <= 1);
}

void backward_euler(Dynamics& dynamics, const StepArrays& s, double t, double h) {
    const std::size_t n = s.x.n;
    if (const UniformField* field = dynamics.uniform_field();
        field != nullptr && steps_in_one_pass(Integrator::backward_euler, *field)) {
        const bool vertical = is_vertical(*field);
        auto run = [&](auto watch_constant, auto pinned_constant) {
            auto at = [&](auto vertical_constant) {
                run_at_width(
                    s.wide_loops(),
                    [](auto... a) {
                        backward_euler_diagonal<decltype(watch_constant)::value, decltype(pinned_constant)::value,
                                                decltype(vertical_constant)::value>(a...);
                    },
                    s.x.c[0], s.x.c[1], s.x.c[2], s.v.c[0], s.v.c[1], s.v.c[2], dynamics.mass() + s.first,
                    dynamics.inv_mass() + s.first, n, *field, h, s.watch);
            };
            vertical ? at(std::true_type{}) : at(std::false_type{});
        };
        auto with_pins = [&](auto watch_constant) {
            s.none_pinned ? run(watch_constant, std::false_type{}) : run(watch_constant, std::true_type{});
        };
        s.watch != nullptr ? with_pins(std::true_type{}) : with_pins(std::false_type{});
        dynamics.count_evaluations(n);
        return;
    }
    const auto size = static_cast<Eigen::Index>(3 * n);
    Jacobians jac;
    const Vec3Span force = s.scratch(0);
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

}  // namespace sim
