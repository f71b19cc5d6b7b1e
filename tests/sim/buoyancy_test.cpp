// Buoyancy against Archimedes: the force of a fully, half and not submerged
// sphere, and the floating depth of a lighter-than-water ball found
// independently by bisection on the cap volume.
#include "sim/buoyancy.h"
#include "sim/error.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sim::test {
namespace {

constexpr double kPi = std::numbers::pi;

// Upward force on one particle at height y, N.
double lift(const Buoyancy& b, double y) {
    Vec3Array x(1), v(1), f(1);
    x.set(0, Vec3(0, y, 0));
    const double mass = 1.0, inv = 1.0;
    accumulate(b, {0.0, 0, x.span(), v.span(), &mass, &inv}, f.span());
    return f.get(0).y();
}

TEST(Buoyancy, ArchimedesForFullHalfAndNoSubmersion) {
    const Buoyancy b{0.0, 1000.0, 9.81, 0.1, 0.0, {}};
    const double sphere = 4.0 / 3.0 * kPi * 0.001;  // m³
    EXPECT_NEAR(lift(b, -1.0), 1000.0 * 9.81 * sphere, 1e-9) << "N, fully under";
    EXPECT_NEAR(lift(b, 0.0), 0.5 * 1000.0 * 9.81 * sphere, 1e-9) << "N, centre on the surface: half";
    EXPECT_EQ(lift(b, 0.1000001), 0.0) << "above the water";
    EXPECT_NEAR(cap_volume(0.1, 0.2), sphere, 1e-15) << "m³: a cap of depth 2r is the sphere";
}

TEST(Buoyancy, ALightBallFloatsWhereItsCapDisplacesItsWeight) {
    // A 0.1 m ball of density 400 kg/m³ (mass 1.676 kg) in water floats
    // where V(h) / V = 0.4. Independent: bisection on π h² (3r - h) / 3.
    const double r = 0.1, rho = 1000.0, g = 9.81, density = 400.0;
    const double sphere = 4.0 / 3.0 * kPi * r * r * r, mass = density * sphere;
    double lo = 0.0, hi = 2 * r;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (kPi * mid * mid * (3 * r - mid) / 3 < 0.4 * sphere ? lo : hi) = mid;
    }
    const double y_float = 0.0 - (lo - r);  // centre height where the cap depth is lo
    const Buoyancy b{0.0, rho, g, r, 0.0, {}};
    EXPECT_NEAR(lift(b, y_float) - mass * g, 0.0, 1e-9) << "N: net force at the floating depth";
    EXPECT_LT(lift(b, y_float + 0.01) - mass * g, 0.0) << "above it, it sinks back";
    EXPECT_GT(lift(b, y_float - 0.01) - mass * g, 0.0) << "below it, it rises";

    // And a world with water drag settles there.
    ParticleModel model;
    model.particles.push_back({Vec3(0, 0.5, 0), Vec3::Zero(), mass, false});
    model.forces.push_back(UniformGravity{Vec3(0, -g, 0)});
    model.forces.push_back(Buoyancy{0.0, rho, g, r, 20.0, {}});
    World world(std::move(model));
    for (int i = 0; i < 1200; ++i) world.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
    EXPECT_NEAR(world.state().x.get(0).y(), y_float, 1e-4) << "m, floating depth " << y_float;
}

TEST(Buoyancy, PotentialIsMinusTheIntegralOfTheLift) {
    // f_y = -dU/dy by central differences across every regime: above the
    // water, entering, half under, nearly under, and deep (u > 2r, where the
    // cap formula no longer applies and U grows linearly).
    const Buoyancy b{0.0, 1000.0, 9.81, 0.1, 0.0, {}};
    auto energy = [&](double y) {
        Vec3Array x(1), v(1);
        x.set(0, Vec3(0, y, 0));
        const double mass = 1.0, inv = 1.0;
        return potential_energy(b, {0.0, 0, x.span(), v.span(), &mass, &inv});
    };
    const double h = 1e-6;  // m
    for (double y : {0.5, 0.09, 0.03, 0.0, -0.05, -0.099, -0.3}) {
        const double numeric = -(energy(y + h) - energy(y - h)) / (2 * h);
        EXPECT_NEAR(numeric, lift(b, y), 1e-6) << "N at y = " << y << " m";
    }
    EXPECT_EQ(energy(0.2), 0.0) << "J, out of the water";
    // Continuous where the ball goes fully under (u = 2r, y = -r).
    EXPECT_NEAR(energy(-0.1 - 1e-9), energy(-0.1 + 1e-9), 1e-6) << "J";
}

TEST(Buoyancy, OnlyTheListedParticlesFloatAlsoBlockByBlock) {
    // Three particles under water; only 0 and 2 are listed. Evaluated whole,
    // then as the blocks [0, 2) and [2, 3) a blocked step would hand it.
    Buoyancy b{0.0, 1000.0, 9.81, 0.1, 0.0, {2, 0}};
    Vec3Array x(3), v(3), whole(3), blocks(3);
    for (std::size_t i = 0; i < 3; ++i) x.set(i, Vec3(static_cast<double>(i), -1.0, 0.0));
    const double mass[3] = {1, 1, 1}, inv[3] = {1, 1, 1};
    const ConstVec3Span cx = x.span(), cv = v.span();
    accumulate(b, {0.0, 0, cx, cv, mass, inv}, whole.span());
    accumulate(b, {0.0, 0, cx.block(0, 2), cv.block(0, 2), mass, inv}, blocks.span().block(0, 2));
    accumulate(b, {0.0, 2, cx.block(2, 1), cv.block(2, 1), mass + 2, inv + 2}, blocks.span().block(2, 1));
    const double full = 1000.0 * 9.81 * 4.0 / 3.0 * kPi * 0.001;  // N
    EXPECT_NEAR(whole.get(0).y(), full, 1e-9) << "N";
    EXPECT_EQ(whole.get(1), Vec3::Zero()) << "not listed";
    EXPECT_NEAR(whole.get(2).y(), full, 1e-9) << "N";
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(blocks.get(i), whole.get(i)) << "particle " << i;
}

TEST(Buoyancy, ValidationNamesTheField) {
    Buoyancy b;
    b.radius = 0.0;
    EXPECT_THROW(validate(b, 1), InputError);
    b.radius = 0.1;
    b.fluid_density = -1.0;
    try {
        validate(b, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "buoyancy.fluid_density must be > 0 and finite, in kg/m³ (got -1)");
    }
    b.fluid_density = 1000.0;
    b.surface_height = NAN;
    try {
        validate(b, 1);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "buoyancy.surface_height must be finite, in m (got nan)");
    }
    b.surface_height = 0.0;
    b.radius = NAN;
    EXPECT_THROW(validate(b, 1), InputError);
    b.radius = 0.1;
    b.drag = -2.0;
    EXPECT_THROW(validate(b, 1), InputError);
    b.drag = 0.0;
    b.particles = {0, 3};
    try {
        validate(b, 2);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "buoyancy.particles[1] is particle 3, but there are only 2");
    }
    b.particles = {1};
    EXPECT_NO_THROW(validate(b, 2));
}

}  // namespace
}  // namespace sim::test
