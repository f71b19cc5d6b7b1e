// sim::Vec3Array's layout: each component on cache lines of its own, and
// what leaves the array (flat(), the state hash) as if the components lay
// end to end, so that golden hashes and recordings did not change with it.
#include "sim/vec3_array.h"
#include "sim/state_hash.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace sim::test {
namespace {

constexpr std::uintptr_t kLine = 64;  // bytes

std::uintptr_t address(const double* p) { return reinterpret_cast<std::uintptr_t>(p); }

// Point i = (i, 1000 + i, 2000 + i).
Vec3Array numbered(std::size_t n) {
    Vec3Array a(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = static_cast<double>(i);
        a.set(i, Vec3(d, 1000.0 + d, 2000.0 + d));
    }
    return a;
}

TEST(Vec3Array, EachComponentStartsOnACacheLine) {
    for (const std::size_t n : {1u, 2u, 7u, 8u, 9u, 1001u, 4096u}) {
        Vec3Array a(n);
        const Vec3Span s = a.span();
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(address(s.c[k]) % kLine, 0u) << "component " << k << " of " << n << " points";
        }
        // Far enough apart for n points each: no component runs into the next.
        EXPECT_GE(address(s.c[1]) - address(s.c[0]), n * sizeof(double)) << n << " points";
        EXPECT_GE(address(s.c[2]) - address(s.c[1]), n * sizeof(double)) << n << " points";
        const Vec3Array copy = a;  // a copy is laid out alike
        for (int k = 0; k < 3; ++k) EXPECT_EQ(address(copy.span().c[k]) % kLine, 0u) << "a copy's component " << k;
    }
}

TEST(Vec3Array, FlatListsAllXThenAllYThenAllZ) {
    const std::size_t n = 1001;
    const std::vector<double> flat = numbered(n).flat();
    ASSERT_EQ(flat.size(), 3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = static_cast<double>(i);
        ASSERT_EQ(flat[i], d) << "x of point " << i;
        ASSERT_EQ(flat[n + i], 1000.0 + d) << "y of point " << i;
        ASSERT_EQ(flat[2 * n + i], 2000.0 + d) << "z of point " << i;
    }
}

TEST(StateHash, IsFnv1aOverTThenXThenVEndToEnd) {
    // The prediction: FNV-1a (offset 14695981039346656037, prime
    // 1099511628211) over the bytes of t and of x's and v's 3n doubles, as
    // they lay before the components were padded.
    ParticleState state;
    state.t = 0.25;
    state.x = numbered(1001);
    state.v = numbered(1001);
    std::vector<double> bytes = {state.t};
    for (const Vec3Array* a : {&state.x, &state.v}) {
        const std::vector<double> f = a->flat();
        bytes.insert(bytes.end(), f.begin(), f.end());
    }
    std::uint64_t expected = 14695981039346656037ull;
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    for (std::size_t i = 0; i < bytes.size() * sizeof(double); ++i) expected = (expected ^ p[i]) * 1099511628211ull;
    EXPECT_EQ(state_hash(state), expected);
}

}  // namespace
}  // namespace sim::test
