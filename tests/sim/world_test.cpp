// sim::World: validation of the description and of the step, substeps,
// block-by-block stepping, energy.
#include "sim/world.h"
#include "sim/cpu.h"
#include "sim/error.h"
#include "sim/mass_spring.h"
#include "sim/problems.h"
#include "sim/state_hash.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sim::test {
namespace {

using namespace sim::problems;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Validation, RefusesBadParticles) {
    auto build = [](ParticleDef p) { return [p] { World world(ParticleModel{{ParticleDef{}, p}, {}}); }; };
    EXPECT_EQ(error_of(build({Vec3::Zero(), Vec3::Zero(), -1.0, false})),
              "particles[1].mass must be > 0 and finite, in kg (got -1)");
    EXPECT_EQ(error_of(build({Vec3::Zero(), Vec3::Zero(), NAN, false})),
              "particles[1].mass must be > 0 and finite, in kg (got nan)");
    EXPECT_EQ(error_of(build({Vec3::Zero(), Vec3::Zero(), 0.0, true})),
              "particles[1].mass must be > 0 and finite, in kg (got 0)");
    EXPECT_EQ(error_of(build({Vec3(0, INFINITY, 0), Vec3::Zero(), 1.0, false})),
              "particles[1].position must be finite, in m (got [0, inf, 0])");
    EXPECT_EQ(error_of(build({Vec3::Zero(), Vec3(NAN, 0, 0), 1.0, false})),
              "particles[1].velocity must be finite, in m/s (got [nan, 0, 0])");
    EXPECT_EQ(error_of(build({Vec3::Zero(), Vec3::Zero(), 2.0, false})), "");
}

TEST(Validation, RefusesBadSteps) {
    World world(ballistic_model());
    const Vec3 before = world.state().x.get(0);
    EXPECT_EQ(error_of([&] { world.step({Integrator::rk4, 0.0, 1}); }), "dt must be > 0 and finite, in s (got 0)");
    EXPECT_EQ(error_of([&] {
                  world.step({Integrator::rk4, -0.01, 1});
              }),
              "dt must be > 0 and finite, in s (got -0.01)");
    EXPECT_EQ(error_of([&] { world.step({Integrator::rk4, NAN, 1}); }), "dt must be > 0 and finite, in s (got nan)");
    EXPECT_EQ(error_of([&] {
                  world.step({Integrator::rk4, INFINITY, 1});
              }),
              "dt must be > 0 and finite, in s (got inf)");
    EXPECT_EQ(error_of([&] { world.step({Integrator::rk4, 0.01, 0}); }), "substeps must be >= 1 (got 0)");
    EXPECT_EQ(world.state().x.get(0), before) << "a refused step changes nothing";
    EXPECT_EQ(world.steps(), 0u);
}

TEST(Substeps, AreStepsOfDtOverSubsteps) {
    World a(kepler_model(0.5));
    World b(kepler_model(0.5));
    for (int i = 0; i < 50; ++i) {
        a.step({Integrator::rk4, 0.04, 4});
        for (int j = 0; j < 4; ++j) {
            b.step({Integrator::rk4, 0.01, 1});
        }
    }
    EXPECT_EQ(a.state().x.flat(), b.state().x.flat()) << "bit-identical";
    EXPECT_EQ(a.steps(), 200u);
}

TEST(Substeps, TheObserverSeesEachSubstepOnceItHasRun) {
    // One substep or three, each seen once, in order, its time already
    // advanced; no longer once the observer is taken away. (A Kepler orbit
    // has no other stage: the World would take its bare step without the
    // observer.)
    for (const int substeps : {1, 3}) {
        SCOPED_TRACE(testing::Message() << substeps << " substeps");
        World world(kepler_model(0.5));
        std::vector<std::pair<int, double>> seen;
        world.set_substep_observer([&](int i) { seen.emplace_back(i, world.state().t); });
        world.step({Integrator::rk4, 0.03, substeps});
        ASSERT_EQ(seen.size(), static_cast<std::size_t>(substeps));
        for (int i = 0; i < substeps; ++i) {
            EXPECT_EQ(seen[i].first, i);
            EXPECT_NEAR(seen[i].second, 0.03 * (i + 1) / substeps, 1e-15) << "s";
        }
        world.set_substep_observer({});
        world.step({Integrator::rk4, 0.03, substeps});
        EXPECT_EQ(seen.size(), static_cast<std::size_t>(substeps)) << "taken away";
    }
}

// Many particles under gravity and drag only: every force is local, so the
// world steps them block by block. Some start with velocity or position
// components of +0 and -0, where a zero force's sign could show.
ParticleModel cloud() {
    ParticleModel model;
    for (int i = 0; i < 1500; ++i) {  // three blocks, the last one partial
        const double s = i;
        Vec3 x(std::sin(s), std::cos(0.3 * s), 0.01 * s), v(0.2 * std::cos(s), 1.0, 0.1);
        if (i % 5 == 1) v = Vec3(0.0, 1.0, -0.0);
        if (i % 5 == 2) v = Vec3(-0.0, 0.0, 0.0), x = Vec3(-0.0, 1.0, 0.0);
        model.particles.push_back({x, v, 0.5 + 0.001 * s, i % 97 == 0});
    }
    model.forces = {UniformGravity{}, LinearDrag{0.02}, QuadraticDrag{0.01}};
    return model;
}

std::vector<std::uint64_t> bits(const std::vector<double>& values) {  // each double's: -0 is not +0 here
    std::vector<std::uint64_t> out(values.size());
    std::transform(values.begin(), values.end(), out.begin(), [](double d) { return std::bit_cast<std::uint64_t>(d); });
    return out;
}

// The gravities the fused loops build for: straight down (the build without
// m 0, is_vertical), slanted, and down with -0 across (the general build).
const Vec3 kGravities[] = {Vec3(0.0, -9.81, 0.0), Vec3(1.5, -9.81, 0.5), Vec3(-0.0, -9.81, -0.0)};

std::string gravity_name(const Vec3& g) {
    auto component = [](double d) { return (std::signbit(d) ? "-" : "") + std::to_string(std::abs(d)); };
    return "g = (" + component(g.x()) + ", " + component(g.y()) + ", " + component(g.z()) + ") m/s²";
}

// The cloud (a uniform field) steps block by block through the fused pass;
// coupled by a spring of zero stiffness, whole through the array path: the
// same bits for each gravity and drag (none: velocity Verlet predicts no v').
class Blocks : public testing::TestWithParam<Integrator> {};

TEST_P(Blocks, BlockByBlockEqualsWholeSystem) {
    for (const Vec3& g : kGravities) {
        for (const std::string drag : {"quadratic drag", "linear drag alone", "no drag"}) {
            SCOPED_TRACE(gravity_name(g) + ", " + drag);
            ParticleModel model = cloud();
            model.forces = {UniformGravity{g}};
            if (drag != "no drag") model.forces.push_back(LinearDrag{0.02});
            if (drag == "quadratic drag") model.forces.push_back(QuadraticDrag{0.01});
            ParticleModel coupled = model;
            coupled.forces.push_back(Springs{{{0, 1, 1.0, 0.0, 0.0}}});
            World blocked(model), whole(coupled);
            for (int i = 0; i < 30; ++i) {
                blocked.step({GetParam(), 1.0 / 60.0, 2});
                whole.step({GetParam(), 1.0 / 60.0, 2});
            }
            EXPECT_EQ(bits(blocked.state().x.flat()), bits(whole.state().x.flat())) << "bit-exact";
            EXPECT_EQ(bits(blocked.state().v.flat()), bits(whole.state().v.flat())) << "bit-exact";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Explicit, Blocks,
                         testing::Values(Integrator::forward_euler, Integrator::symplectic_euler, Integrator::leapfrog,
                                         Integrator::velocity_verlet, Integrator::position_verlet, Integrator::rk4),
                         [](const auto& info) { return std::string(integrator_info(info.param).name); });

// The particles' passes run their AVX2 builds where the CPU has it, and the
// pinned instruction set's otherwise (sim/cpu.h). Both must give the same
// bits, for every method, on the fused path (the cloud: gravity, linear and
// quadratic drag) and on the array path (a damped mass-spring cloth with
// pinned corners, gravity and drag), each over more than a few particles.
class Widths : public testing::TestWithParam<Integrator> {};

ParticleModel sheet() {
    ParticleModel model;
    constexpr int kSide = 9;  // 81 particles
    for (int i = 0; i < kSide; ++i) {
        for (int j = 0; j < kSide; ++j) {
            model.particles.push_back({Vec3(0.1 * i, 2.0, 0.1 * j + 0.01 * i), Vec3(0.0, 0.0, 0.3 * std::sin(i + j)),
                                       0.02, i == 0 && (j == 0 || j == kSide - 1)});
        }
    }
    Springs springs;
    for (int i = 0; i < kSide; ++i) {
        for (int j = 0; j < kSide; ++j) {
            const auto at = [](int a, int b) { return static_cast<std::uint32_t>(a * kSide + b); };
            if (i + 1 < kSide) springs.list.push_back({at(i, j), at(i + 1, j), 0.1, 40.0, 0.05});
            if (j + 1 < kSide) springs.list.push_back({at(i, j), at(i, j + 1), 0.1, 40.0, 0.05});
            if (i + 1 < kSide && j + 1 < kSide) springs.list.push_back({at(i, j), at(i + 1, j + 1), 0.0, 5.0, 0.0});
        }
    }
    model.forces = {UniformGravity{}, LinearDrag{0.01}, std::move(springs)};
    return model;
}

TEST_P(Widths, AvxBuildsGiveThePinnedBuildsBits) {
    if (!avx2_available()) GTEST_SKIP() << "this CPU has no AVX2: only the pinned builds run";
    for (const bool cloth : {false, true}) {
        SCOPED_TRACE(cloth ? "array path (springs)" : "fused path (uniform field)");
        World wide(cloth ? sheet() : cloud());
        World pinned(cloth ? sheet() : cloud());
        pinned.set_wide(false);
        ASSERT_TRUE(wide.wide());
        ASSERT_FALSE(pinned.wide());
        for (int i = 0; i < 30; ++i) {
            wide.step({GetParam(), 1.0 / 60.0, 4});
            pinned.step({GetParam(), 1.0 / 60.0, 4});
        }
        ASSERT_FALSE(wide.verdict().exploded()) << wide.verdict().message("the wide run");
        EXPECT_EQ(wide.state().x.flat(), pinned.state().x.flat()) << "bit-exact";
        EXPECT_EQ(wide.state().v.flat(), pinned.state().v.flat()) << "bit-exact";
    }
}

INSTANTIATE_TEST_SUITE_P(All, Widths, testing::ValuesIn([] {
                             std::vector<Integrator> all;
                             for (const IntegratorInfo& info : kIntegrators) all.push_back(info.id);
                             return all;
                         }()),
                         [](const auto& info) { return std::string(integrator_info(info.param).name); });

// Backward Euler on gravity and one linear drag solves its diagonal system
// particle by particle (backward_euler.cpp); a zero-stiffness spring makes the
// same system coupled, solved through the sparse LDLᵀ. Same bits, with
// pinned particles and without (the diagonal solve then leaves their
// factor out), for each of kGravities; with a second drag or quadratic drag
// it must take the sparse path.
TEST(BackwardEuler, DiagonalSolveEqualsTheSparseSolve) {
    for (const Vec3& g : kGravities) {
        for (const bool pins : {true, false}) {
            for (double c : {0.0, 0.05}) {
                ParticleModel model = cloud();
                if (!pins) {
                    for (ParticleDef& p : model.particles) p.pinned = false;
                }
                model.forces = {UniformGravity{g}, LinearDrag{c}};
                ParticleModel coupled = model;
                coupled.forces.push_back(Springs{{{0, 1, 1.0, 0.0, 0.0}}});
                World diagonal(model), sparse(coupled);
                for (int i = 0; i < 20; ++i) {
                    diagonal.step({Integrator::backward_euler, 1.0 / 60.0, 2});
                    sparse.step({Integrator::backward_euler, 1.0 / 60.0, 2});
                }
                const std::string what =
                    gravity_name(g) + ", c = " + std::to_string(c) + " N·s/m" + (pins ? ", pins" : "");
                EXPECT_EQ(bits(diagonal.state().x.flat()), bits(sparse.state().x.flat())) << what << ", bit-exact";
                EXPECT_EQ(bits(diagonal.state().v.flat()), bits(sparse.state().v.flat())) << what << ", bit-exact";
                EXPECT_EQ(diagonal.force_evaluations(), sparse.force_evaluations());
            }
        }
    }
}

// The watchdog's per-particle rules run inside the integrator's last pass
// when no later stage moves a particle: each method's fused loop where a
// uniform field is the whole force (block by block), its array path's last
// pass otherwise (here a spring of zero stiffness makes the force more than
// the field: the same motion, the array path). A far-away ground plane
// (never reached) makes the same cloud take the full pass after the
// collisions stage: both must reach the same verdict, frame, particle and
// value, for a particle in the last, partial block, with every integrator.
TEST(Watchdog, ChecksInsideTheIntegratorsPassFindWhatTheFullPassFinds) {
    struct Case {
        const char* quantity;
        Vec3 x, v;  // m, m/s of particle 1400
    };
    for (const IntegratorInfo& method : kIntegrators) {
        for (const Case& c : {Case{"speed", Vec3(0.0, 0.0, 0.0), Vec3(0.0, -499.0, 0.0)},
                              Case{"bounds", Vec3(9999.5, 0.0, 0.0), Vec3(20.0, 0.0, 0.0)},
                              Case{"non-finite", Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.0)}}) {
            for (const bool array_path : {false, true}) {
                ParticleModel model = cloud();
                model.forces = {UniformGravity{}};
                if (array_path) model.forces.push_back(Springs{{{0, 1, 1.0, 0.0, 0.0}}});
                model.particles[1400].position = c.x;
                model.particles[1400].velocity = c.v;
                ParticleModel watched_after = model;
                watched_after.collisions.colliders.push_back(PlaneCollider{Vec3::UnitY(), -5000.0});
                World inside(model), after(watched_after);
                const std::string what =
                    std::string(method.name) + ", " + c.quantity + (array_path ? ", array path" : ", fused");
                for (int i = 0; i < 60; ++i) {
                    if (i == 30 && std::string_view(c.quantity) == "non-finite") {
                        // A NaN that only the per-particle rules can see (the loader never lets one in).
                        inside.edit_state().v.set(1400, Vec3(0.0, std::nan(""), 0.0));
                        after.edit_state().v.set(1400, Vec3(0.0, std::nan(""), 0.0));
                    }
                    inside.step({method.id, 1.0 / 60.0, 1});
                    after.step({method.id, 1.0 / 60.0, 1});
                }
                ASSERT_TRUE(inside.verdict().exploded()) << what;
                EXPECT_EQ(inside.verdict().index, 1400u) << what;
                EXPECT_EQ(inside.verdict().quantity, after.verdict().quantity) << what;
                EXPECT_EQ(inside.verdict().frame, after.verdict().frame) << what;
                if (std::string_view(c.quantity) != "non-finite") {
                    EXPECT_EQ(inside.verdict().quantity, c.quantity) << what;
                    EXPECT_EQ(inside.verdict().value, after.verdict().value) << what << ", bit-exact";
                }
            }
        }
    }
}

// The per-system times are measured on a sample of frames: the first, then
// few for a light step (the clocks would cost as much as the step), every
// one for a heavy step. What the timing reports is per sampled
// step; it never changes the physics (same bits with the frames timed or not).
TEST(Timing, SamplesFewFramesOfALightStepAndEveryFrameOfAHeavyOne) {
    World light(oscillator_model({}, Vec3(1.0, 0.0, 0.0), Vec3::Zero()));
    for (int i = 0; i < 20000; ++i) light.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    const World::SystemTimes& t = light.times();
    // (How many depends on what a clock read costs against the step here:
    // about 35, one frame in 500 or so after the first few.)
    EXPECT_GE(t.sampled_frames, 2u) << "the second frame (the first is not timed), and more as the run goes on";
    EXPECT_LT(t.sampled_frames, 20000u / 20) << "a ~20 ns step is not timed every frame";
    EXPECT_EQ(t.sampled_steps, t.sampled_frames) << "one step per frame";
    EXPECT_GT(t.ms_per_step(t.total), 0.0);
    EXPECT_GE(t.ms_per_step(t.total), t.ms_per_step(t.particles)) << "the whole step includes its stages";

    World heavy(cloud());  // 1500 particles, 8 substeps of RK4: about 80 µs a frame here
    for (int i = 0; i < 40; ++i) heavy.step({Integrator::rk4, 1.0 / 60.0, 8});
    EXPECT_GE(heavy.times().sampled_frames, 20u) << "the clocks cost under 1% of such a frame";
    EXPECT_EQ(heavy.times().sampled_steps, 8 * heavy.times().sampled_frames);
    EXPECT_EQ(light.times().ms_per_step(0.0), 0.0);
    EXPECT_EQ(World::SystemTimes{}.ms_per_step(1.0), 0.0) << "no sample yet: 0, not a division by zero";
}

// A sampled frame times the step that runs, not a slower one: a bead's
// spring is evaluated inline (the pair's path, every method but position
// Verlet's and backward Euler's), in the sampled frames too, so its time is
// the particles' and the springs' stays 0; a cloth's spring pass is a pass,
// timed apart.
TEST(Timing, ASampledFrameTimesTheStepThatRuns) {
    for (const IntegratorInfo& method : kIntegrators) {
        if (method.id == Integrator::position_verlet || method.needs_jacobians) continue;
        World bead(oscillator_model({}, Vec3(1.0, 0.0, 0.0), Vec3::Zero()));
        for (int i = 0; i < 2000; ++i) bead.step({method.id, 1.0 / 60.0, 1});
        EXPECT_GT(bead.times().sampled_frames, 1u) << method.name;
        EXPECT_EQ(bead.times().springs, 0.0) << method.name << ", s: inside the particles' time";
        EXPECT_GT(bead.times().particles, 0.0) << method.name << ", s";
    }
    World cloth(sheet());
    for (int i = 0; i < 20; ++i) cloth.step({Integrator::symplectic_euler, 1.0 / 60.0, 2});
    EXPECT_GT(cloth.times().springs, 0.0) << "s, the spring pass of 81 particles";
}

// One definition of the systems: the World's stages, the names `run --json`
// lists, and a time for each name. A spring's pass is timed apart from the
// particles' (the two partition the force evaluation).
TEST(Timing, EverySystemTheWorldRunsHasATime) {
    ParticleModel model = oscillator_model({}, Vec3(1.0, 0.0, 0.0), Vec3::Zero());
    model.collisions.colliders.push_back(PlaneCollider{Vec3::UnitY(), -10.0});
    World timed(model);
    const std::vector<std::string> names = timed.systems().names();
    EXPECT_EQ(names, (std::vector<std::string>{"particles", "springs", "collisions", "watchdog"}));
    for (int i = 0; i < 20; ++i) timed.step({Integrator::rk4, 1.0 / 60.0, 2});
    for (const std::string& name : names) EXPECT_GE(timed.times().of(name), 0.0) << name << ", s";
    EXPECT_GT(timed.times().sampled_frames, 0u);
    EXPECT_THROW(timed.times().of("gravity"), InputError) << "not a system: a generator inside particles";

    // A colliderless model has no collision stage, and its name is not listed.
    model.collisions.colliders.clear();
    EXPECT_EQ(World(model).systems().names(), (std::vector<std::string>{"particles", "springs", "watchdog"}));
}

TEST(Energy, KineticPlusPotential) {
    World world(ballistic_model());
    // ½ m |v|² = ½ · 1 · 25 J, U = -m g·x = 0 at the origin
    EXPECT_DOUBLE_EQ(world.kinetic_energy(), 12.5);
    EXPECT_DOUBLE_EQ(world.potential_energy(), 0.0);
    world.step({Integrator::velocity_verlet, 0.1, 1});
    // Exact for a constant force: the total stays 12.5 J to round-off.
    EXPECT_NEAR(world.energy(), 12.5, 1e-12) << "J";
}

TEST(Energy, TwoBodiesConserveMomentum) {
    ParticleModel model;
    model.particles.push_back({Vec3(-1, 0, 0), Vec3(0, -0.2, 0), 3.0, false});
    model.particles.push_back({Vec3(2, 0, 0), Vec3(0, 0.6, 0.1), 1.0, false});
    model.forces.push_back(NewtonGravity{1.0, 0.0});
    World world(model);
    auto momentum = [&] {
        return Vec3(world.state().mass[0] * world.state().v.get(0) + world.state().mass[1] * world.state().v.get(1));
    };
    const Vec3 p0 = momentum();
    for (int i = 0; i < 1000; ++i) {
        world.step({Integrator::velocity_verlet, 0.01, 1});
    }
    EXPECT_LT((momentum() - p0).norm(), 1e-12) << "kg·m/s";
}

TEST(EditState, RestartsIntegratorMemory) {
    // After an edit, leapfrog must not reuse the acceleration cached for the
    // old position: the result equals a fresh world started from the edit.
    ParticleModel model = oscillator_model({1.0, 4.0, 0.0}, Vec3(1, 0, 0), Vec3::Zero());
    World edited(model);
    for (int i = 0; i < 5; ++i) {
        edited.step({Integrator::leapfrog, 0.01, 1});
    }
    edited.edit_state().x.set(1, Vec3(0.2, 0.3, 0.0));
    edited.edit_state().v.set(1, Vec3::Zero());
    edited.step({Integrator::leapfrog, 0.01, 1});

    model.particles[1].position = Vec3(0.2, 0.3, 0.0);
    World fresh(model);
    fresh.step({Integrator::leapfrog, 0.01, 1});
    EXPECT_EQ(edited.state().x.get(1), fresh.state().x.get(1));
}

TEST(EditState, ArraysReplacedWholeAreTheOnesStepped) {
    // The World keeps a small system's step arrays from step to step; arrays
    // replaced whole through edit_state (moved in: a new allocation) must be
    // the ones the next step reads and advances, for every method.
    for (const IntegratorInfo& info : kIntegrators) {
        const ParticleModel model = oscillator_model({1.0, 4.0, 0.0}, Vec3(1, 0, 0), Vec3::Zero());
        World edited(model);
        for (int i = 0; i < 3; ++i) edited.step({info.id, 0.01, 1});
        Vec3Array x(2), v(2);
        x.set(1, Vec3(0.2, 0.3, 0.0));
        edited.edit_state().x = std::move(x);
        edited.edit_state().v = std::move(v);
        edited.step({info.id, 0.01, 1});

        ParticleModel moved = model;
        moved.particles[1].position = Vec3(0.2, 0.3, 0.0);
        World fresh(moved);
        fresh.step({info.id, 0.01, 1});
        EXPECT_EQ(edited.state().x.get(1), fresh.state().x.get(1)) << info.name;
        EXPECT_EQ(edited.state().v.get(1), fresh.state().v.get(1)) << info.name;
    }
}
// A hook (pinned, at the origin) and `beads` particles of 1 kg, each on a
// spring of 1 N/m and rest length 0 to it: the report's batch, whose spring
// pass reads the shared stiffness and inverse mass once (sim/spring_plan.h).
ParticleModel beads_on_a_hook(std::uint32_t beads) {
    ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    Springs springs;
    for (std::uint32_t b = 1; b <= beads; ++b) {
        const double s = b;
        model.particles.push_back({Vec3(std::cos(s), std::sin(s), 0.01 * s), Vec3(0.0, 0.5, 0.0), 1.0, false});
        springs.list.push_back({0, b, 0.0, 1.0, 0.0});
    }
    model.forces.push_back(std::move(springs));
    return model;
}

// A World started from `state` (its positions, velocities and masses) of beads_on_a_hook.
std::unique_ptr<World> started_from(const ParticleState& state) {
    ParticleModel model = beads_on_a_hook(static_cast<std::uint32_t>(state.size() - 1));
    for (std::size_t i = 0; i < state.size(); ++i) {
        model.particles[i] = {state.x.get(i), state.v.get(i), state.mass[i], state.inv_mass[i] == 0.0};
    }
    return std::make_unique<World>(std::move(model));
}

TEST(Masses, EveryWriteReachesTheSpringPass) {
    // The spring pass keeps what it found in the inverse masses (every bead
    // of one mass) until the World says they changed. After each write of
    // a bead's mass (edit_state, restore) the run goes on as a World built
    // with the new masses, bit for bit; a contained range (pinned) stays
    // where it was frozen.
    const StepSettings step{Integrator::velocity_verlet, 0.01, 1};
    {
        SCOPED_TRACE("edit_state");
        World world(beads_on_a_hook(64));
        for (int i = 0; i < 10; ++i) world.step(step);
        ParticleState& state = world.edit_state();
        state.mass[5] = 4.0, state.inv_mass[5] = 0.25;
        const auto fresh = started_from(world.state());
        for (int i = 0; i < 50; ++i) world.step(step), fresh->step(step);
        EXPECT_EQ(bits(world.state().x.flat()), bits(fresh->state().x.flat())) << "bit-exact";
        EXPECT_EQ(bits(world.state().v.flat()), bits(fresh->state().v.flat())) << "bit-exact";
    }
    {
        SCOPED_TRACE("restore");
        World world(beads_on_a_hook(64));
        world.edit_state().mass[5] = 4.0, world.edit_state().inv_mass[5] = 0.25;
        const World::Snapshot saved = world.snapshot();
        world.edit_state().mass[5] = 1.0, world.edit_state().inv_mass[5] = 1.0;
        for (int i = 0; i < 10; ++i) world.step(step);
        world.restore(saved);
        const auto fresh = started_from(saved.state);
        for (int i = 0; i < 50; ++i) world.step(step), fresh->step(step);
        EXPECT_EQ(bits(world.state().x.flat()), bits(fresh->state().x.flat())) << "bit-exact";
        EXPECT_EQ(bits(world.state().v.flat()), bits(fresh->state().v.flat())) << "bit-exact";
    }
    {
        SCOPED_TRACE("a contained range");
        ParticleModel model = beads_on_a_hook(64);
        model.particles[3].velocity = Vec3(600.0, 0.0, 0.0);  // over the watchdog's 500 m/s
        const Vec3 start4 = model.particles[4].position;
        World world(std::move(model));
        WatchdogLimits limits;
        limits.contain.push_back({"bead 3", 3, 1});
        world.set_watchdog(limits);
        world.step(step);
        ASSERT_EQ(world.contained().size(), 1u);
        const Vec3 frozen = world.state().x.get(3);
        for (int i = 0; i < 50; ++i) world.step(step);
        EXPECT_EQ(world.state().x.get(3), frozen) << "pinned, bit-exact";
        EXPECT_EQ(world.state().v.get(3), Vec3::Zero());
        EXPECT_NE(world.state().x.get(4), start4) << "the others move";
    }
}

// Rewind: snapshot mid-run (integrator memory warm), run on, restore, run
// the same frames again. Both runs, and a run that never rewound, must agree
// to the bit, for every method (position Verlet's x_prev and leapfrog's
// cached acceleration are part of what a snapshot holds).
class Rewind : public testing::TestWithParam<Integrator> {};

TEST_P(Rewind, RestoreAndStepGivesTheSameBits) {
    const StepSettings step{GetParam(), 1.0 / 60.0, 3};
    World straight(kepler_model(0.5));
    World rewound(kepler_model(0.5));
    for (int i = 0; i < 10; ++i) {
        straight.step(step);
        rewound.step(step);
    }
    const World::Snapshot saved = rewound.snapshot();
    for (int i = 0; i < 20; ++i) {
        rewound.step(step);
        straight.step(step);
    }
    const std::uint64_t first = state_hash(rewound.state());
    ASSERT_EQ(first, state_hash(straight.state()));

    rewound.restore(saved);
    EXPECT_EQ(rewound.frames(), 10u);
    EXPECT_EQ(state_hash(rewound.state()), state_hash(saved.state));
    for (int i = 0; i < 20; ++i) {
        rewound.step(step);
    }
    EXPECT_EQ(state_hash(rewound.state()), first);
    EXPECT_EQ(rewound.steps(), straight.steps());
}

TEST(Rewind, RestoringBeforeAnExplosionClearsTheVerdict) {
    // Forward Euler on the oscillator at omega dt = 0.5 grows by (1 + 0.25)^(n/2):
    // the energy rule fires; a snapshot from before it has no verdict.
    World world(oscillator_model({1.0, 100.0, 0.0}, Vec3(1, 0, 0), Vec3::Zero()));
    WatchdogLimits limits;
    limits.energy_growth = 2.0;
    world.set_watchdog(limits);
    const World::Snapshot start = world.snapshot();
    for (int i = 0; i < 100 && !world.verdict().exploded(); ++i) {
        world.step({Integrator::forward_euler, 0.05, 1});
    }
    ASSERT_TRUE(world.verdict().exploded());
    world.restore(start);
    EXPECT_FALSE(world.verdict().exploded());
    EXPECT_EQ(world.frames(), 0u);
}

TEST(Rewind, PlasticRestLengthsAndRigidBodiesAreRewoundToo) {
    // A plastic lattice dented on the ground, and a rigid box falling beside it.
    ParticleModel model;
    LatticeDef cube;
    cube.nx = cube.ny = cube.nz = 3;
    cube.corner = Vec3(-0.3, 0.5, -0.3);
    cube.size = Vec3(0.6, 0.6, 0.6);
    cube.velocity = Vec3(0, -4, 0);
    cube.links.stiffness = 200.0;
    cube.plasticity = {0.02, 30.0, 0.5};
    add_lattice(model, cube);
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    model.collisions.colliders.push_back(PlaneCollider{});
    BodyDef box;
    box.position = Vec3(2, 1, 0);
    model.rigid.bodies.push_back(box);
    World world(model), straight(model);
    const StepSettings step{Integrator::symplectic_euler, 1.0 / 60.0, 10};
    for (int i = 0; i < 20; ++i) {
        world.step(step);
        straight.step(step);
    }
    const World::Snapshot saved = world.snapshot();
    EXPECT_FALSE(saved.plastic_rest.empty());
    EXPECT_EQ(saved.bodies.size(), 1u);
    for (int i = 0; i < 20; ++i) world.step(step);
    world.restore(saved);
    for (int i = 0; i < 20; ++i) {
        world.step(step);
        straight.step(step);
    }
    EXPECT_EQ(world.state().x.flat(), straight.state().x.flat());
    EXPECT_EQ(world.rigid()->hash(), straight.rigid()->hash());
    // A snapshot whose plastic rest lengths or bodies do not fit (one read
    // from an edited recording: these are not in the state hash) is refused
    // with an InputError, the world unchanged.
    for (int part = 0; part < 2; ++part) {
        World::Snapshot bad = world.snapshot();
        if (part == 0) bad.plastic_rest.pop_back();
        if (part == 1) bad.bodies.push_back(bad.bodies.front());
        bad.state.x.set(0, Vec3(9, 9, 9));
        const std::vector<double> before = world.state().x.flat();
        EXPECT_NE(error_of([&] { world.restore(bad); }).find("snapshot's arrays do not fit the world"),
                  std::string::npos);
        EXPECT_EQ(world.state().x.flat(), before) << "unchanged";
    }
}

// The viewer's mouse spring. Hanging from it under gravity, a particle
// settles where the spring holds its weight: m ω² d = m g, so the sag below
// the target is d = g / ω² whatever the mass (the spring scales by it). The
// spring acts as an implicit impulse before the integrator adds gravity; that
// splitting makes the discrete sag D g / ω² with D = 1 + 2ζωh + ω²h² (the
// fixed point of v1 = (v0 + ω²h (T - x0)) / D, v2 = v1 + g h = 0): first
// order in h, exact for the closed form as h -> 0.
TEST(Drag, AParticleHangsFromTheMouseSpringByGOverOmegaSquared) {
    for (double mass : {0.001, 1.0, 70.0}) {
        for (int substeps : {1, 100}) {
            ParticleModel model;
            model.particles.push_back(ParticleDef{Vec3(1, 2, 0), Vec3::Zero(), mass, false});
            model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
            World world(model);
            Drag drag;
            drag.index = 0;
            drag.target = Vec3(0, 3, 0);
            world.set_drag(drag);
            for (int i = 0; i < 600; ++i) world.step({Integrator::symplectic_euler, 1.0 / 60.0, substeps});
            const double w = 2.0 * std::numbers::pi * drag.frequency, h = 1.0 / 60.0 / substeps;
            const double closed_form = 9.81 / (w * w);  // m
            const double discrete = (1.0 + 2.0 * drag.damping_ratio * w * h + w * w * h * h) * closed_form;
            const double sag = drag.target.y() - world.state().x.get(0).y();
            EXPECT_NEAR(sag, discrete, 1e-9) << "m, mass " << mass << " kg, h = " << h << " s";
            if (substeps == 100) {
                EXPECT_NEAR(sag, closed_form, 2e-4) << "m (g/ω² = " << closed_form << " m)";
            }
            EXPECT_NEAR(world.state().x.get(0).x(), drag.target.x(), 1e-9) << "m";
            EXPECT_FALSE(world.verdict().exploded());
            world.set_drag(std::nullopt);  // let go: it falls
            world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
            EXPECT_LT(world.state().v.get(0).y(), -0.1) << "m/s";
        }
    }
}

// Implicit, so stable at any stiffness: 50 Hz at 1/30 s (ω h = 10) does not blow up.
TEST(Drag, StaysStableWhenTheSpringIsFarStifferThanTheStep) {
    ParticleModel model;
    model.particles.push_back(ParticleDef{Vec3(0, 0, 0), Vec3::Zero(), 1.0, false});
    World world(model);
    Drag drag;
    drag.target = Vec3(2, 0, 0);
    drag.frequency = 50.0;
    world.set_drag(drag);
    for (int i = 0; i < 30; ++i) world.step({Integrator::forward_euler, 1.0 / 30.0, 1});
    EXPECT_LT((world.state().x.get(0) - drag.target).norm(), 1e-3) << "m after 1 s";
}

TEST(Drag, ABodyHangsFromTheGrabbedPoint) {
    ParticleModel model;
    BodyDef ball;
    ball.shape = RigidShape::sphere;
    ball.size = Vec3(0.2, 0, 0);
    ball.mass = 5.0;
    ball.position = Vec3(0, 3, 0);
    model.rigid.bodies.push_back(ball);
    World world(model);
    Drag drag;
    drag.kind = Drag::Kind::body;
    drag.index = 0;
    drag.target = Vec3(0.5, 3.5, 0);  // the centre grabbed (anchor 0): no torque
    world.set_drag(drag);
    for (int i = 0; i < 600; ++i) world.step({Integrator::symplectic_euler, 1.0 / 60.0, 2});
    const double w = 2.0 * std::numbers::pi * drag.frequency;
    const Vec3 expected = drag.target - Vec3(0, 9.81 / (w * w), 0);
    EXPECT_LT((world.rigid()->state({0, 0}).position - expected).norm(), 1e-3) << "m after 10 s";
}

// What force arrows draw: a 2 kg bob hanging 1.5 m below a pinned point on a
// spring of rest 1 m and 100 N/m feels k (1.5 - 1) = 50 N up and m g = 19.62 N down.
TEST(NetForces, AreTheGeneratorsSumAtTheCurrentState) {
    ParticleModel model;
    model.particles.push_back(ParticleDef{Vec3(0, 3, 0), Vec3::Zero(), 1.0, true});
    model.particles.push_back(ParticleDef{Vec3(0, 1.5, 0), Vec3::Zero(), 2.0, false});
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    model.forces.push_back(Springs{{Spring{0, 1, 1.0, 100.0, 0.0}}, {}});
    const World world(model);
    const Vec3Array f = world.net_forces();
    EXPECT_NEAR(f.get(1).y(), 50.0 - 2.0 * 9.81, 1e-12) << "N";
    EXPECT_NEAR(f.get(1).x(), 0.0, 1e-12) << "N";
    EXPECT_DOUBLE_EQ(world.force_evaluations(), 0.0) << "drawing is not a force evaluation";
}

// A hard pull far away is energy put in by hand, not an explosion: the
// watchdog's E0 follows the drag's work; the stretch saturates at 1 m, so the
// speed stays about ω · 1 m (19 m/s at 3 Hz), not ω · 20 m.
TEST(Drag, AFarPullIsNotAnExplosionAndItsSpeedIsBounded) {
    ParticleModel model;
    model.particles.push_back(ParticleDef{Vec3(0, 1, 0), Vec3::Zero(), 1.0, false});
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    World world(model);
    WatchdogLimits limits;
    limits.energy_growth = 1.1;  // the energy rule on: 10% over E0 is an explosion
    world.set_watchdog(limits);
    Drag drag;
    drag.target = Vec3(20, 1, 0);
    world.set_drag(drag);
    double fastest = 0.0;  // m/s
    for (int i = 0; i < 240; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
        fastest = std::max(fastest, world.state().v.get(0).norm());
    }
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("drag");
    EXPECT_LT(fastest, 2.0 * std::numbers::pi * drag.frequency * 1.0) << "m/s";
    EXPECT_LT((world.state().x.get(0) - drag.target).norm(), 0.1)
        << "m: it got there in 4 s (the sag at 1/60 s is 4 cm, see above)";
}

TEST(Drag, RefusesWhatCannotBeGrabbed) {
    ParticleModel model;
    model.particles.push_back(ParticleDef{Vec3::Zero(), Vec3::Zero(), 1.0, true});
    model.particles.push_back(ParticleDef{Vec3::Zero(), Vec3::Zero(), 1.0, false});
    World world(model);
    Drag d;
    d.index = 0;
    EXPECT_EQ(error_of([&] { world.set_drag(d); }), "drag: particle 0 is pinned");
    d.index = 7;
    EXPECT_EQ(error_of([&] { world.set_drag(d); }), "drag: no particle 7 (the world has 2)");
    d.index = 1;
    d.frequency = -1.0;
    EXPECT_NE(error_of([&] { world.set_drag(d); }).find("frequency > 0 Hz"), std::string::npos);
    d.frequency = 3.0;
    d.kind = Drag::Kind::body;
    EXPECT_EQ(error_of([&] { world.set_drag(d); }), "drag: no rigid body 1");
    EXPECT_FALSE(world.drag().has_value());
}

TEST(Rigid, TheWatchdogWatchesBodiesToo) {
    ParticleModel model;
    BodyDef shot;
    shot.shape = RigidShape::sphere;
    shot.size = Vec3(0.1, 0, 0);
    shot.position = Vec3(0, 5, 0);
    shot.velocity = Vec3(300, 0, 0);  // m/s
    model.rigid.bodies.push_back(BodyDef{});
    model.rigid.bodies.push_back(shot);
    model.rigid.settings.ground = false;
    World world(model);
    world.set_watchdog({.max_speed = 100.0});
    world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    ASSERT_TRUE(world.verdict().exploded());
    EXPECT_EQ(world.verdict().subject, "body");
    EXPECT_EQ(world.verdict().index, 1u);
    EXPECT_EQ(world.verdict().quantity, "speed");
    const std::uint64_t hash = world.rigid()->hash();
    world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    EXPECT_EQ(world.rigid()->hash(), hash) << "no steps after an explosion";
}

TEST(Rigid, ParticlesLandOnARigidBodyAndDoNotPushIt) {
    // One-way coupling: grains poured on a heavy box resting on the ground
    // stop on its top face; the box does not feel them.
    ParticleModel model;
    for (int i = 0; i < 10; ++i) {
        ParticleDef p;
        p.position = Vec3(-0.3 + 0.06 * i, 2.0 + 0.1 * i, 0.02 * (i % 3));
        p.radius = 0.02;
        p.mass = 0.01;
        model.particles.push_back(p);
    }
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    BodyDef box;
    box.size = Vec3(1.0, 0.5, 1.0);
    box.position = Vec3(0, 0.25, 0);
    box.mass = 50.0;
    model.rigid.bodies.push_back(box);
    model.rigid.settings.sleep = false;
    ParticleModel box_only;
    box_only.rigid = model.rigid;
    World alone(box_only), world(model);
    for (int i = 0; i < 180; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
        alone.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
    }
    double lowest = 1e9;
    for (std::size_t i = 0; i < world.state().size(); ++i) lowest = std::min(lowest, world.state().x.get(i).y());
    EXPECT_NEAR(lowest, 0.52, 0.01) << "m: the grains rest on the top face (0.5 m) by their radius";
    EXPECT_EQ(world.rigid()->hash(), alone.rigid()->hash()) << "one way: the box moves as if they were not there";
}

TEST(Rewind, RefusesASnapshotOfAnotherModel) {
    World two(kepler_model(0.5));
    World one(ballistic_model());
    EXPECT_EQ(error_of([&] { one.restore(two.snapshot()); }), "snapshot has 2 particles, the world has 1");
}

TEST(Watchdog, AContainedExplosionFreezesItsRangeAndTheRunGoesOn) {
    // Particles 0-1: a stiff spring at ω dt = 16.7 (explodes within frames),
    // contained; particle 2 falls freely beside them and must not notice.
    ParticleModel model;
    model.particles.push_back({Vec3(0, 1, 0), Vec3::Zero(), 1.0, true});
    model.particles.push_back({Vec3(1.01, 1, 0), Vec3::Zero(), 1.0, false});
    model.particles.push_back({Vec3(3, 10, 0), Vec3::Zero(), 1.0, false});
    model.forces.push_back(Springs{{{0, 1, 1.0, 1e6, 0.0}}});
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    World world(std::move(model));
    WatchdogLimits limits;
    limits.contain.push_back({"stiff spring", 0, 2});
    world.set_watchdog(limits);
    for (int i = 0; i < 60; ++i) world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("contained");
    ASSERT_EQ(world.contained().size(), 1u);
    EXPECT_EQ(world.contained()[0].name, "stiff spring");
    EXPECT_EQ(world.contained()[0].verdict.index, 1u);
    EXPECT_TRUE(world.state().x.get(1).allFinite());
    EXPECT_EQ(world.state().v.get(1), Vec3::Zero()) << "frozen";
    EXPECT_EQ(world.state().inv_mass[1], 0.0);
    // The free particle fell as symplectic Euler says: y_n = y0 - g h² n(n+1)/2.
    const double h = 1.0 / 60.0;
    EXPECT_NEAR(world.state().x.get(2).y(), 10.0 - 9.81 * h * h * 60 * 61 / 2, 1e-9) << "m";

    // An explosion outside the contained range still stops the run.
    WatchdogLimits other;
    other.contain.push_back({"the falling one", 2, 1});
    World stopped(world.model());
    stopped.set_watchdog(other);
    for (int i = 0; i < 60 && !stopped.verdict().exploded(); ++i) stopped.step({Integrator::symplectic_euler, h, 1});
    EXPECT_TRUE(stopped.verdict().exploded());
    EXPECT_EQ(stopped.verdict().index, 1u);
}

// A contained range that starts outside the world box is frozen where it
// was, still outside: the watchdog once froze it again without end (issue 51,
// GBs of contained_ entries). Now the run stops at the first step, once contained.
TEST(Watchdog, ARangeFrozenOutsideTheBoxStopsTheRunInsteadOfLooping) {
    ParticleModel model;
    model.particles.push_back({Vec3(0, 51, 0), Vec3::Zero(), 1.0, false});
    model.particles.push_back({Vec3(0, 1, 0), Vec3::Zero(), 1.0, false});
    World world(std::move(model));
    WatchdogLimits limits;
    limits.world_half_extent = 50.0;
    limits.contain.push_back({"outside", 0, 1});
    world.set_watchdog(limits);
    world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    ASSERT_TRUE(world.verdict().exploded());
    EXPECT_EQ(world.verdict().quantity, "bounds");
    EXPECT_EQ(world.verdict().index, 0u);
    EXPECT_EQ(world.contained().size(), 1u) << "contained once, not again and again";
    EXPECT_EQ(world.state().x.get(0), Vec3(0, 51, 0)) << "frozen where it started";
}

INSTANTIATE_TEST_SUITE_P(Every, Rewind,
                         testing::ValuesIn(std::vector<Integrator>{
                             Integrator::forward_euler, Integrator::symplectic_euler, Integrator::leapfrog,
                             Integrator::velocity_verlet, Integrator::position_verlet, Integrator::rk4,
                             Integrator::backward_euler}),
                         [](const auto& info) { return std::string(integrator_info(info.param).name); });

}  // namespace
}  // namespace sim::test
