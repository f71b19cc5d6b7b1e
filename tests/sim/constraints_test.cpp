// XPBD distance constraints: one projection against its closed form, the
// compliant equilibrium against Hooke's law, pinned and degenerate cases.
#include "sim/constraints.h"
#include "sim/error.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sim::test {
namespace {

TEST(Constraints, AnInextensibleProjectionRestoresTheLengthAndKeepsTheCentreOfMass) {
    // Masses 1 kg and 3 kg, 1.5 m apart, rest 1 m: after one projection they
    // are 1 m apart, each moved in proportion to its inverse mass, so the
    // centre of mass has not moved.
    Vec3Array x(2);
    x.set(0, Vec3(0, 0, 0));
    x.set(1, Vec3(1.5, 0, 0));
    const double inv_mass[2] = {1.0, 1.0 / 3.0};
    Constraints c;
    c.distance.push_back({0, 1, 1.0, 0.0});
    std::vector<double> lambda;
    project(c, x.span(), inv_mass, 0.01, lambda);
    EXPECT_NEAR((x.get(1) - x.get(0)).norm(), 1.0, 1e-15) << "m";
    EXPECT_NEAR(x.get(0).x(), 0.375, 1e-15) << "m: the light one moves 3/4 of the 0.5 m";
    EXPECT_NEAR((1.0 * x.get(0).x() + 3.0 * x.get(1).x()) / 4.0, 4.5 / 4.0, 1e-15) << "m, centre of mass";
}

TEST(Constraints, APinnedEndDoesNotMoveAndTwoPinnedEndsAreLeftAlone) {
    Vec3Array x(3);
    x.set(0, Vec3(0, 0, 0));
    x.set(1, Vec3(0, -2, 0));
    x.set(2, Vec3(5, 0, 0));
    const double inv_mass[3] = {0.0, 1.0, 0.0};
    Constraints c;
    c.distance.push_back({0, 1, 1.0, 0.0});
    c.distance.push_back({0, 2, 1.0, 0.0});  // both pinned: cannot be satisfied, must not move or blow up
    std::vector<double> lambda;
    project(c, x.span(), inv_mass, 0.01, lambda);
    EXPECT_EQ(x.get(0), Vec3(0, 0, 0));
    EXPECT_EQ(x.get(2), Vec3(5, 0, 0));
    EXPECT_NEAR(x.get(1).y(), -1.0, 1e-15) << "m";
}

TEST(Constraints, CoincidentParticlesGiveNoNaN) {
    Vec3Array x(2);
    x.set(0, Vec3(1, 1, 1));
    x.set(1, Vec3(1, 1, 1));
    const double inv_mass[2] = {1.0, 1.0};
    Constraints c;
    c.distance.push_back({0, 1, 0.5, 0.0});
    std::vector<double> lambda;
    project(c, x.span(), inv_mass, 0.01, lambda);
    EXPECT_TRUE(x.get(0).allFinite());
    EXPECT_TRUE(x.get(1).allFinite());
}

TEST(Constraints, ACompliantConstraintHangsAtHookesEquilibrium) {
    // Compliance α = 1/k: a 2 kg mass under 9.81 m/s² hangs rest + m g / k
    // below a pinned anchor, as on a spring of stiffness k = 500 N/m.
    const double k = 500.0, m = 2.0, g = 9.81, rest = 1.0;
    ParticleModel model;
    model.particles.push_back({Vec3(0, 0, 0), Vec3::Zero(), 1.0, true});
    model.particles.push_back({Vec3(0, -rest, 0), Vec3::Zero(), m, false});
    model.forces.push_back(UniformGravity{Vec3(0, -g, 0)});
    model.forces.push_back(LinearDrag{4.0});  // N·s/m: lets it settle
    model.constraints.distance.push_back({0, 1, rest, 1.0 / k});
    World world(std::move(model));
    for (int i = 0; i < 1200; ++i) world.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
    const double expected = -(rest + m * g / k);
    EXPECT_NEAR(world.state().x.get(1).y(), expected, 1e-4) << "m; Hooke: " << expected;
    // Its stored energy is that of the stretched spring: ½ k s².
    const double s = m * g / k;
    EXPECT_NEAR(potential_energy(world.model().constraints, world.state().x.span()), 0.5 * k * s * s, 1e-5) << "J";
}

TEST(Constraints, ValidationNamesTheConstraint) {
    Constraints c;
    c.distance.push_back({0, 1, 1.0, 0.0});
    c.distance.push_back({1, 2, 1.0, -1.0});
    try {
        validate(c, 3);
        FAIL() << "accepted a negative compliance";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "constraints.distance[1].compliance must be >= 0 and finite, in m/N (got -1)");
    }
    c.distance[1] = {1, 3, 1.0, 0.0};
    EXPECT_THROW(validate(c, 3), InputError);
    c.distance[1] = {1, 1, 1.0, 0.0};
    EXPECT_THROW(validate(c, 3), InputError);
    c.distance[1] = {1, 2, 1.0, 0.0};
    c.iterations = 0;
    EXPECT_THROW(validate(c, 3), InputError);
}

}  // namespace
}  // namespace sim::test
