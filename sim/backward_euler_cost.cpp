// What backward Euler's sparse factorization costs, estimated from its
// pattern alone (integrators.h, backward_euler_factor_flops): the loader's
// work limits ask it before a scene runs. Its own file: it uses Eigen's
// symbolic analysis, not the integrators' step code.
#include "sim/integrators.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <vector>

namespace sim {

namespace {

// SimplicialLDLT's symbolic half only: analyzePattern() orders the matrix and
// lays out L, whose column pointers then give the non-zeros of each column
// below the unit diagonal (protected in Eigen, hence the subclass; read from
// m_matrix, which Eigen 3.4 and 5 both fill so, not from 3.4's
// m_nonZerosPerCol, which Eigen 5 dropped); factorize() is never called.
struct SymbolicLDLT : Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> {
    double flops() const {
        const auto* column = m_matrix.outerIndexPtr();
        double sum = 0.0;
        for (Eigen::Index j = 0; j < m_matrix.outerSize(); ++j) {
            const double count = static_cast<double>(column[j + 1] - column[j]) + 1.0;  // and the diagonal
            sum += count * count;
        }
        return sum;
    }
};

}  // namespace

double backward_euler_factor_flops(std::size_t n, const std::vector<std::array<std::uint32_t, 2>>& links) {
    if (links.empty()) return 0.0;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(n + 2 * links.size());
    for (std::size_t i = 0; i < n; ++i) entries.emplace_back(i, i, 1.0);
    for (const auto& [a, b] : links) entries.emplace_back(a, b, 1.0), entries.emplace_back(b, a, 1.0);
    Eigen::SparseMatrix<double> pattern(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    pattern.setFromTriplets(entries.begin(), entries.end());
    SymbolicLDLT symbolic;
    symbolic.analyzePattern(pattern);
    return 27.0 * symbolic.flops();
}

}  // namespace sim
