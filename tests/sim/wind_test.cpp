// Wind: a plate facing it and edge-on, a lone sphere, the gusts' determinism,
// continuity and statistics, and no NaN on degenerate triangles.
#include "sim/wind.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sim::test {
namespace {

// Forces of `wind` on three resting particles at a, b, c.
Vec3Array forces(const Wind& wind, const Vec3& a, const Vec3& b, const Vec3& c, double t = 0.0) {
    Vec3Array x(3), v(3), f(3);
    x.set(0, a);
    x.set(1, b);
    x.set(2, c);
    const double mass[3] = {1, 1, 1}, inv[3] = {1, 1, 1};
    accumulate(wind, {t, 0, x.span(), v.span(), mass, inv}, f.span());
    return f;
}

TEST(Wind, APlateFacingTheWindFeelsHalfRhoCdAUSquared) {
    // A right triangle of legs 1 m in the y-z plane (A = 0.5 m²), wind 10 m/s along x.
    Wind w;
    w.velocity = Vec3(10, 0, 0);
    w.triangles = {{0, 1, 2}};
    const Vec3Array f = forces(w, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1));
    const double total = 0.5 * 1.2 * 1.0 * 0.5 * 100.0;  // N
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(f.get(i).x(), total / 3, 1e-12) << "N, corner " << i;
        EXPECT_NEAR(f.get(i).y(), 0.0, 1e-12);
    }
    // Edge-on (the plate in the x-y plane, wind along x): no force.
    const Vec3Array edge = forces(w, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
    EXPECT_NEAR(edge.get(0).norm(), 0.0, 1e-12) << "N";
    // Degenerate (coincident corners): nothing, and no NaN.
    const Vec3Array flat = forces(w, Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1));
    EXPECT_EQ(flat.get(0), Vec3::Zero());
}

TEST(Wind, ALoneSphereFeelsItsCrossSection) {
    Wind w;
    w.velocity = Vec3(0, 0, 5);
    w.particles = {1};
    w.radius = 0.2;
    const Vec3Array f = forces(w, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
    EXPECT_NEAR(f.get(1).z(), 0.5 * 1.2 * 1.0 * std::numbers::pi * 0.04 * 25.0, 1e-12) << "N";
    EXPECT_EQ(f.get(0), Vec3::Zero());
}

TEST(Wind, GustsAreAPureSmoothFunctionOfTime) {
    Wind a, b;
    a.gust_strength = b.gust_strength = 2.0;
    a.gust_period = b.gust_period = 0.5;
    EXPECT_EQ(wind_at(a, 3.3), wind_at(b, 3.3)) << "two objects, same time, same wind";
    // Continuous across keys: over a 1 ms step the wind changes by at most
    // its largest slope times 1 ms (slope <= 1.5 |Δgust| / period).
    double worst = 0.0;
    for (double t = 0.0; t < 20.0; t += 0.001) worst = std::max(worst, (wind_at(a, t + 0.001) - wind_at(a, t)).norm());
    EXPECT_LT(worst, 1.5 * 6 * 2.0 / 0.5 * 0.001) << "m/s per ms";
    // Statistics over many keys: mean near the mean wind, spread of the order of the strength.
    Vec3 sum = Vec3::Zero();
    double sum2 = 0.0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
        const Vec3 g = wind_at(a, k * 0.5) - a.velocity;  // at the keys: the gust itself
        sum += g;
        sum2 += g.x() * g.x();
    }
    EXPECT_LT((sum / n).norm(), 5 * 2.0 * std::sqrt(3.0 / n)) << "m/s";
    EXPECT_NEAR(std::sqrt(sum2 / n), 2.0, 0.1) << "m/s, the gust's standard deviation";
    Wind calm;
    EXPECT_EQ(wind_at(calm, 12.0), calm.velocity);
}

TEST(Wind, ValidationNamesTheField) {
    Wind w;
    w.triangles = {{0, 1, 5}};
    EXPECT_THROW(validate(w, 3), InputError);
    w.triangles.clear();
    w.gust_period = 0.0;
    try {
        validate(w, 3);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "wind.gust_period must be > 0 and finite, in s (got 0)");
    }
}

}  // namespace
}  // namespace sim::test
