// sim::Random: the reference sequences of SplitMix64 and xoshiro256**, and the
// distributions' moments against their closed forms.
#include "sim/random.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

namespace sim::test {
namespace {

TEST(SplitMix64, MatchesTheReferenceSequence) {
    // SplitMix64 from seed 0: the first output is the published
    // 0xE220A8397B1DCDAF; the others come from a separate Python transcription
    // of Vigna's splitmix64.c (64-bit wrap-around arithmetic).
    SplitMix64 g(0);
    EXPECT_EQ(g.next(), 0xE220A8397B1DCDAFull);
    EXPECT_EQ(g.next(), 0x6E789E6AA1B965F4ull);
    EXPECT_EQ(g.next(), 0x06C45D188009454Full);
    EXPECT_EQ(g.next(), 0xF88BB8A8724C81ECull);
}

TEST(Random, MatchesTheReferenceXoshiro256StarStar) {
    // xoshiro256** seeded with the four SplitMix64 words above, from the same
    // Python transcription of xoshiro256starstar.c.
    Random r(0);
    const std::array<std::uint64_t, 5> expected = {0x99EC5F36CB75F2B4ull, 0xBF6E1F784956452Aull, 0x1A5F849D4933E6E0ull,
                                                   0x6AA594F1262D2D2Cull, 0xBBA5AD4A1F842E59ull};
    for (std::uint64_t e : expected) {
        EXPECT_EQ(r.next_u64(), e);
    }
    Random r42(42);
    EXPECT_EQ(r42.next_u64(), 0x15780B2E0C2EC716ull);
    EXPECT_EQ(r42.next_u64(), 0x6104D9866D113A7Eull);
}

TEST(Random, SameSeedSameSequenceOtherSeedAnother) {
    Random a(7), b(7), c(8);
    int same_as_c = 0;
    for (int i = 0; i < 1000; ++i) {
        const std::uint64_t x = a.next_u64();
        EXPECT_EQ(x, b.next_u64());
        same_as_c += x == c.next_u64();
    }
    EXPECT_EQ(same_as_c, 0);
}

TEST(Random, UniformHasTheMomentsOfU01) {
    // N draws of U[0, 1): mean 1/2 and variance 1/12; the standard error of
    // the mean is sqrt(1/12 / N) = 2.9e-4 for N = 1e6, the tolerance 5 of them.
    constexpr int n = 1'000'000;
    Random r(1);
    double sum = 0.0, sum2 = 0.0, lo = 1.0, hi = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform();
        sum += u;
        sum2 += u * u;
        lo = std::min(lo, u);
        hi = std::max(hi, u);
    }
    const double mean = sum / n;
    EXPECT_NEAR(mean, 0.5, 5 * 2.9e-4);
    EXPECT_NEAR(sum2 / n - mean * mean, 1.0 / 12.0, 1e-3);
    EXPECT_GE(lo, 0.0);
    EXPECT_LT(hi, 1.0);
    EXPECT_LT(lo, 1e-5) << "a million draws reach near 0";
    EXPECT_GT(hi, 1.0 - 1e-5) << "and near 1";
}

TEST(Random, UniformInAnIntervalStaysInside) {
    Random r(2);
    for (int i = 0; i < 10000; ++i) {
        const double u = r.uniform(-3.0, 5.0);
        ASSERT_GE(u, -3.0);
        ASSERT_LT(u, 5.0);
    }
}

TEST(Random, BelowIsUniformOverItsRange) {
    // 600000 draws in [0, 6): each count is binomial with mean 100000 and
    // standard deviation sqrt(600000 (1/6)(5/6)) = 289; tolerance 5 of them.
    Random r(3);
    std::array<int, 6> counts{};
    for (int i = 0; i < 600000; ++i) {
        const std::uint64_t k = r.below(6);
        ASSERT_LT(k, 6u);
        ++counts[k];
    }
    for (int c : counts) {
        EXPECT_NEAR(c, 100000, 5 * 289);
    }
    EXPECT_EQ(r.below(1), 0u);
}

TEST(Random, NormalHasTheMomentsOfAStandardGaussian) {
    // Mean 0 (standard error 1/sqrt(N) = 1e-3), variance 1 (standard error
    // sqrt(2/N) = 1.4e-3), and P(|X| < 1) = erf(1/sqrt 2) = 0.682689.
    constexpr int n = 1'000'000;
    Random r(4);
    double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
    int inside = 0;
    for (int i = 0; i < n; ++i) {
        const double x = r.normal();
        sum += x;
        sum2 += x * x;
        sum4 += x * x * x * x;
        inside += std::abs(x) < 1.0;
    }
    EXPECT_NEAR(sum / n, 0.0, 5e-3);
    EXPECT_NEAR(sum2 / n, 1.0, 7e-3);
    EXPECT_NEAR(sum4 / n, 3.0, 0.03) << "kurtosis of a Gaussian is 3";
    EXPECT_NEAR(static_cast<double>(inside) / n, std::erf(1.0 / std::sqrt(2.0)), 5 * 4.7e-4);
}

TEST(Random, UnitVectorsAreUnitAndIsotropic) {
    // Uniform on the sphere: |u| = 1, E[u] = 0, E[u_k^2] = 1/3 for each axis.
    constexpr int n = 200'000;
    Random r(5);
    Vec3 sum = Vec3::Zero();
    Vec3 sum2 = Vec3::Zero();
    for (int i = 0; i < n; ++i) {
        const Vec3 u = r.unit_vector();
        ASSERT_NEAR(u.norm(), 1.0, 1e-15);
        sum += u;
        sum2 += u.cwiseProduct(u);
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(sum[k] / n, 0.0, 5 * std::sqrt(1.0 / 3.0 / n)) << "axis " << k;
        EXPECT_NEAR(sum2[k] / n, 1.0 / 3.0, 5e-3) << "axis " << k;
    }
}

TEST(Random, SnapshotRestoresTheSequenceSpareNormalIncluded) {
    Random r(6);
    r.normal();  // leaves the pair's second value waiting
    const Random::Snapshot saved = r.snapshot();
    const double a1 = r.normal(), a2 = r.uniform(), a3 = r.normal();
    r.restore(saved);
    EXPECT_EQ(r.normal(), a1);
    EXPECT_EQ(r.uniform(), a2);
    EXPECT_EQ(r.normal(), a3);
}

}  // namespace
}  // namespace sim::test
