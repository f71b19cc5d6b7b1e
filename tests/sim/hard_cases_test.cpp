// The hard cases of mass-spring systems (ctest label `stability`), each with
// an automatic oracle that prints what it measured:
//  - a stiff spring far past symplectic Euler's limit ω dt < 2 explodes and
//    the watchdog names the frame; backward Euler and XPBD stay bounded;
//  - a heavy ball on a light chain (1000:1) keeps the chain's length with XPBD;
//  - a 32 x 32 cloth at 1/30 s without substeps keeps its edges;
//  - a particle at 200 m/s never gets behind a 1 cm wall;
//  - degenerate inputs (zero-length spring, coincident particles, a fully
//    pinned cloth) give no NaN;
//  - a 200-segment rope hanging for 10 s comes to rest without drifting.
#include "sim/mass_spring.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace sim::test {
namespace {

// The measured value of an oracle, printed beside the verdict.
void report(const char* what, double value, const char* unit) {
    std::printf("[ measured ] %s: %.6g %s\n", what, value, unit);
}

// A 1 kg bob on a spring (or a compliant constraint) of k = 1e6 N/m to a
// pinned anchor, released 1 cm stretched: ω = 1000 rad/s, ω dt = 16.7 at 1/60 s.
constexpr double kStiff = 1e6;  // N/m
ParticleModel stiff(bool constraint) {
    ParticleModel model;
    model.particles.push_back({Vec3(0, 0, 0), Vec3::Zero(), 1.0, true});
    model.particles.push_back({Vec3(1.01, 0, 0), Vec3::Zero(), 1.0, false});
    if (constraint) {
        model.constraints.distance.push_back({0, 1, 1.0, 1.0 / kStiff});
    } else {
        model.forces.push_back(Springs{{{0, 1, 1.0, kStiff, 0.0}}});
    }
    return model;
}

WatchdogLimits energy_watch() {
    WatchdogLimits limits;
    limits.energy_growth = 1.5;
    return limits;
}

TEST(StiffSpring, SymplecticEulerExplodesAndTheWatchdogNamesTheFrame) {
    World world(stiff(false));
    world.set_watchdog(energy_watch());
    const double omega_dt = std::sqrt(kStiff / 1.0) / 60.0;
    for (int i = 0; i < 600 && !world.verdict().exploded(); ++i)
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
    ASSERT_TRUE(world.verdict().exploded()) << "ω dt = " << omega_dt << " is far past 2";
    report("symplectic Euler, ω dt = 16.7: exploded at frame", static_cast<double>(world.verdict().frame), "");
    std::printf("[ measured ] %s\n", world.verdict().message("stiff-spring").c_str());
    EXPECT_LE(world.verdict().frame, 3u) << "the amplification per step is about (ω dt)² = 278";
}

TEST(StiffSpring, BackwardEulerStaysBounded) {
    World world(stiff(false));
    world.set_watchdog(energy_watch());
    const double e0 = world.energy();
    double e_max = e0;
    for (int i = 0; i < 600; ++i) {
        world.step({Integrator::backward_euler, 1.0 / 60.0, 1});
        e_max = std::max(e_max, world.energy());
    }
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("stiff-spring");
    report("backward Euler, max E / E0", e_max / e0, "");
    EXPECT_LE(e_max, e0 * (1 + 1e-12)) << "J: backward Euler only dissipates";
}

TEST(StiffSpring, XpbdStaysBounded) {
    World world(stiff(true));
    world.set_watchdog(energy_watch());
    const double e0 = world.energy();
    double e_max = e0;
    for (int i = 0; i < 600; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
        e_max = std::max(e_max, world.energy());
    }
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("stiff-spring");
    report("XPBD, max E / E0", e_max / e0, "");
    EXPECT_LE(e_max, e0 * (1 + 1e-9)) << "J";
}

TEST(HeavyBallOnALightChain, XpbdKeepsTheLengthAtAMassRatioOf1000) {
    // A 10-link, 1 m chain of 1 g nodes pinned at the top, a 1 kg ball at the
    // end (1000:1), released horizontal: after 5 s the chain is within 1% of
    // its length and the energy has not grown.
    ParticleModel model;
    RopeDef rope;
    rope.start = Vec3(0, 2, 0);
    rope.end = Vec3(1, 2, 0);
    rope.segments = 10;
    rope.mass = 0.011;  // kg: 11 nodes of 1 g
    rope.links.kind = LinkSettings::Kind::constraints;
    const BodyRange chain = add_rope(model, rope);
    model.particles.back().mass = 1.0;  // the ball
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    World world(std::move(model));
    const double e0 = world.energy();
    double e_max = e0, worst = 0.0;
    for (int i = 0; i < 300; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 20});
        e_max = std::max(e_max, world.energy());
        worst = std::max(worst, max_link_strain(world.model(), chain, world.state().x.span()));
    }
    const double length = [&] {
        double l = 0;
        for (int i = 0; i + 1 < chain.nx; ++i)
            l += (world.state().x.get(chain.at(i + 1)) - world.state().x.get(chain.at(i))).norm();
        return l;
    }();
    report("chain length error after 5 s", std::abs(length - 1.0) * 100, "%");
    report("largest link strain over 5 s", worst * 100, "%");
    report("max E - E0 over 5 s", e_max - e0, "J");
    EXPECT_LE(std::abs(length - 1.0), 0.01) << "m, 1% of 1 m";
    EXPECT_LE(e_max - e0, 1e-6 * std::abs(e0) + 1e-9) << "J: no energy gain";
}

TEST(Cloth, ThirtyTwoSquaredAtOneThirtiethWithoutSubstepsKeepsItsEdges) {
    ParticleModel model;
    ClothDef cloth;
    cloth.nx = cloth.ny = 32;
    cloth.corner = Vec3(-1, 3, 0);
    cloth.u = Vec3(2, 0, 0);
    cloth.v = Vec3(0, 0, 2);  // horizontal, pinned along one side: it swings down
    cloth.pins = ClothDef::Pins::corners;
    cloth.links.kind = LinkSettings::Kind::constraints;
    const BodyRange body = add_cloth(model, cloth);
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    model.constraints.iterations = 10;
    World world(std::move(model));
    double worst = 0.0;
    for (int i = 0; i < 150; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 30.0, 1});
        ASSERT_FALSE(world.verdict().exploded()) << world.verdict().message("cloth");
        worst = std::max(worst, max_link_strain(world.model(), body, world.state().x.span()));
    }
    report("cloth 32x32, dt 1/30 s, no substeps: max edge strain over 5 s", worst * 100, "%");
    EXPECT_LE(worst, 0.10);
}

TEST(Degenerate, ZeroLengthSpringsCoincidentParticlesAndAFullyPinnedClothGiveNoNaN) {
    ParticleModel model;
    model.particles.push_back({Vec3(0, 1, 0), Vec3::Zero(), 1.0, false});
    model.particles.push_back({Vec3(0, 1, 0), Vec3::Zero(), 1.0, false});  // coincident
    model.forces.push_back(Springs{{{0, 1, 0.0, 100.0, 1.0}, {0, 1, 0.5, 100.0, 1.0}}});
    model.constraints.distance.push_back({0, 1, 0.3, 0.0});
    ClothDef cloth;
    cloth.nx = cloth.ny = 4;
    cloth.pins = ClothDef::Pins::all;
    cloth.links.kind = LinkSettings::Kind::constraints;
    add_cloth(model, cloth);
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    for (Integrator integrator : {Integrator::symplectic_euler, Integrator::rk4, Integrator::backward_euler}) {
        World world(model);
        for (int i = 0; i < 120; ++i) world.step({integrator, 1.0 / 60.0, 2});
        EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message(integrator_info(integrator).name);
        for (std::size_t i = 0; i < world.state().size(); ++i) {
            ASSERT_TRUE(world.state().x.get(i).allFinite() && world.state().v.get(i).allFinite()) << "particle " << i;
        }
    }
}

TEST(LongRope, TwoHundredSegmentsHangingForTenSecondsComeToRestWithoutDrift) {
    ParticleModel model;
    RopeDef rope;
    rope.start = Vec3(0, 5, 0);
    rope.end = Vec3(4, 5, 0);
    rope.segments = 200;
    rope.mass = 2.0;
    rope.links.kind = LinkSettings::Kind::constraints;
    const BodyRange body = add_rope(model, rope);
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    // N·s/m per node: c/m = 3 /s, about twice the swing's lowest frequency
    // (1.2 sqrt(g / L) = 1.9 rad/s for a 4 m chain): near critical damping,
    // so the swing dies out instead of creeping (more drag is overdamped and
    // creeps for longer, less keeps swinging).
    model.forces.push_back(LinearDrag{0.03});
    World world(std::move(model));
    Vec3 end_at_9s = Vec3::Zero();
    for (int i = 0; i < 600; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 10});
        if (i == 539) end_at_9s = world.state().x.get(body.at(body.nx - 1));
    }
    double fastest = 0.0;
    for (std::size_t i = 0; i < world.state().size(); ++i) fastest = std::max(fastest, world.state().v.get(i).norm());
    const double drift = (world.state().x.get(body.at(body.nx - 1)) - end_at_9s).norm();
    report("200-segment rope after 10 s: fastest node", fastest, "m/s");
    report("200-segment rope: end moved over the last second", drift * 1000, "mm");
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("rope");
    EXPECT_LE(fastest, 0.001) << "m/s";
    EXPECT_LE(drift, 0.001) << "m";
    EXPECT_NEAR(world.state().x.get(body.at(body.nx - 1)).x(), 0.0, 0.05) << "m: hangs under its pin";
}

}  // namespace
}  // namespace sim::test
