// The ragdoll builder: its bodies and joints, masses against the fractions it
// was given, joints that start exactly together, the heavy-part warning,
// refused input, create and destroy, and a fall that keeps the knees and
// elbows within their limits and ends asleep.
#include "sim/ragdoll.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace sim::test {
namespace {

TEST(Ragdoll, SixteenBodiesWhoseMassesAreTheFractionsOfTheWhole) {
    RigidWorld world;
    RagdollDef def;
    def.mass = 80.0;
    const Ragdoll doll = create_ragdoll(world, def);
    EXPECT_EQ(world.body_count(), kRagdollBones);
    EXPECT_TRUE(doll.warnings.empty()) << "Winter's fractions have no jointed pair over 10:1";
    const double fraction_sum = std::accumulate(def.mass_fractions.begin(), def.mass_fractions.end(), 0.0);
    double total = 0.0;
    for (std::size_t k = 0; k < kRagdollBones; ++k) {
        const double m = world.mass(doll.bodies[k]);
        EXPECT_NEAR(m, def.mass * def.mass_fractions[k] / fraction_sum, 1e-9)
            << "kg, " << name(static_cast<RagdollBone>(k));
        total += m;
    }
    EXPECT_NEAR(total, 80.0, 1e-9) << "kg";
    for (const JointId j : doll.joints) EXPECT_LT(world.joint_separation(j), 1e-12) << "m: made together";
    // Standing: the head above the chest above the pelvis, the feet lowest.
    const double head = world.state(doll.body(RagdollBone::head)).position.y();
    const double chest = world.state(doll.body(RagdollBone::chest)).position.y();
    const double pelvis = world.state(doll.body(RagdollBone::pelvis)).position.y();
    const double foot = world.state(doll.body(RagdollBone::foot_left)).position.y();
    EXPECT_GT(head, chest);
    EXPECT_GT(chest, pelvis);
    EXPECT_GT(pelvis, foot);
    EXPECT_NEAR(head - foot, 0.88 * def.height, 0.05 * def.height) << "m: head centre to foot centre";
}

TEST(Ragdoll, AHeavyHeadOnALightChestWarns) {
    RagdollDef def;
    def.mass_fractions[static_cast<std::size_t>(RagdollBone::head)] = 2.5;  // a diving helmet
    const RagdollParts parts = ragdoll_parts(def);
    ASSERT_EQ(parts.warnings.size(), 1u);
    EXPECT_NE(parts.warnings[0].find("head"), std::string::npos) << parts.warnings[0];
    EXPECT_NE(parts.warnings[0].find("chest"), std::string::npos) << parts.warnings[0];
    EXPECT_NE(parts.warnings[0].find("> 10:1"), std::string::npos) << parts.warnings[0];
}

TEST(Ragdoll, BadInputIsRefusedByName) {
    RigidWorld world;
    auto error_of = [&](const RagdollDef& def) -> std::string {
        try {
            create_ragdoll(world, def);
        } catch (const InputError& e) {
            return e.what();
        }
        return "accepted";
    };
    RagdollDef def;
    def.height = -1.8;
    EXPECT_NE(error_of(def).find("ragdoll.height"), std::string::npos) << error_of(def);
    def = {};
    def.mass = 0.0;
    EXPECT_NE(error_of(def).find("ragdoll.mass"), std::string::npos);
    def = {};
    def.joint_friction = -1.0;
    EXPECT_NE(error_of(def).find("ragdoll.joint_friction"), std::string::npos);
    def = {};
    def.orientation = Eigen::Quaterniond(2, 0, 0, 0);
    EXPECT_NE(error_of(def).find("unit quaternion"), std::string::npos);
    def = {};
    def.mass_fractions[3] = 0.0;
    EXPECT_NE(error_of(def).find("mass_fractions[head]"), std::string::npos) << error_of(def);
    EXPECT_EQ(world.body_count(), 0u) << "nothing half-built";
}

TEST(Ragdoll, DestroyRemovesEveryBodyAndJoint) {
    RigidWorld world;
    const Ragdoll a = create_ragdoll(world, {});
    RagdollDef second;
    second.position = Vec3(2, 1, 0);
    const Ragdoll b = create_ragdoll(world, second);
    EXPECT_EQ(world.body_count(), 2 * kRagdollBones);
    destroy_ragdoll(world, a);
    EXPECT_EQ(world.body_count(), kRagdollBones);
    for (const BodyId id : a.bodies) EXPECT_FALSE(world.alive(id));
    EXPECT_THROW(world.state(a.body(RagdollBone::head)), InputError) << "a stale id is refused";
    for (int i = 0; i < 30; ++i) world.step(1.0 / 60.0);  // the other one still steps
    EXPECT_TRUE(world.state(b.body(RagdollBone::head)).position.allFinite());
}

TEST(Ragdoll, AFallKeepsKneesAndElbowsWithinTheirLimitsAndEndsAsleep) {
    RigidWorld world({.iterations = 40});
    RagdollDef def;
    def.position = Vec3(0, 2.0, 0);
    def.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(1.2, Vec3(1, 0, 0.3).normalized()));
    def.velocity = Vec3(1.0, 0.0, -0.5);
    def.angular_velocity = Vec3(2.0, 0.0, 1.0);
    const Ragdoll doll = create_ragdoll(world, def);
    const RagdollParts parts = ragdoll_parts(def);
    const RagdollBone hinged[] = {RagdollBone::lower_arm_left, RagdollBone::lower_arm_right,
                                  RagdollBone::lower_leg_left, RagdollBone::lower_leg_right};
    double worst = 0.0;  // rad beyond a limit
    int asleep_at = -1;
    for (int i = 1; i <= 360; ++i) {
        world.step(1.0 / 60.0);
        for (const RagdollBone bone : hinged) {
            const std::size_t k = static_cast<std::size_t>(bone) - 1;  // bone k + 1's joint
            const JointDef& j = parts.joints[k].joint;
            ASSERT_EQ(j.type, JointType::hinge) << name(bone);
            const double angle = world.joint_position(doll.joints[k]);
            worst = std::max({worst, j.lo - angle, angle - j.hi});
        }
        if (asleep_at < 0 && world.awake_count() == 0) asleep_at = i;
    }
    std::printf("[ measured ] knees and elbows beyond their limits by at most %.4f rad; asleep from step %d\n", worst,
                asleep_at);
    // Without speculative stops the elbows swung 0.51 rad past straight on landing.
    EXPECT_LT(worst, 0.1) << "rad: the stops hold (speculative; the iterative solver leaves a few degrees)";
    EXPECT_GT(asleep_at, 0) << "asleep within 6 s";
}

}  // namespace
}  // namespace sim::test
