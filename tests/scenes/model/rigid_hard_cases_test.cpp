// The hard cases of rigid bodies and ragdolls (ctest label `stability`), each
// an automatic oracle that prints what it measured. The scenes are the
// shipped ones, loaded as every other consumer loads them:
//  - a ragdoll thrown at 30 m/s into the ground holds together (joint
//    separation <= 1 cm after 1 s; a few frames of worse are tolerated if it
//    recovers, the lecture says);
//  - twenty ragdolls in a pile are all asleep by frame 300 (5 s) and stay
//    asleep to the scene's last frame, with no NaN, and a second run in the
//    same process gives the same hash;
//  - a 200 kg ball on a chain of 2 kg links (100:1) keeps its joints within
//    a bound and gains no energy;
//  - a free spinning T-handle keeps its angular momentum over 10 s.
#include "scenes/model/scene.h"
#include "sim/ragdoll.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace scenes {
namespace {

void report(const char* what, double value, const char* unit) {
    std::printf("[ measured ] %s: %.6g %s\n", what, value, unit);
}

// The largest joint separation of a world built from a model, m: model joint
// k is the world's joint {k, 0}.
double max_separation(const sim::RigidWorld& rigid, std::size_t joints) {
    double worst = 0.0;
    for (std::uint32_t k = 0; k < joints; ++k) worst = std::max(worst, rigid.joint_separation({k, 0}));
    return worst;
}

TEST(RigidHardCases, ARagdollThrownAt30MetresPerSecondIntoTheGroundHoldsTogether) {
    // The ragdoll scene's solver and step, shipped settings; no sleep, so the
    // ragdoll is judged on its own motion.
    const SceneDef scene = load_scene(resolve_scene("ragdoll"));
    sim::RigidSettings settings = scene.model.rigid.settings;
    settings.sleep = false;
    sim::RigidWorld world(settings);
    sim::RagdollDef def;
    def.position = sim::Vec3(0, 1.5, 0);
    def.velocity = sim::Vec3(18, -24, 0);  // 30 m/s, 53 degrees down into the ground
    def.angular_velocity = sim::Vec3(0, 0, -3);
    const sim::Ragdoll doll = sim::create_ragdoll(world, def);
    auto separation = [&] {
        double worst = 0.0;
        for (const sim::JointId j : doll.joints) worst = std::max(worst, world.joint_separation(j));
        return worst;
    };
    const double h = scene.step.dt / scene.step.substeps;  // s
    const int per_second = static_cast<int>(std::lround(1.0 / h));
    double impact = 0.0, at_1s = 0.0;
    int bad_frames = 0;  // steps in the second after 1 s with a joint over 1 cm apart
    for (int i = 1; i <= 3 * per_second; ++i) {
        world.step(h);
        for (const sim::BodyId b : doll.bodies) ASSERT_TRUE(world.state(b).position.allFinite()) << "step " << i;
        const double s = separation();
        if (i < per_second) impact = std::max(impact, s);
        if (i == per_second) at_1s = s;
        if (i > per_second && i <= 2 * per_second && s > 0.01) ++bad_frames;
    }
    report("largest joint separation in the first second (the impact)", impact, "m");
    report("largest joint separation at 1 s", at_1s, "m");
    report("steps over 1 cm in the second after", bad_frames, "of 120");
    report("largest joint separation at 3 s", separation(), "m");
    EXPECT_LE(at_1s, 0.01) << "m, at 1 s";
    EXPECT_LE(bad_frames, per_second / 10) << "a few frames of inconsistency, then it recovers";
    EXPECT_LE(separation(), 0.002) << "m, at 3 s: recovered";
    for (const sim::BodyId b : doll.bodies) {
        EXPECT_GT(world.state(b).position.y(), -0.05)
            << "m: " << sim::name(static_cast<sim::RagdollBone>(b.index)) << " is not under the ground";
    }
}

// Runs a shipped scene's whole length; returns the final rigid hash.
struct PileRun {
    std::uint64_t hash = 0;
    std::size_t awake = 0;
    int asleep_from = -1;  // first frame with every body asleep
    bool exploded = false;
};
PileRun run_pile(const SceneDef& scene) {
    sim::World world(scene.model);
    world.set_watchdog(scene.watchdog);
    PileRun out;
    for (int f = 0; f < scene.frames; ++f) {
        world.step(scene.step);
        if (out.asleep_from < 0 && world.rigid()->awake_count() == 0) out.asleep_from = f + 1;
    }
    out.hash = world.rigid()->hash();
    out.awake = world.rigid()->awake_count();
    out.exploded = world.verdict().exploded();
    return out;
}

TEST(RigidHardCases, TwentyRagdollsInAPileFallAsleepTheSameWayTwice) {
    const SceneDef scene = load_scene(resolve_scene("ragdoll-pile"));
    ASSERT_EQ(scene.model.rigid.bodies.size(), 20u * sim::kRagdollBones);
    const PileRun first = run_pile(scene);
    const PileRun second = run_pile(scene);
    report("frame from which every body is asleep", first.asleep_from, "(of the scene's 480)");
    EXPECT_FALSE(first.exploded) << "no NaN, no speed or bounds violation";
    EXPECT_GT(first.asleep_from, 0) << "every body asleep at some frame";
    EXPECT_LE(first.asleep_from, 300) << "frames: every body asleep by 5 s";
    EXPECT_EQ(first.awake, 0u) << "bodies awake again at the scene's last frame (8 s)";
    EXPECT_EQ(first.hash, second.hash) << "the same scene twice in one process";
    EXPECT_EQ(first.asleep_from, second.asleep_from);
}

TEST(RigidHardCases, AHeavyBallOnALightChainStaysJointedAndGainsNoEnergy) {
    SceneDef scene = load_scene(resolve_scene("wrecking-ball"));
    // The chain alone, no wall: energy is then conserved but for the solver.
    // The bricks go (no joint names them); the joints' body indices follow.
    sim::RigidModel& m = scene.model.rigid;
    std::vector<int> kept(m.bodies.size(), -1);  // old index -> new, -1 for a brick
    std::vector<sim::BodyDef> chain;
    for (std::size_t k = 0; k < m.bodies.size(); ++k) {
        if (scene.body_names[k].starts_with("brick")) continue;
        kept[k] = static_cast<int>(chain.size());
        chain.push_back(m.bodies[k]);
    }
    m.bodies = chain;
    for (sim::RigidJoint& j : m.joints) {
        j.a = kept[static_cast<std::size_t>(j.a)];
        if (j.b >= 0) j.b = kept[static_cast<std::size_t>(j.b)];
    }
    ASSERT_EQ(m.bodies.size(), 9u) << "8 links and the ball";
    const sim::RigidJoint& hook = m.joints.back();  // the last link and the ball
    ASSERT_DOUBLE_EQ(m.bodies[static_cast<std::size_t>(hook.b)].mass / m.bodies[static_cast<std::size_t>(hook.a)].mass,
                     100.0);
    sim::World world(scene.model);
    const std::size_t joints = scene.model.rigid.joints.size();
    const double e0 = world.energy();
    double worst = 0.0, e_max_first = e0, e_max_last = e0;  // J, over each half of the run
    for (int f = 0; f < scene.frames; ++f) {
        world.step(scene.step);
        worst = std::max(worst, max_separation(*world.rigid(), joints));
        double& e_max = 2 * f < scene.frames ? e_max_first : e_max_last;
        e_max = std::max(e_max, world.energy());
    }
    report("largest joint separation over 5 s", worst, "m");
    report("largest energy gain over 5 s", (std::max(e_max_first, e_max_last) - e0) / e0, "(of E0)");
    EXPECT_LE(worst, 0.005) << "m: the 100:1 chain does not stretch";
    // Unsoftened joints (joint_cfm 0) keep the swing's energy: it oscillates
    // by about ω h / 2 (0.2 % here, symplectic Euler's bounded error), no more,
    // and the oscillation does not grow.
    EXPECT_LE(std::max(e_max_first, e_max_last), e0 * (1.0 + 3e-3)) << "J: no energy gain past the oscillation";
    EXPECT_LE(e_max_last, e_max_first + 1e-4 * e0) << "J: the second half's peak over the first's: no growth";
}

TEST(RigidHardCases, AFreeSpinningBodyKeepsItsAngularMomentum) {
    const SceneDef scene = load_scene(resolve_scene("inertia"));
    sim::World world(scene.model);
    const sim::RigidWorld& rigid = *world.rigid();
    auto momentum = [&](std::uint32_t k) {
        const sim::BodyState s = rigid.state({k, 0});
        const Eigen::Matrix3d R = s.orientation.toRotationMatrix();
        return sim::Vec3(R * rigid.inertia({k, 0}) * R.transpose() * s.angular_velocity);
    };
    std::vector<sim::Vec3> L0;
    for (std::uint32_t k = 0; k < 3; ++k) L0.push_back(momentum(k));
    const double e0 = world.energy();
    double drift = 0.0;
    bool flipped = false;  // the intermediate axis turns over
    for (int f = 0; f < scene.frames; ++f) {
        world.step(scene.step);
        for (std::uint32_t k = 0; k < 3; ++k) drift = std::max(drift, (momentum(k) - L0[k]).norm() / L0[k].norm());
        const Eigen::Matrix3d R = rigid.state({1, 0}).orientation.toRotationMatrix();
        flipped = flipped || (R * sim::Vec3::UnitX()).x() < -0.9;
    }
    report("largest relative angular momentum drift over 10 s", drift, "");
    report("energy drift over 10 s", (world.energy() - e0) / e0, "(of E0)");
    EXPECT_LE(drift, 0.02) << "|L - L0| / |L0|";
    EXPECT_NEAR(world.energy(), e0, 1e-4 * e0) << "J: a free spin keeps its energy";
    EXPECT_TRUE(flipped) << "the T-handle spun about its intermediate axis turns over";
}

}  // namespace
}  // namespace scenes
