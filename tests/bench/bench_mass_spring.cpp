// Mass-spring and particle-effect speed (issue targets, figures in the notes):
//  - Cloth64: a 64 x 64 cloth (structural, shear and bend springs: 23938)
//    stepped by symplectic Euler, one step per iteration: target <= 0.25 ms.
//  - BulletCloth64: the same cloth (the same 23938 links) as Bullet's
//    btSoftBody (a peer, linked only here) with 1 solver iteration: ours
//    should make >= 5x its steps/s.
//  - Cloth64Xpbd: the same cloth with XPBD constraints, 1 iteration.
//  - SpringPass64/0 and /1: the cloth's spring forces alone (the fast pass of
//    sim/spring.h, after 200 steps of motion), the pinned (SSE) build and the
//    AVX2 build the step uses where the CPU has it.
//  - Fountain10k: 10,000 droplets with ground and particle collisions, one
//    1/60 s frame (one step, as the fountain scene) after 4 s of warm-up:
//    target <= 1.65 ms, the lecture's 5% of a 33 ms frame.
#include "bench_world.h"
#include "sim/cpu.h"
#include "sim/mass_spring.h"
#include "sim/world.h"

#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

namespace {

constexpr int kSide = 64;      // nodes per side
constexpr double kSize = 2.0;  // m
constexpr double kMass = 1.0;  // kg
constexpr double kDt = 5e-4;   // s: ω dt = 0.4 with the stiffness below, stable for any number of steps

sim::ParticleModel cloth(sim::LinkSettings::Kind kind) {
    sim::ParticleModel model;
    sim::ClothDef def;
    def.nx = def.ny = kSide;
    def.corner = sim::Vec3(-1, 2, 0);
    def.u = sim::Vec3(kSize, 0, 0);
    def.v = sim::Vec3(0, 0, kSize);
    def.mass = kMass;
    def.pins = sim::ClothDef::Pins::corners;
    def.links.kind = kind;
    // 0.24 g nodes on 20 N/m links (shear and bend at 0.5 and 0.1 of it):
    // ω ~ sqrt(6.4 k / m) = 730 rad/s.
    def.links.stiffness = 20.0;  // N/m
    def.links.damping = 0.001;   // N·s/m
    def.links.tethers = false;   // the plain algorithm, as Bullet runs it
    sim::add_cloth(model, def);
    model.forces.push_back(sim::UniformGravity{sim::Vec3(0, -9.81, 0)});
    return model;
}

void Cloth64(benchmark::State& state) {
    sim::World world(cloth(sim::LinkSettings::Kind::springs));
    std::size_t springs = 0;
    for (const auto& f : world.model().forces) {
        if (const auto* s = std::get_if<sim::Springs>(&f)) springs += s->list.size();
    }
    for (auto _ : state) {
        world.step({sim::Integrator::symplectic_euler, kDt, 1});
        benchmark::DoNotOptimize(world.state().x.span().c[0]);
    }
    if (!bench::still_running(state, world, state.iterations(), "cloth64")) return;
    state.counters["springs"] = static_cast<double>(springs);
    state.counters["steps_per_s"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(Cloth64)->Unit(benchmark::kMillisecond);

void SpringPass64(benchmark::State& state) {
    const bool wide = state.range(0) != 0;
    if (wide && !sim::avx2_available()) {
        state.SkipWithError("this CPU has no AVX2");
        return;
    }
    sim::World world(cloth(sim::LinkSettings::Kind::springs));
    for (int i = 0; i < 200; ++i) world.step({sim::Integrator::symplectic_euler, kDt, 1});
    if (!bench::still_running(state, world, 200, "cloth64")) return;  // the pass below times this state
    const sim::Springs* springs = nullptr;
    for (const auto& f : world.model().forces) {
        if (const auto* s = std::get_if<sim::Springs>(&f)) springs = s;
    }
    const sim::ParticleState& now = world.state();
    sim::SpringPlan plan = sim::plan_springs(*springs, now.size());
    plan.wide = wide;
    sim::Vec3Array f(now.size());
    const sim::ForceInput in{0.0, 0, now.x.span(), now.v.span(), now.mass.data(), now.inv_mass.data()};
    for (auto _ : state) {
        sim::accumulate(*springs, plan, in, f.span());
        benchmark::DoNotOptimize(f.span().c[0]);
    }
    state.SetLabel(wide ? "AVX2" : "pinned x86-64-v2");
}
BENCHMARK(SpringPass64)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void Cloth64Xpbd(benchmark::State& state) {
    sim::World world(cloth(sim::LinkSettings::Kind::constraints));
    for (auto _ : state) {
        world.step({sim::Integrator::symplectic_euler, kDt, 1});
        benchmark::DoNotOptimize(world.state().x.span().c[0]);
    }
    if (!bench::still_running(state, world, state.iterations(), "cloth64 (XPBD)")) return;
    state.counters["steps_per_s"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(Cloth64Xpbd)->Unit(benchmark::kMillisecond);

void BulletCloth64(benchmark::State& state) {
    btSoftBodyRigidBodyCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDefaultSoftBodySolver soft_solver;
    btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &config, &soft_solver);
    world.setGravity(btVector3(0, -9.81, 0));
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = btVector3(0, -9.81, 0);
    info.m_sparsesdf.Initialize();
    const btScalar h = 2.0;
    // Corners (x, z) at y = 2; fixed = 1 + 2: the two corners of the first
    // side, as ours. The structural links come with the patch; the shear and
    // bend links are added one by one, so the two cloths have the same 23938
    // links (Bullet's generateBendingConstraints(2) would add 43k).
    btSoftBody* body =
        btSoftBodyHelpers::CreatePatch(info, btVector3(-1, h, 0), btVector3(1, h, 0), btVector3(-1, h, 2),
                                       btVector3(1, h, 2), kSide, kSide, 1 + 2, false);
    auto node = [](int i, int j) { return j * kSide + i; };
    for (int j = 0; j + 1 < kSide; ++j) {
        for (int i = 0; i + 1 < kSide; ++i) {
            body->appendLink(node(i, j), node(i + 1, j + 1));
            body->appendLink(node(i + 1, j), node(i, j + 1));
        }
    }
    for (int j = 0; j < kSide; ++j) {
        for (int i = 0; i < kSide; ++i) {
            if (i + 2 < kSide) body->appendLink(node(i, j), node(i + 2, j));
            if (j + 2 < kSide) body->appendLink(node(i, j), node(i, j + 2));
        }
    }
    body->m_cfg.piterations = 1;  // 1 solver iteration
    body->setTotalMass(kMass);
    world.addSoftBody(body);
    for (auto _ : state) {
        world.stepSimulation(kDt, 0);  // maxSubSteps 0: exactly one step of kDt
        benchmark::DoNotOptimize(body->m_nodes[0].m_x);
    }
    state.counters["links"] = static_cast<double>(body->m_links.size());
    state.counters["steps_per_s"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    world.removeSoftBody(body);
    delete body;
}
BENCHMARK(BulletCloth64)->Unit(benchmark::kMillisecond);

void Fountain10k(benchmark::State& state) {
    sim::ParticleModel model;
    sim::Emitter e;
    e.count = 10'000;
    e.position = sim::Vec3(0, 0.3, 0);
    e.cone = 12.0;
    e.speed = 6.5;
    e.speed_jitter = 0.15;
    e.rate = 2500.0;  // each droplet lives 4 s
    e.seed = 7;
    for (std::uint32_t k = 0; k < e.count; ++k) {
        sim::ParticleDef p;
        p.position = sim::parked_position(e);
        p.mass = 0.001;
        p.radius = 0.025;
        p.pinned = true;
        model.particles.push_back(p);
    }
    model.emitters.push_back(e);
    model.forces.push_back(sim::UniformGravity{sim::Vec3(0, -9.81, 0)});
    model.collisions.colliders.push_back(sim::PlaneCollider{});
    model.collisions.particle_particle = true;
    model.collisions.restitution = 0.3;
    model.collisions.friction = 0.2;
    sim::World world(std::move(model));
    const sim::StepSettings frame{sim::Integrator::symplectic_euler, 1.0 / 60.0, 1};
    constexpr int kWarmUp = 240;  // 4 s: every droplet born, a pool on the ground
    for (int i = 0; i < kWarmUp; ++i) world.step(frame);
    for (auto _ : state) {
        world.step(frame);
        benchmark::DoNotOptimize(world.state().x.span().c[0]);
    }
    if (!bench::still_running(state, world, kWarmUp + state.iterations(), "fountain10k")) return;
    state.counters["contacts"] = static_cast<double>(world.contacts());
}
BENCHMARK(Fountain10k)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
