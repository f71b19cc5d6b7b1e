// The integrator table, pinned particles, and the bookkeeping of a step
// (memory, force-evaluation counts). Accuracy lives in
// integrators_accuracy_test.cpp, energy behaviour in integrators_stability_test.cpp.
#include "sim/integrators.h"
#include "sim/cpu.h"
#include "sim/forces.h"
#include "sim/problems.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

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
        return world.state().x.flat();
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

// Forces that read no velocity (springs without dampers, gravity, a central
// attractor) tell the integrators so, and velocity Verlet then skips
// predicting the velocity they would see. The skip must change no bit: the
// same steps through the same forces with the prediction made.
class PredictingForces final : public Dynamics {
public:
    explicit PredictingForces(ParticleForces& forces) : forces_(forces) {}
    bool velocity_free() const override { return false; }
    void acceleration(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                      const Vec3Span& a) override {
        forces_.acceleration(t, first, x, v, a);
    }
    void force_and_jacobians(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                             const Vec3Span& f, Jacobians& jac) override {
        forces_.force_and_jacobians(t, first, x, v, f, jac);
    }
    const double* mass() const override { return forces_.mass(); }
    const double* inv_mass() const override { return forces_.inv_mass(); }

private:
    ParticleForces& forces_;
};

// n particles, the first pinned, each other on a spring to it (rest length
// 0 or 0.7 m, 40 N/m, a damper of `damping` N·s/m), all moving.
struct Fan {
    std::vector<double> mass, inv_mass;
    Vec3Array x, v;
    Springs springs;
    Fan(std::size_t n, double damping) : x(n), v(n) {
        for (std::size_t i = 0; i < n; ++i) {
            const double s = static_cast<double>(i);
            mass.push_back(1.0 + 0.1 * s);
            inv_mass.push_back(i == 0 ? 0.0 : 1.0 / mass.back());
            x.set(i, Vec3(1.0 + 0.3 * s, std::sin(s), 0.1 * s));
            v.set(i, Vec3(std::cos(s), 0.5, -0.2 * s));
            if (i > 0) springs.list.push_back({0, static_cast<std::uint32_t>(i), i % 2 ? 0.0 : 0.7, 40.0, damping});
        }
    }
};

TEST(VelocityFree, VelocityVerletSkipsThePredictionWithTheSameBits) {
    for (const std::size_t n : {std::size_t{3}, std::size_t{40}}) {  // the few-particle path and the wide one
        Fan fan(n, 0.0);
        auto& [mass, inv_mass, x, v, springs] = fan;
        const std::vector<ForceDef> defs = {UniformGravity{}, springs, CentralGravity{Vec3(0.0, -3.0, 0.0), 5.0}};
        ParticleForces forces(defs, mass, inv_mass);
        ASSERT_TRUE(forces.velocity_free());
        PredictingForces predicting(forces);
        Vec3Array x2 = x, v2 = v, a(n), a2(n), w(n);
        for (int step = 0; step < 50; ++step) {
            auto arrays = [&](Vec3Array& xs, Vec3Array& vs, Vec3Array& as) {
                return StepArrays{.x = xs.span(),
                                  .v = vs.span(),
                                  .a = as.span(),
                                  .memory_valid = step > 0,
                                  .temporaries = &w,
                                  .wide = avx2_available()};
            };
            velocity_verlet(forces, arrays(x, v, a), 0.01 * step, 0.01);
            velocity_verlet(predicting, arrays(x2, v2, a2), 0.01 * step, 0.01);
        }
        for (std::size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(x.get(i)[k], x2.get(i)[k]) << "particle " << i << " axis " << k << ", m";
                EXPECT_EQ(v.get(i)[k], v2.get(i)[k]) << "particle " << i << " axis " << k << ", m/s";
            }
        }
    }
    // A damper or drag reads v: no skip.
    const std::vector<double> mass = {1.0, 1.0}, inv_mass = {0.0, 1.0};
    Springs damped;
    damped.list.push_back({0, 1, 0.5, 10.0, 0.1});
    const std::vector<ForceDef> with_damper = {damped}, with_drag = {UniformGravity{}, LinearDrag{0.1}};
    EXPECT_FALSE(ParticleForces(with_damper, mass, inv_mass).velocity_free());
    EXPECT_FALSE(ParticleForces(with_drag, mass, inv_mass).velocity_free());
}

std::uint64_t bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// Velocity Verlet given a second acceleration array (StepArrays::a_next, as
// the World gives it) writes v once a step instead of twice: the same bits
// as without, on the few-particle path and the wide one, with a force that
// reads v (a damper: the predicted velocity) and one that does not, and the
// same count from the watchdog's rules (a box that some particles leave).
TEST(VelocityVerlet, ItsSecondAccelerationArrayGivesTheSameBits) {
    for (const bool damped : {false, true}) {
        for (const std::size_t n : {std::size_t{3}, std::size_t{40}}) {
            SCOPED_TRACE(std::to_string(n) + (damped ? " particles, dampers" : " particles, no damper"));
            Fan fan(n, damped ? 0.3 : 0.0);
            auto& [mass, inv_mass, x, v, springs] = fan;
            const std::vector<ForceDef> defs = {UniformGravity{}, springs};
            ParticleForces forces(defs, mass, inv_mass);
            ASSERT_EQ(forces.velocity_free(), !damped);
            Vec3Array x2 = x, v2 = v, a(n), a2(n), a_next(n), w(n);
            std::size_t suspects = 0, suspects2 = 0;
            for (int step = 0; step < 50; ++step) {
                StepArrays::Watch watch{4.0, 3.0}, watch2 = watch;  // m²/s², m: some particles fail
                bool taken = false;
                velocity_verlet(forces,
                                {.x = x.span(),
                                 .v = v.span(),
                                 .a = a.span(),
                                 .a_next = a_next.span(),
                                 .a_next_taken = &taken,
                                 .memory_valid = step > 0,
                                 .temporaries = &w,
                                 .wide = avx2_available(),
                                 .watch = &watch},
                                0.01 * step, 0.01);
                ASSERT_TRUE(taken);
                std::swap(a, a_next);
                velocity_verlet(forces,
                                {.x = x2.span(),
                                 .v = v2.span(),
                                 .a = a2.span(),
                                 .memory_valid = step > 0,
                                 .temporaries = &w,
                                 .wide = avx2_available(),
                                 .watch = &watch2},
                                0.01 * step, 0.01);
                suspects += watch.suspects, suspects2 += watch2.suspects;
            }
            EXPECT_EQ(suspects, suspects2);
            EXPECT_GT(suspects, 0u) << "the box and the speed limit catch some";
            for (std::size_t i = 0; i < n; ++i) {
                for (int k = 0; k < 3; ++k) {
                    EXPECT_EQ(bits(x.get(i)[k]), bits(x2.get(i)[k])) << "particle " << i << " axis " << k;
                    EXPECT_EQ(bits(v.get(i)[k]), bits(v2.get(i)[k])) << "particle " << i << " axis " << k;
                    EXPECT_EQ(bits(a.get(i)[k]), bits(a2.get(i)[k])) << "particle " << i << " axis " << k;
                }
            }
        }
    }
}

// A few particles (at most StepArrays::kFewParticles) take their own paths:
// RK4's stages on the stack, and the force of one spring list (with a field
// or not) on at most kFewSpringParticles evaluated straight. The same
// particles inside a larger system (their springs first, then others among
// 20 more particles that never touch them) take the array paths: each of the
// few must end with the same bits, for every explicit method, with and
// without a field (linear drag alone, or with quadratic drag), dampers, on
// one bead (RK4's two-particle build, the spring pair, which leaves an
// anchor at rest out; its spring listed from the anchor, or to it with a
// rest length and a damper, or both springs; the anchor listed second),
// two free particles on one spring, a bead on a plastic spring, two beads,
// and a chain of more particles and springs than the straight evaluation
// takes (RK4's stack path with the spring plan's pass). Bits, not values:
// -0 is not +0 here.
enum class FewField { none, linear_drag, quadratic_drag };
enum class FewShape {
    one_bead,
    one_bead_reversed,
    one_bead_two_springs,
    anchor_second,
    free_pair,
    plastic_bead,
    two_beads,
    chain
};

ParticleModel few_beads(std::size_t extra, FewField field, FewShape shape) {
    ParticleModel model;
    model.particles = {{Vec3::Zero(), Vec3::Zero(), 1.0, true}, {Vec3(1.0, 0.2, 0.0), Vec3(0.0, 0.5, 0.1), 1.0, false}};
    Springs springs;
    springs.list = {{0, 1, 0.0, 4.0, 0.0}};
    if (shape == FewShape::one_bead_reversed) springs.list = {{1, 0, 0.6, 9.0, 0.3}};
    if (shape == FewShape::one_bead_two_springs) springs.list.push_back({1, 0, 0.6, 9.0, 0.3});
    if (shape == FewShape::anchor_second) std::swap(model.particles[0], model.particles[1]);
    if (shape == FewShape::free_pair) model.particles[0] = {Vec3(-0.3, 0.1, 0.2), Vec3(0.4, -0.2, 0.3), 2.5, false};
    if (shape == FewShape::plastic_bead) {  // its rest length creeps as it stretches: the pair reads the live spring
        springs.list = {{1, 0, 0.6, 9.0, 0.3}};
        springs.plasticity = {0.02, 3.0, 0.5};
    }
    if (shape == FewShape::two_beads || shape == FewShape::chain) {
        model.particles.push_back({Vec3(1.5, -0.4, 0.3), Vec3(0.2, 0.0, -0.3), 0.7, false});
        springs.list.push_back({1, 2, 0.6, 9.0, 0.3});
    }
    const std::size_t chain = shape == FewShape::chain ? 7 : 0;
    // The chain: each new bead tied to the one before and the one two before.
    for (std::size_t i = 0; i < chain; ++i) {
        const double s = static_cast<double>(i);
        const auto bead = static_cast<std::uint32_t>(3 + i);
        model.particles.push_back(
            {Vec3(2.0 + 0.5 * s, 0.3 * std::cos(s), -0.2 * s), Vec3(0.1, -0.2 * s, 0.05), 0.8, false});
        springs.list.push_back({bead - 1, bead, 0.5, 7.0, 0.2});
        springs.list.push_back({bead - 2, bead, 1.0, 3.0, 0.0});
    }
    const std::size_t few = model.particles.size();
    for (std::size_t i = 0; i < extra; ++i) {
        const double s = static_cast<double>(i);
        model.particles.push_back(
            {Vec3(5.0 + 0.4 * s, std::sin(s), 0.1 * s), Vec3(std::cos(s), 0.3, 0.0), 0.5, i == 0});
        if (i > 0)
            springs.list.push_back(
                {static_cast<std::uint32_t>(few + i - 1), static_cast<std::uint32_t>(few + i), 0.4, 6.0, 0.1});
    }
    model.forces.push_back(std::move(springs));
    if (field == FewField::linear_drag) model.forces.insert(model.forces.begin(), {UniformGravity{}, LinearDrag{0.05}});
    if (field == FewField::quadratic_drag)
        model.forces.insert(model.forces.begin(), {UniformGravity{}, LinearDrag{0.05}, QuadraticDrag{0.01}});
    return model;
}

TEST(FewParticles, TheirPathsGiveTheArrayPathsBits) {
    const char* fields[] = {"springs alone", "gravity and linear drag", "gravity, linear and quadratic drag"};
    const char* shapes[] = {"one bead",
                            "one bead, its spring reversed",
                            "one bead, two springs",
                            "one bead, the anchor second",
                            "two free particles",
                            "one plastic bead",
                            "two beads",
                            "a chain"};
    for (const IntegratorInfo& info : kIntegrators) {
        if (info.needs_jacobians) continue;
        for (const FewField field : {FewField::none, FewField::linear_drag, FewField::quadratic_drag}) {
            for (const FewShape shape : {FewShape::one_bead, FewShape::one_bead_reversed,
                                         FewShape::one_bead_two_springs, FewShape::anchor_second, FewShape::free_pair,
                                         FewShape::plastic_bead, FewShape::two_beads, FewShape::chain}) {
                SCOPED_TRACE(std::string(info.name) + ", " + fields[static_cast<int>(field)] + ", " +
                             shapes[static_cast<int>(shape)]);
                World few(few_beads(0, field, shape)), many(few_beads(20, field, shape));
                if (shape != FewShape::chain) {
                    ASSERT_LE(few.state().size(), kFewSpringParticles);
                } else {
                    ASSERT_GT(few.state().size(), kFewSpringParticles);
                }
                ASSERT_LE(few.state().size(), StepArrays::kFewParticles);
                ASSERT_GT(many.state().size(), StepArrays::kFewParticles);
                for (int i = 0; i < 120; ++i) {
                    few.step({info.id, 1.0 / 60.0, 2});
                    many.step({info.id, 1.0 / 60.0, 2});
                }
                ASSERT_FALSE(few.verdict().exploded()) << few.verdict().message("few");
                EXPECT_EQ(few.verdict().exploded(), many.verdict().exploded());
                for (std::size_t i = 0; i < few.state().size(); ++i) {
                    for (int k = 0; k < 3; ++k) {
                        EXPECT_EQ(bits(few.state().x.get(i)[k]), bits(many.state().x.get(i)[k]))
                            << "particle " << i << " axis " << k;
                        EXPECT_EQ(bits(few.state().v.get(i)[k]), bits(many.state().v.get(i)[k]))
                            << "particle " << i << " axis " << k;
                    }
                }
                const std::size_t bead = shape == FewShape::anchor_second ? 0 : 1;
                EXPECT_NE(few.state().x.get(bead), few.model().particles[bead].position) << "it moved";
                if (shape == FewShape::plastic_bead) {
                    EXPECT_NE(std::get<Springs>(few.live_forces().back()).list[0].rest, 0.6) << "m, it crept";
                }
            }
        }
    }
}

// `method` by two Dynamics of the same system from the same (x, v),
// `steps` steps of h, each side's acceleration kept as the World keeps it
// (two arrays that trade places when the method takes the second): the same
// bits for every particle. x, v: the first side's at the end.
void expect_same_bits(StepFn method, Dynamics& one, Dynamics& other, const Vec3Array& x0, const Vec3Array& v0,
                      int steps, double h, Vec3Array& x, Vec3Array& v) {
    struct Side {
        Dynamics& dynamics;
        Vec3Array x, v, a, a_next;
    };
    const std::size_t n = x0.size();
    Side sides[2] = {{one, x0, v0, Vec3Array(n), Vec3Array(n)}, {other, x0, v0, Vec3Array(n), Vec3Array(n)}};
    Vec3Array w(n);
    for (int step = 0; step < steps; ++step) {
        for (Side& side : sides) {
            bool taken = false;
            method(side.dynamics,
                   StepArrays{.x = side.x.span(),
                              .v = side.v.span(),
                              .a = side.a.span(),
                              .a_next = side.a_next.span(),
                              .a_next_taken = &taken,
                              .memory_valid = step > 0,
                              .temporaries = &w},
                   h * step, h);
            if (taken) std::swap(side.a, side.a_next);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(bits(sides[0].x.get(i)[k]), bits(sides[1].x.get(i)[k])) << "particle " << i << " axis " << k;
            EXPECT_EQ(bits(sides[0].v.get(i)[k]), bits(sides[1].v.get(i)[k])) << "particle " << i << " axis " << k;
        }
    }
    x = sides[0].x, v = sides[0].v;
}

// The methods with a pair path (the force inline, sim/pair_forces.h).
const std::pair<const char*, StepFn> kPairMethods[] = {{"RK4", rk4},
                                                       {"velocity Verlet", velocity_verlet},
                                                       {"leapfrog", leapfrog},
                                                       {"symplectic Euler", symplectic_euler},
                                                       {"forward Euler", forward_euler}};

// RK4 on a bead and its anchor (one spring, a field) leaves an anchor at
// rest out of its arithmetic; velocity Verlet, leapfrog and the Eulers step
// the pair inline too.
// Against the general path (the same list and a second, empty one: the few
// springs' and the pairs' paths take one list alone), the same bits: the
// anchor at rest,
// moving (pinned particles' velocities are 0 in a World, but the step does
// not assume it) or at -0 on two axes, first or second, the spring listed
// either way, over 200 steps; and on a step that overflows (a spring of
// 1e300 N/m), where the general path's anchor goes NaN (f 0), so the
// pair's must too.
TEST(FewParticles, AnAnchorAtRestGivesTheGeneralPathsBits) {
    const char* anchors[] = {"at rest", "moving", "at -0"};
    for (const bool overflow : {false, true}) {
        for (int anchor_state = 0; anchor_state < 3; ++anchor_state) {
            for (const bool anchor_second : {false, true}) {
                for (const bool reversed : {false, true}) {
                    SCOPED_TRACE(std::string(overflow ? "overflowing" : "200 steps") + ", anchor " +
                                 anchors[anchor_state] + (anchor_second ? ", second" : ", first") +
                                 (reversed ? ", spring listed from the bead" : ", spring listed from the anchor"));
                    const std::uint32_t anchor = anchor_second ? 1 : 0, bead = 1 - anchor;
                    std::vector<double> mass = {1.0, 1.0}, inv_mass = {1.0, 1.0};
                    inv_mass[anchor] = 0.0;
                    Vec3Array x(2), v(2);
                    x.set(bead, Vec3(1.0, 0.2, 0.0));
                    v.set(bead, Vec3(0.0, 0.5, 0.1));
                    if (anchor_state == 1) v.set(anchor, Vec3(0.3, -0.1, 0.0));
                    if (anchor_state == 2) x.set(anchor, Vec3(-0.0, 0.0, -0.0));
                    Springs springs;
                    springs.list = {{anchor, bead, 0.3, overflow ? 1e300 : 4.0, 0.2}};
                    if (reversed) std::swap(springs.list[0].i, springs.list[0].j);
                    const std::vector<ForceDef> defs = {UniformGravity{}, LinearDrag{0.05}, springs};
                    std::vector<ForceDef> two_lists = defs;
                    two_lists.push_back(Springs{});
                    ParticleForces pair(defs, mass, inv_mass), general(two_lists, mass, inv_mass);
                    ASSERT_NE(pair.pair_path(2).spring, nullptr);
                    ASSERT_EQ(general.pair_path(2).spring, nullptr);
                    for (const auto& [name, method] : kPairMethods) {
                        SCOPED_TRACE(name);
                        Vec3Array x1, v1;
                        expect_same_bits(method, pair, general, x, v, overflow ? 1 : 200, 0.01, x1, v1);
                        if (method == rk4) {  // (velocity Verlet's one step, on the forces at the start, stays finite)
                            EXPECT_EQ(x1.get(anchor).allFinite(), !overflow) << "NaN on both paths, or finite";
                        }
                        EXPECT_NE(x1.get(bead), Vec3(1.0, 0.2, 0.0)) << "it moved";
                    }
                }
            }
        }
    }
}

// A bead on a stiff spring of rest length 0 (linear: no amplitude where it
// would stop growing) to its anchor (ω = 100 rad/s), a micrometre from
// rest, and `extra` free particles at rest beside it that no force moves.
ParticleModel stiff_bead(std::size_t extra) {
    ParticleModel model;
    model.particles = {{Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.0, true},
                       {Vec3(1e-6, 0.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.0, false}};
    for (std::size_t i = 0; i < extra; ++i) {
        model.particles.push_back({Vec3(2.0 + static_cast<double>(i), 0.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.0, false});
    }
    Springs springs;
    springs.list = {{0, 1, 0.0, 1e4, 0.0}};
    model.forces = {springs};
    return model;
}

// Past its stability limit (ω h = 3) every explicit method blows the stiff
// bead up, over frames (RK4's amplitude grows 1.5 times a step, symplectic
// Euler's 6.9 times), and the watchdog, whose rules the pair paths
// (all but position Verlet's) apply themselves, stops it at the frame and for
// the reason it does when the bead is stepped among 20 more particles (the
// array path). Not on the first frame: the World times it, and a timed frame
// takes the general path.
TEST(FewParticles, TheWatchdogStopsAPairAsItStopsTheArrays) {
    for (const IntegratorInfo& info : kIntegrators) {
        if (info.needs_jacobians) continue;
        SCOPED_TRACE(info.name);
        World pair(stiff_bead(0)), many(stiff_bead(20));
        ASSERT_GT(many.state().size(), StepArrays::kFewParticles);
        for (int i = 0; i < 400; ++i) {
            pair.step({info.id, 0.03, 1});
            many.step({info.id, 0.03, 1});
        }
        ASSERT_TRUE(many.verdict().exploded()) << "the array path's verdict, the prediction";
        ASSERT_GT(many.verdict().frame, 2u);
        ASSERT_TRUE(pair.verdict().exploded()) << "stopped within 400 frames, as the array path was";
        EXPECT_EQ(pair.verdict().frame, many.verdict().frame);
        EXPECT_EQ(pair.verdict().quantity, many.verdict().quantity);
    }
}

// Orbiters [first, first + n) of a family, all pulled towards one fixed
// point (central gravity: local, and not a uniform field, so no fused pass).
ParticleModel orbiters(std::size_t n, std::size_t first = 0) {
    ParticleModel model;
    for (std::size_t i = first; i < first + n; ++i) {
        const double s = static_cast<double>(i);
        model.particles.push_back({Vec3(1.0 + 0.1 * s, 0.2 * s, -0.1), Vec3(0.1, 1.0, 0.05 * s), 1.0, false});
    }
    model.forces.push_back(CentralGravity{Vec3(0.0, 0.0, 0.0), 1.0});
    return model;
}

// Every explicit method, `frames` frames: orbiter `in_many` of `many` gets
// the bits the one orbiter of `alone` gets.
void expect_alone_bits(const ParticleModel& alone_model, const ParticleModel& many_model, std::size_t in_many,
                       int frames) {
    for (const IntegratorInfo& info : kIntegrators) {
        if (info.needs_jacobians) continue;
        SCOPED_TRACE(info.name);
        World alone(alone_model), many(many_model);
        for (int i = 0; i < frames; ++i) {
            alone.step({info.id, 1.0 / 60.0, 2});
            many.step({info.id, 1.0 / 60.0, 2});
        }
        ASSERT_FALSE(many.verdict().exploded()) << many.verdict().message("many");
        ASSERT_FALSE(alone.verdict().exploded()) << alone.verdict().message("alone");
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(bits(alone.state().x.get(0)[k]), bits(many.state().x.get(in_many)[k])) << "axis " << k;
            EXPECT_EQ(bits(alone.state().v.get(0)[k]), bits(many.state().v.get(in_many)[k])) << "axis " << k;
        }
        EXPECT_NE(alone.state().x.get(0), alone.model().particles[0].position) << "it moved";
    }
}

// One particle alone (RK4's stack path) and inside 20 more: the same bits.
TEST(FewParticles, OneParticleGivesTheArrayPathsBits) {
    ASSERT_GT(orbiters(21).particles.size(), StepArrays::kFewParticles);
    expect_alone_bits(orbiters(1), orbiters(21), 0, 120);
}

// A system of local forces larger than a block is stepped block by block,
// each block's arrays built from the World's (velocity Verlet's two
// acceleration arrays trading places after every step): the last orbiter
// of 1100 (in the second block) gets the bits it gets alone.
TEST(FewParticles, TheLastBlocksParticleGivesItsBitsAlone) {
    expect_alone_bits(orbiters(1, 1099), orbiters(1100), 1099, 60);
}

// The methods with a pair path on Newton's gravity between two particles (a
// planet around its sun) evaluate it inline (Dynamics::pair_path's
// gravity); a Dynamics that only forwards acceleration() takes the general
// few-particle path instead: the same bits, with the sun pinned (first or
// second) or free, softened or not, in a field or not, with drag (a force
// that reads velocity: velocity Verlet's prediction) or without.
TEST(FewParticles, TheGravityPairGivesTheGeneralPathsBits) {
    const char* fields[] = {"no field", "in a field", "in a field with drag"};
    for (const int field : {0, 1, 2}) {
        for (const double softening : {0.0, 0.05}) {
            for (int pinned = -1; pinned < 2; ++pinned) {
                SCOPED_TRACE(std::string(fields[field]) + ", softening " + std::to_string(softening) +
                             " m, pinned particle " + std::to_string(pinned));
                std::vector<double> mass = {2.0, 1e-3}, inv_mass = {0.5, 1e3};
                if (pinned >= 0) inv_mass[static_cast<std::size_t>(pinned)] = 0.0;
                Vec3Array x(2), v(2);
                x.set(1, Vec3(0.5, 0.1, 0.0));
                v.set(1, Vec3(0.0, 2.0, 0.1));
                std::vector<ForceDef> defs = {NewtonGravity{1.0, softening}};
                if (field > 0) defs.insert(defs.begin(), UniformGravity{});
                if (field > 1) defs.insert(defs.begin(), LinearDrag{0.3});
                ParticleForces pair(defs, mass, inv_mass), forwarded(defs, mass, inv_mass);
                PredictingForces general(forwarded);
                ASSERT_NE(pair.pair_path(2).gravity, nullptr);
                ASSERT_EQ(general.pair_path(2).gravity, nullptr);
                for (const auto& [name, method] : kPairMethods) {
                    SCOPED_TRACE(name);
                    Vec3Array x1, v1;
                    expect_same_bits(method, pair, general, x, v, 200, 0.005, x1, v1);
                    EXPECT_TRUE(x1.get(1).allFinite());
                    EXPECT_NE(x1.get(1), Vec3(0.5, 0.1, 0.0)) << "it moved";
                }
            }
        }
    }
}

}  // namespace
}  // namespace sim::test
