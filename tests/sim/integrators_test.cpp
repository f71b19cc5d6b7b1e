// The integrator table, pinned particles, and the bookkeeping of a step
// (memory, force-evaluation counts). Accuracy lives in
// integrators_accuracy_test.cpp, energy behaviour in integrators_stability_test.cpp.
#include "sim/integrators.h"
#include "sim/problems.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace sim::test {
namespace {

using namespace sim::problems;

TEST(Table, NamesRoundTripAndAreUnique) {
    std::set<std::string_view> names;
    for (const IntegratorInfo& info : kIntegrators) {
        EXPECT_TRUE(names.insert(info.name).second) << info.name;
        ASSERT_TRUE(integrator_from_name(info.name).has_value()) << info.name;
        EXPECT_EQ(*integrator_from_name(info.name), info.id);
        EXPECT_EQ(&integrator_info(info.id), &info);
        EXPECT_LE(info.scratch_arrays, kMaxScratch);
    }
    EXPECT_FALSE(integrator_from_name("euler").has_value());
    EXPECT_EQ(integrator_names(),
              "forward_euler, symplectic_euler, leapfrog, velocity_verlet, position_verlet, rk4, backward_euler");
}

// A rope of springs hanging from a pinned particle, with gravity and drag.
ParticleModel pinned_rope() {
    ParticleModel model;
    Springs springs;
    for (std::uint32_t i = 0; i < 6; ++i) {
        model.particles.push_back({Vec3(0.3 * i, 0.0, 0.0), Vec3(0.0, 0.1 * i, 0.0), 0.2, i == 0});
        if (i > 0) {
            springs.list.push_back({i - 1, i, 0.3, 500.0, 0.5});
        }
    }
    model.particles[3].pinned = true;  // one in the middle too
    model.forces = {UniformGravity{}, springs, LinearDrag{0.05}};
    return model;
}

class EveryIntegrator : public testing::TestWithParam<Integrator> {};

TEST_P(EveryIntegrator, PinnedParticlesDoNotMove) {
    World world(pinned_rope());
    const Vec3 anchor = world.state().x.get(0);
    const Vec3 middle = world.state().x.get(3);
    for (int i = 0; i < 200; ++i) {
        world.step({GetParam(), 1.0 / 240.0, 2});
    }
    EXPECT_EQ(world.state().x.get(0), anchor) << "bit-exact, m";
    EXPECT_EQ(world.state().x.get(3), middle) << "bit-exact, m";
    EXPECT_EQ(world.state().v.get(0), Vec3::Zero());
    EXPECT_NE(world.state().x.get(5), pinned_rope().particles[5].position) << "the free end does move";
}

TEST_P(EveryIntegrator, CountsForceEvaluations) {
    World world(ballistic_model());
    const IntegratorInfo& info = integrator_info(GetParam());
    for (int i = 0; i < 10; ++i) {
        world.step({GetParam(), 0.01, 1});
    }
    // First-same-as-last methods pay one extra evaluation on the first step.
    const bool fsal = info.id == Integrator::leapfrog || info.id == Integrator::velocity_verlet;
    EXPECT_EQ(world.force_evaluations(), 10.0 * info.force_evaluations + (fsal ? 1.0 : 0.0));
}

TEST_P(EveryIntegrator, SameResultEveryRun) {
    auto run = [&] {
        World world(pinned_rope());
        for (int i = 0; i < 100; ++i) {
            world.step({GetParam(), 1.0 / 120.0, 1});
        }
        return world.state().x.raw();
    };
    EXPECT_EQ(run(), run()) << "bit-identical positions";
}

INSTANTIATE_TEST_SUITE_P(All, EveryIntegrator,
                         testing::Values(Integrator::forward_euler, Integrator::symplectic_euler, Integrator::leapfrog,
                                         Integrator::velocity_verlet, Integrator::position_verlet, Integrator::rk4,
                                         Integrator::backward_euler),
                         [](const auto& info) { return std::string(integrator_info(info.param).name); });

TEST(Memory, ChangingDtRestartsVerletHistory) {
    // Störmer's x_prev belongs to the old dt; after a change it must be rebuilt
    // from (x, v), or the velocity implied by x - x_prev would be wrong by the
    // ratio of the steps. With a constant force the restart is exact.
    World world(ballistic_model());
    for (int i = 0; i < 10; ++i) {
        world.step({Integrator::position_verlet, 0.01, 1});
    }
    for (int i = 0; i < 10; ++i) {
        world.step({Integrator::position_verlet, 0.03, 1});
    }
    const auto exact = analytic::ballistic(Vec3::Zero(), kShotVelocity, kShotGravity, world.state().t);
    EXPECT_LT((world.state().x.get(0) - exact.x).norm(), 1e-12) << "m";
    EXPECT_LT((world.state().v.get(0) - exact.v).norm(), 1e-12) << "m/s";
}

}  // namespace
}  // namespace sim::test
