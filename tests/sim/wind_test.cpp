// Wind: a plate facing it and edge-on, a lone sphere, the gusts' determinism,
// continuity and statistics, and no NaN on degenerate triangles.
#include "sim/wind.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sim::test {
namespace {

// Forces of `wind` on three particles at a, b, c, all moving at `velocity`.
Vec3Array forces(const Wind& wind, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& velocity = Vec3::Zero()) {
    Vec3Array x(3), v(3), f(3);
    x.set(0, a);
    x.set(1, b);
    x.set(2, c);
    for (std::size_t i = 0; i < 3; ++i) v.set(i, velocity);
    const double mass[3] = {1, 1, 1}, inv[3] = {1, 1, 1};
    accumulate(wind, {0.0, 0, x.span(), v.span(), mass, inv}, f.span());
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

TEST(Wind, ATiltedPlateFeelsCosineSquaredAlongItsNormal) {
    // The same plate turned by 60° about z: its normal n = (cos 60°, sin 60°, 0)
    // sees u·n = |w| cos 60°, so F = ½ ρ C_d A |w|² cos² 60° n in total.
    Wind w;
    w.velocity = Vec3(10, 0, 0);
    w.air_density = 1.25;
    w.drag_coefficient = 1.2;
    w.triangles = {{0, 1, 2}};
    const double angle = std::numbers::pi / 3;
    const Vec3 n(std::cos(angle), std::sin(angle), 0.0);
    const Vec3 along(-std::sin(angle), std::cos(angle), 0.0);  // in the plate, perpendicular to z
    const Vec3Array f = forces(w, Vec3(0, 0, 0), along, Vec3(0, 0, 1));
    const double cosine = std::cos(angle);
    const Vec3 expected = (0.5 * 1.25 * 1.2 * 0.5 * 100.0 * cosine * cosine) * n;  // N, whole plate
    EXPECT_LT((f.get(0) + f.get(1) + f.get(2) - expected).norm(), 1e-12) << "N, total " << expected.transpose();
    EXPECT_EQ(f.get(0), f.get(1)) << "every corner gets the same third";
    EXPECT_EQ(f.get(0), f.get(2)) << "every corner gets the same third";
    // Winding the triangle the other way flips n and (u·n): the same force.
    w.triangles = {{0, 2, 1}};
    const Vec3Array flipped = forces(w, Vec3(0, 0, 0), along, Vec3(0, 0, 1));
    EXPECT_LT((flipped.get(0) - f.get(0)).norm(), 1e-12) << "N";
}

TEST(Wind, APlateMovingWithTheWindFeelsOnlyTheRelativeWind) {
    Wind w;
    w.velocity = Vec3(10, 0, 0);
    w.triangles = {{0, 1, 2}};
    const Vec3Array with = forces(w, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(10, 0, 0));
    EXPECT_EQ(with.get(0), Vec3::Zero()) << "N, no relative wind";
    // Running into the wind at 5 m/s: u = 15 m/s.
    const Vec3Array against = forces(w, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-5, 0, 0));
    EXPECT_NEAR(against.get(0).x(), 0.5 * 1.2 * 1.0 * 0.5 * 225.0 / 3, 1e-12) << "N, corner 0";
}

TEST(Wind, DegenerateTrianglesGetNothingAndNoNaN) {
    Wind w;
    w.velocity = Vec3(10, -3, 2);
    w.gust_strength = 1.0;
    w.triangles = {{0, 1, 2}};
    // Collinear corners (zero area, distinct points), then all three on one point.
    for (const Vec3Array& f : {forces(w, Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)),
                               forces(w, Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1))}) {
        for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(f.get(i), Vec3::Zero()) << "N, corner " << i;
    }
    // A lone particle moving exactly with the wind: |u| = 0, no NaN.
    Wind calm;
    calm.velocity = Vec3(1, 2, 3);
    calm.particles = {0};
    const Vec3Array f = forces(calm, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3(1, 2, 3));
    EXPECT_EQ(f.get(0), Vec3::Zero());
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
    calm.velocity = Vec3(1.5, -0.5, 2.0);
    for (double t : {-3.0, 0.0, 0.37, 12.0, 1e5}) EXPECT_EQ(wind_at(calm, t), calm.velocity) << "t = " << t << " s";
}

// A gust period far below any step (1e-300 s) puts t / period at 1e300,
// beyond every integer: the key was converted to an int64 anyway (undefined;
// here it came out -2^63, and the blend between keys went to infinity). The
// key is clamped first: the gust holds at one key, finite, the same at any
// later time. A gust is the mean wind plus one normal draw of standard
// deviation gust_strength per component: within 6 of them (a 1e-9 event).
TEST(Wind, AGustPeriodFarBelowTheStepHoldsOneFiniteGust) {
    Wind w;
    w.gust_strength = 2.0;  // m/s
    w.gust_period = 1e-300;
    const Vec3 early = wind_at(w, 1.0), late = wind_at(w, 2.0);
    ASSERT_TRUE(early.allFinite()) << early.transpose();
    EXPECT_EQ(early, late) << "held at one key";
    EXPECT_LT((early - w.velocity).cwiseAbs().maxCoeff(), 6.0 * 2.0) << "m/s, one gust";
}

TEST(Wind, LocalOnlyWithoutTriangles) {
    Wind w;
    w.particles = {0, 2};
    EXPECT_TRUE(is_local(w)) << "lone particles feel only their own velocity";
    w.triangles = {{0, 1, 2}};
    EXPECT_FALSE(is_local(w)) << "a triangle couples its corners";
}

TEST(Wind, ValidationNamesTheField) {
    Wind w;
    w.triangles = {{0, 1, 5}};
    try {
        validate(w, 3);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "wind.triangles[0] names particle 5, but there are only 3");
    }
    w.triangles.clear();
    w.air_density = -1.0;
    EXPECT_THROW(validate(w, 3), InputError);
    w.air_density = 1.2;
    w.velocity = Vec3(NAN, 0, 0);
    EXPECT_THROW(validate(w, 3), InputError);
    w.velocity = Vec3(1, 0, 0);
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
