// Point sets as flat arrays: n points stored component by component
// (all x, then all y, then all z) so that per-particle loops are plain loops
// over contiguous doubles that the compiler vectorises.
#pragma once

#include <Eigen/Core>

#include <cassert>
#include <cstddef>
#include <cstring>
#include <new>
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

// Storage that starts on a cache line (64 bytes), for Vec3Array below.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    static constexpr std::align_val_t kAlign{64};
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlign)); }
    // (Unsized: clang declares no sized delete without -fsized-deallocation.)
    void deallocate(T* p, std::size_t) { ::operator delete(p, kAlign); }
    template <class U>
    bool operator==(const CacheLineAllocator<U>&) const {
        return true;
    }
};

// Owning storage for n points, one allocation. Each component starts on a
// cache line and takes a whole number of lines (its n doubles, then zeros up
// to a multiple of 8): a 4-wide load at a multiple of 4 never straddles two
// lines, whatever n is. (With the components end to end, y and z of 1001
// particles began 8 and 16 bytes into a line, and every other vector load
// of theirs straddled two: velocity Verlet's step on 1000 beads ran 8-15%
// slower, measured.)
class Vec3Array {
public:
    Vec3Array() = default;
    explicit Vec3Array(std::size_t n) : data_(3 * padded(n), 0.0), n_(n), stride_(padded(n)) {}

    std::size_t size() const { return n_; }
    void resize(std::size_t n) {
        data_.assign(3 * padded(n), 0.0);
        n_ = n;
        stride_ = padded(n);
    }

    Vec3Span span() { return {data_.data(), data_.data() + stride_, data_.data() + 2 * stride_, n_}; }
    ConstVec3Span span() const { return {data_.data(), data_.data() + stride_, data_.data() + 2 * stride_, n_}; }

    Vec3 get(std::size_t i) const { return span().get(i); }
    void set(std::size_t i, const Vec3& p) { span().set(i, p); }

    // The coordinates as 3n doubles, all x, then all y, then all z (a copy:
    // the components are padded in memory).
    std::vector<double> flat() const {
        std::vector<double> out;
        out.reserve(3 * n_);
        for (const double* c : span().c) out.insert(out.end(), c, c + n_);
        return out;
    }

private:
    static constexpr std::size_t kLine = 8;  // doubles in a cache line
    static std::size_t padded(std::size_t n) { return (n + kLine - 1) / kLine * kLine; }

    std::vector<double, CacheLineAllocator<double>> data_;  // [x0..xn-1, 0.., y0..yn-1, 0.., z0..zn-1, 0..]
    std::size_t n_ = 0;
    std::size_t stride_ = 0;  // doubles from one component to the next
};

}  // namespace sim
