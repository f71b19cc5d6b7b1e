// Point sets as flat arrays: n points stored component by component
// (all x, then all y, then all z) so that per-particle loops are plain loops
// over contiguous doubles that the compiler vectorises.
#pragma once

#include <Eigen/Core>

#include <cassert>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

namespace sim {

using Vec3 = Eigen::Vector3d;

// A non-owning view of n points inside a Vec3Array (or a block of one).
// c[k][i] is component k (0 = x, 1 = y, 2 = z) of point i. T is double for a
// writable view and const double for a read-only one.
template <class T>
struct Vec3View {
    T* c[3] = {nullptr, nullptr, nullptr};
    std::size_t n = 0;

    Vec3View() = default;
    Vec3View(T* x, T* y, T* z, std::size_t count) : c{x, y, z}, n(count) {}
    // A writable view converts to a read-only one.
    template <class U>
    // (Copied whole, as the 32 bytes it is: member by member, GCC writes it
    // with 8-byte stores that the callee then reads with 16-byte loads, a
    // store-forwarding stall on every force evaluation.)
    requires(std::is_const_v<T>&& std::is_same_v<std::remove_const_t<T>, U>) Vec3View(const Vec3View<U>& other) {
        static_assert(sizeof(Vec3View) == sizeof(Vec3View<U>));
        std::memcpy(static_cast<void*>(this), &other, sizeof(Vec3View));
    }

    Vec3 get(std::size_t i) const { return {c[0][i], c[1][i], c[2][i]}; }
    void set(std::size_t i, const Vec3& p) const requires(!std::is_const_v<T>) {
        c[0][i] = p.x();
        c[1][i] = p.y();
        c[2][i] = p.z();
    }
    void add(std::size_t i, const Vec3& p) const requires(!std::is_const_v<T>) {
        c[0][i] += p.x();
        c[1][i] += p.y();
        c[2][i] += p.z();
    }
    // The points [first, first + count) of this view.
    Vec3View block(std::size_t first, std::size_t count) const {
        assert(first + count <= n);
        return {c[0] + first, c[1] + first, c[2] + first, count};
    }
};

using Vec3Span = Vec3View<double>;
using ConstVec3Span = Vec3View<const double>;

// Owning storage for n points, one allocation of 3n doubles.
class Vec3Array {
public:
    Vec3Array() = default;
    explicit Vec3Array(std::size_t n) : data_(3 * n, 0.0), n_(n) {}

    std::size_t size() const { return n_; }
    void resize(std::size_t n) {
        data_.assign(3 * n, 0.0);
        n_ = n;
    }

    Vec3Span span() { return {data_.data(), data_.data() + n_, data_.data() + 2 * n_, n_}; }
    ConstVec3Span span() const { return {data_.data(), data_.data() + n_, data_.data() + 2 * n_, n_}; }

    Vec3 get(std::size_t i) const { return span().get(i); }
    void set(std::size_t i, const Vec3& p) { span().set(i, p); }

    const std::vector<double>& raw() const { return data_; }  // 3n doubles, x block first

private:
    std::vector<double> data_;  // [x0..xn-1, y0..yn-1, z0..zn-1]
    std::size_t n_ = 0;
};

}  // namespace sim
