// What every force generator sees, and the verbs each one has.
//
// A generator is a plain struct of parameters (the description) plus free
// functions in its own file, all with the same names:
//   validate(g, n)                      throws InputError for bad parameters
//   is_local(g)                         true when particle i's force depends
//                                       on particle i alone (gravity, drag);
//                                       such forces may be evaluated block by block
//   accumulate(g, in, f)                f += this generator's force, N
//   potential_energy(g, in)             J (0 for dissipative forces)
//   accumulate_jacobians(g, in, jac)    ∂f/∂x and ∂f/∂v, for implicit methods
// forces.h gathers them in one variant, ForceDef.
#pragma once

#include "sim/vec3_array.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sim {

// The particles a generator acts on: the block [first, first + x.n) of the
// system. Coupled (non-local) generators are only ever given the whole system
// (first = 0).
struct ForceInput {
    double t = 0.0;                    // s
    std::size_t first = 0;             // global index of the block's first particle
    ConstVec3Span x;                   // position, m
    ConstVec3Span v;                   // velocity, m/s
    const double* mass = nullptr;      // (block) kg
    const double* inv_mass = nullptr;  // (block) 1/kg, 0 = pinned
    // A stamp of inv_mass's contents: the same value promises the same
    // contents as the last pass given it (ParticleForces::masses_changed
    // moves it on), so that a pass may keep what it found in them (the
    // spring plan's same_inv_mass). 0: no promise, every pass reads them.
    std::uint64_t masses = 0;
};

// Force Jacobians of a block as sparse triplets over the block's 3n unknowns,
// row/column 3 * i + k for component k of block particle i.
struct Jacobians {
    std::vector<Eigen::Triplet<double>> dfdx;  // N/m
    std::vector<Eigen::Triplet<double>> dfdv;  // N·s/m

    // Adds the 3x3 block m at (particle i, particle j).
    static void add(std::vector<Eigen::Triplet<double>>& list, std::size_t i, std::size_t j, const Eigen::Matrix3d& m) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                if (m(r, c) != 0.0) {
                    list.emplace_back(static_cast<int>(3 * i) + r, static_cast<int>(3 * j) + c, m(r, c));
                }
            }
        }
    }
};

}  // namespace sim
