// Rigid-body and ragdoll speed (issue targets, figures in the notes):
//  - Pile/wrapper: 20 ragdolls (320 bodies, 300 joints) dropped in a
//    criss-cross pile, the ragdoll-pile scene's, through sim::RigidWorld with
//    its shipped settings:
//    ms per 1/60 s step over the first 2 s (the pile falls, lands and
//    tangles: every contact is live). Target <= 1.65 ms (5% of a 33 ms frame).
//  - Pile/raw_ode: the same bodies, joints, contacts and solver settings
//    written directly against ODE's C API, no wrapper.
//  - Pile/wrapper_plain: the wrapper asked for what raw_ode does (no
//    speculative stops, position iterations, gyroscopic RK4, sleep or
//    reduced coordinates): the
//    wrapper itself (ids, groups, parameters) should cost <= 10% over raw_ode.
//  - Pile/world: the same through sim::World, as a scene runs it (adds
//    the watchdog over every body).
//  - Pile/wrapper/1: one ragdoll (the pile's first) falling onto the ground:
//    target <= 0.1 ms.
//
// Each iteration builds a fresh world (not timed) and times 120 steps, so
// every iteration measures the same 2 s of the same simulation.
#include "bench_world.h"
#include "scenes/model/scene.h"
#include "sim/ragdoll.h"
#include "sim/rigid.h"
#include "sim/world.h"

#include <benchmark/benchmark.h>
#include <ode/ode.h>

#include <vector>

namespace {

constexpr double kDt = 1.0 / 60.0;  // s
constexpr int kSteps = 120;         // 2 s

// The first `count` ragdolls of the ragdoll-pile scene (5 crossed layers of 4).
sim::RigidModel pile(int count) {
    sim::RigidModel model = scenes::load_scene(scenes::resolve_scene("ragdoll-pile")).model.rigid;
    model.bodies.resize(static_cast<std::size_t>(count) * sim::kRagdollBones);
    model.joints.resize(static_cast<std::size_t>(count) * sim::kRagdollJoints);
    return model;
}

void time_steps(benchmark::State& state, const sim::RigidModel& model) {
    for (auto _ : state) {
        state.PauseTiming();
        sim::RigidWorld world(model);
        state.ResumeTiming();
        for (int i = 0; i < kSteps; ++i) world.step(kDt);
        benchmark::DoNotOptimize(world.hash());
    }
    state.counters["ms_per_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * kSteps * 1e-3,
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void Wrapper(benchmark::State& state) { time_steps(state, pile(static_cast<int>(state.range(0)))); }

// The wrapper asked for no more than raw_ode does: no speculative stops,
// position iterations, gyroscopic RK4, sleep or search for trees to step in
// reduced coordinates (a ragdoll has limits: never one). Against raw_ode: the
// wrapper's own cost; against wrapper: what those features cost.
void Plain(benchmark::State& state) {
    sim::RigidModel model = pile(static_cast<int>(state.range(0)));
    model.settings.speculative_stops = false;
    model.settings.position_iterations = 0;
    model.settings.gyroscopic_rk4 = false;
    model.settings.sleep = false;
    model.settings.articulated = false;
    time_steps(state, model);
}

void SceneWorld(benchmark::State& state) {
    sim::ParticleModel model;
    model.rigid = pile(static_cast<int>(state.range(0)));
    for (auto _ : state) {
        state.PauseTiming();
        sim::World world(model);
        state.ResumeTiming();
        for (int i = 0; i < kSteps; ++i) world.step({sim::Integrator::symplectic_euler, kDt, 1});
        benchmark::DoNotOptimize(world.rigid()->hash());
        if (!bench::still_running(state, world, kSteps, "ragdoll pile")) break;
    }
    state.counters["ms_per_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * kSteps * 1e-3,
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// --- the same, straight against ODE's C API -----------------------------------------

struct Raw {
    dWorldID world;
    dSpaceID space;
    dJointGroupID contacts;
    double mu, bounce, bounce_vel, contact_erp, contact_cfm;
};

void raw_near(void* data, dGeomID a, dGeomID b) {
    auto* r = static_cast<Raw*>(data);
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    // As the wrapper (RigidSettings::self_collision false): no contacts within one ragdoll.
    if (ba != nullptr && bb != nullptr && dBodyGetData(ba) == dBodyGetData(bb)) return;
    dContact c[4];
    const int n = dCollide(a, b, 4, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
        c[i].surface.mode =
            dContactBounce | dContactApprox1 | dContactSoftERP | dContactSoftCFM | dContactSlip1 | dContactSlip2;
        c[i].surface.slip1 = c[i].surface.slip2 = r->contact_cfm;
        c[i].surface.mu = r->mu;
        c[i].surface.bounce = r->bounce;
        c[i].surface.bounce_vel = r->bounce_vel;
        c[i].surface.soft_erp = r->contact_erp;
        c[i].surface.soft_cfm = r->contact_cfm;
        dJointAttach(dJointCreateContact(r->world, r->contacts, &c[i]), ba, bb);
    }
}

void RawOde(benchmark::State& state) {
    const sim::RigidModel model = pile(static_cast<int>(state.range(0)));
    const sim::RigidSettings& s = model.settings;
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    for (auto _ : state) {
        state.PauseTiming();
        Raw r{dWorldCreate(), dHashSpaceCreate(nullptr), dJointGroupCreate(0), s.friction,
              s.restitution,  s.bounce_velocity,         s.contact_erp,        s.contact_cfm};
        dWorldSetGravity(r.world, 0, -9.81, 0);
        dWorldSetERP(r.world, s.joint_erp);
        dWorldSetCFM(r.world, s.joint_cfm);
        dWorldSetQuickStepNumIterations(r.world, s.iterations);
        dCreatePlane(r.space, 0, 1, 0, 0);
        std::vector<dBodyID> bodies;
        for (const sim::BodyDef& b : model.bodies) {
            dMass m;
            dGeomID g = nullptr;
            switch (b.shape) {
                case sim::RigidShape::box:
                    dMassSetBox(&m, 1, b.size.x(), b.size.y(), b.size.z());
                    g = dCreateBox(r.space, b.size.x(), b.size.y(), b.size.z());
                    break;
                case sim::RigidShape::sphere:
                    dMassSetSphere(&m, 1, b.size.x());
                    g = dCreateSphere(r.space, b.size.x());
                    break;
                default:
                    dMassSetCapsule(&m, 1, 3, b.size.x(), b.size.y());
                    g = dCreateCapsule(r.space, b.size.x(), b.size.y());
                    break;
            }
            dMassAdjust(&m, b.mass);
            dBodyID body = dBodyCreate(r.world);
            dBodySetMass(body, &m);
            dGeomSetBody(g, body);
            dBodySetData(body, reinterpret_cast<void*>(bodies.size() / sim::kRagdollBones + 1));  // its ragdoll
            dBodySetPosition(body, b.position.x(), b.position.y(), b.position.z());
            const dQuaternion q = {b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()};
            dBodySetQuaternion(body, q);
            bodies.push_back(body);
        }
        for (const sim::RigidJoint& rj : model.joints) {
            const sim::JointDef& j = rj.joint;
            dBodyID a = bodies[static_cast<std::size_t>(rj.a)], b = bodies[static_cast<std::size_t>(rj.b)];
            const double lim[3][2] = {{j.lo, j.hi}, {j.lo2, j.hi2}, {j.lo3, j.hi3}};
            if (j.type == sim::JointType::ball) {
                dJointID ball = dJointCreateBall(r.world, nullptr);
                dJointAttach(ball, a, b);
                dJointSetBallAnchor(ball, j.anchor.x(), j.anchor.y(), j.anchor.z());
                dJointID m = dJointCreateAMotor(r.world, nullptr);
                dJointAttach(m, a, b);
                dJointSetAMotorMode(m, dAMotorEuler);
                dJointSetAMotorAxis(m, 0, 1, j.axis.x(), j.axis.y(), j.axis.z());
                dJointSetAMotorAxis(m, 2, 2, j.axis2.x(), j.axis2.y(), j.axis2.z());
                for (int k = 0; k < 3; ++k) {
                    dJointSetAMotorParam(m, dParamLoStop + k * dParamGroup, lim[k][0]);
                    dJointSetAMotorParam(m, dParamHiStop + k * dParamGroup, lim[k][1]);
                    dJointSetAMotorParam(m, dParamVel + k * dParamGroup, 0.0);
                    dJointSetAMotorParam(m, dParamFMax + k * dParamGroup, j.motor_max_force);
                }
            } else if (j.type == sim::JointType::hinge) {
                dJointID h = dJointCreateHinge(r.world, nullptr);
                dJointAttach(h, a, b);
                dJointSetHingeAnchor(h, j.anchor.x(), j.anchor.y(), j.anchor.z());
                dJointSetHingeAxis(h, j.axis.x(), j.axis.y(), j.axis.z());
                dJointSetHingeParam(h, dParamLoStop, j.lo);
                dJointSetHingeParam(h, dParamHiStop, j.hi);
                dJointSetHingeParam(h, dParamVel, 0.0);
                dJointSetHingeParam(h, dParamFMax, j.motor_max_force);
            } else {
                dJointID u = dJointCreateUniversal(r.world, nullptr);
                dJointAttach(u, a, b);
                dJointSetUniversalAnchor(u, j.anchor.x(), j.anchor.y(), j.anchor.z());
                dJointSetUniversalAxis1(u, j.axis.x(), j.axis.y(), j.axis.z());
                dJointSetUniversalAxis2(u, j.axis2.x(), j.axis2.y(), j.axis2.z());
                for (int k = 0; k < 2; ++k) {
                    dJointSetUniversalParam(u, dParamLoStop + k * dParamGroup, lim[k][0]);
                    dJointSetUniversalParam(u, dParamHiStop + k * dParamGroup, lim[k][1]);
                    dJointSetUniversalParam(u, dParamVel + k * dParamGroup, 0.0);
                    dJointSetUniversalParam(u, dParamFMax + k * dParamGroup, j.motor_max_force);
                }
            }
        }
        state.ResumeTiming();
        for (int i = 0; i < kSteps; ++i) {
            dRandSetSeed(static_cast<unsigned long>(i));
            dSpaceCollide(r.space, &r, &raw_near);
            dWorldQuickStep(r.world, kDt);
            dJointGroupEmpty(r.contacts);
        }
        benchmark::DoNotOptimize(dBodyGetPosition(bodies[0]));
        state.PauseTiming();
        dJointGroupDestroy(r.contacts);
        dSpaceDestroy(r.space);
        dWorldDestroy(r.world);
        state.ResumeTiming();
    }
    dCloseODE();
    state.counters["ms_per_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * kSteps * 1e-3,
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(Wrapper)->Name("Pile/wrapper")->Arg(20)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(Plain)->Name("Pile/wrapper_plain")->Arg(20)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(RawOde)->Name("Pile/raw_ode")->Arg(20)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(SceneWorld)->Name("Pile/world")->Arg(20)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
