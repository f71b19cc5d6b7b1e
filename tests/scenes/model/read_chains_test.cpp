// [[chains]] (scenes/model/read_chains.cpp): the links, joints and end body
// the loader builds, against the closed form of a straight chain (joint i at
// anchor + i L d, link i's centre at anchor + (i + 1/2) L d, its capsule's
// axis along d, the end body's centre end_offset beyond the last joint); one
// key changes the whole chain; the shipped wrecking ball is the scene its
// hand-computed file was, and holds together when stepped; and every bad
// input is refused with file:line:column and the value.
#include "scenes/model/scene.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace scenes {
namespace {

// A chain of 5 links of 0.4 m down a slanted direction (1, -2, 2) / 3 with a
// 0.2 m sphere at its end, and a crate that is not part of it.
constexpr const char* kChain = R"(description = "A chain."
[[bodies]]
name = "crate"
position = [3, 0.25, 0]
[[bodies]]
name = "ball"
shape = "sphere"
size = [0.2, 0, 0]
mass = 50
[[chains]]
name = "link"
anchor = [1, 4, -1]
direction = [1, -2, 2]
links = 5
link_length = 0.4
radius = 0.05
mass = 2
end = "ball"
[rigid]
quickstep = false
)";

const sim::Vec3 kAnchor(1, 4, -1);                     // m
const sim::Vec3 kDirection = sim::Vec3(1, -2, 2) / 3;  // unit: |(1, -2, 2)| = 3

// Every link, joint and the end body of a parsed kChain against the closed
// form for link length L (m) and n links; the crate and the ball come first.
void expect_straight_chain(const SceneDef& s, double L, int n) {
    const auto& bodies = s.model.rigid.bodies;
    const auto& joints = s.model.rigid.joints;
    ASSERT_EQ(bodies.size(), static_cast<std::size_t>(2 + n)) << "the crate, the ball, then the links";
    ASSERT_EQ(joints.size(), static_cast<std::size_t>(n + 1)) << "the world's, n - 1 between links, the ball's";
    auto joint_point = [&](int i) { return sim::Vec3(kAnchor + i * L * kDirection); };
    for (int i = 0; i < n; ++i) {
        const sim::BodyDef& link = bodies[static_cast<std::size_t>(2 + i)];
        EXPECT_EQ(s.body_names[static_cast<std::size_t>(2 + i)], "link" + std::to_string(i));
        EXPECT_EQ(link.shape, sim::RigidShape::capsule);
        EXPECT_DOUBLE_EQ(link.size.x(), 0.05) << "m, the radius";
        EXPECT_NEAR(link.size.y(), L - 0.1, 1e-15) << "m, the straight part: link_length - 2 radius";
        EXPECT_DOUBLE_EQ(link.mass, 2.0) << "kg";
        EXPECT_LT((link.position - (kAnchor + (i + 0.5) * L * kDirection)).norm(), 1e-12)
            << "m, link " << i << "'s centre half-way between its joints";
        const sim::Vec3 axis = link.orientation * sim::Vec3::UnitZ();
        EXPECT_LT((axis - kDirection).norm(), 1e-12) << "the capsule's axis (local z) along the chain, link " << i;
        // Its round ends reach its two joints: centre -+ (L / 2) axis.
        EXPECT_LT((link.position - 0.5 * L * axis - joint_point(i)).norm(), 1e-12) << "m, upper end, link " << i;
        EXPECT_LT((link.position + 0.5 * L * axis - joint_point(i + 1)).norm(), 1e-12) << "m, lower end, link " << i;
        const sim::RigidJoint& j = joints[static_cast<std::size_t>(i)];
        EXPECT_EQ(j.joint.type, sim::JointType::ball);
        EXPECT_LT((j.joint.anchor - joint_point(i)).norm(), 1e-12) << "m, joint " << i;
        EXPECT_EQ(j.a, i == 0 ? 2 : 2 + i - 1) << "joint " << i;
        EXPECT_EQ(j.b, i == 0 ? -1 : 2 + i) << "joint " << i << " (-1: the world)";
    }
    const sim::RigidJoint& end = joints.back();
    EXPECT_LT((end.joint.anchor - joint_point(n)).norm(), 1e-12) << "m, the ball's joint at the chain's end";
    EXPECT_EQ(end.a, 2 + n - 1);
    EXPECT_EQ(end.b, 1) << "the ball";
    EXPECT_LT((bodies[1].position - (kAnchor + (n * L + 0.2) * kDirection)).norm(), 1e-12)
        << "m, the ball's centre its radius (0.2 m) beyond the last joint";
    EXPECT_LT((bodies[0].position - sim::Vec3(3, 0.25, 0)).norm(), 1e-15) << "m, the crate is not moved";
}

TEST(ReadChains, LinksJointsAndTheEndBodyLieOnTheChainsLine) {
    expect_straight_chain(parse_scene(kChain, "chain.toml"), 0.4, 5);
}

TEST(ReadChains, OneKeyChangesTheWholeChain) {
    expect_straight_chain(parse_scene(kChain, "chain.toml", {{"chains[0].link_length", "0.7"}}), 0.7, 5);
    expect_straight_chain(parse_scene(kChain, "chain.toml", {{"chains[0].links", "9"}}), 0.4, 9);
}

TEST(ReadChains, AFreeChainHasNoJointToTheWorldAndABoxNeedsItsOffset) {
    std::string text = kChain;
    const std::string sphere = "shape = \"sphere\"\nsize = [0.2, 0, 0]";
    text.replace(text.find(sphere), sphere.size(), "size = [0.6, 0.6, 0.6]");
    const SceneDef s =
        parse_scene(text + "[[chains]]\nlinks = 2\nfixed = false\n", "chain.toml", {{"chains[0].end_offset", "0.3"}});
    const auto& m = s.model.rigid;
    EXPECT_LT((m.bodies[1].position - (kAnchor + (5 * 0.4 + 0.3) * kDirection)).norm(), 1e-12)
        << "m, the box's centre end_offset (0.3 m) beyond the last joint";
    // The second chain: default anchor (0, 2, 0), direction down, links of 0.2 m, named chain1_<i>.
    ASSERT_EQ(m.bodies.size(), 2u + 5u + 2u);
    EXPECT_EQ(s.body_names[7], "chain1_0");
    EXPECT_LT((m.bodies[8].position - sim::Vec3(0, 2 - 1.5 * 0.2, 0)).norm(), 1e-12) << "m";
    ASSERT_EQ(m.joints.size(), 6u + 1u) << "the first chain's 6, and one between the free chain's two links";
    EXPECT_EQ(m.joints.back().a, 7);
    EXPECT_EQ(m.joints.back().b, 8);
    EXPECT_LT((m.joints.back().joint.anchor - sim::Vec3(0, 1.8, 0)).norm(), 1e-12) << "m";
}

TEST(ReadChains, AHeavyEndOnTheIterativeSolverWarnsAtTheChain) {
    std::string text = kChain;
    text.erase(text.find("[rigid]"));
    const SceneDef s = parse_scene(text, "chain.toml");
    ASSERT_EQ(s.warnings.size(), 1u) << "only the 2 kg link and the 50 kg ball: 25:1";
    EXPECT_NE(s.warnings[0].find("chain.toml:10:1: link4 (2 kg) and ball (50 kg)"), std::string::npos) << s.warnings[0];
}

// The wrecking ball's file before the chain builder: its hand-computed link
// centres, ball centre and joint anchors, to 4 decimals (m).
constexpr std::array<std::array<double, 2>, 9> kHandCentres = {{{-0.2165, 5.0750},
                                                                {-0.6495, 4.8250},
                                                                {-1.0825, 4.5750},
                                                                {-1.5155, 4.3250},
                                                                {-1.9486, 4.0750},
                                                                {-2.3816, 3.8250},
                                                                {-2.8146, 3.5750},
                                                                {-3.2476, 3.3250},
                                                                {-3.7672, 3.0250}}};
constexpr std::array<std::array<double, 2>, 9> kHandAnchors = {{{0.0000, 5.2000},
                                                                {-0.4330, 4.9500},
                                                                {-0.8660, 4.7000},
                                                                {-1.2990, 4.4500},
                                                                {-1.7321, 4.2000},
                                                                {-2.1651, 3.9500},
                                                                {-2.5981, 3.7000},
                                                                {-3.0311, 3.4500},
                                                                {-3.4641, 3.2000}}};

// The index of a body by name in a loaded scene.
std::size_t body(const SceneDef& s, const std::string& name) {
    const auto it = std::find(s.body_names.begin(), s.body_names.end(), name);
    EXPECT_NE(it, s.body_names.end()) << name;
    return static_cast<std::size_t>(it - s.body_names.begin());
}

TEST(ReadChains, TheWreckingBallIsTheSceneItsHandComputedFileWas) {
    const SceneDef s = load_scene(resolve_scene("wrecking-ball"));
    const auto& m = s.model.rigid;
    double worst = 0.0;  // m
    for (std::size_t i = 0; i < 9; ++i) {
        const sim::Vec3 hand(kHandCentres[i][0], kHandCentres[i][1], 0);
        const sim::BodyDef& b = m.bodies[body(s, i < 8 ? "link" + std::to_string(i) : "ball")];
        worst = std::max(worst, (b.position - hand).norm());
        EXPECT_LE((b.position - hand).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12) << "m: the hand value rounded, body " << i;
        const sim::Vec3 hand_anchor(kHandAnchors[i][0], kHandAnchors[i][1], 0);
        EXPECT_LE((m.joints[i].joint.anchor - hand_anchor).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12)
            << "m: the hand value rounded, joint " << i;
        if (i < 8) {
            EXPECT_NEAR(b.mass, 2.0, 0.0) << "kg";
            // The hand file's rotation = [0, -90, 30] turned the capsule's z to (-cos 30°, -sin 30°, 0).
            const sim::Vec3 axis = b.orientation * sim::Vec3::UnitZ();
            EXPECT_LT((axis - sim::Vec3(-std::sqrt(3.0) / 2, -0.5, 0)).norm(), 1e-12) << "link " << i;
        }
    }
    std::printf("[ measured ] largest change of a body's start from the hand values: %.3g m\n", worst);
    EXPECT_NEAR(m.bodies[body(s, "ball")].mass, 200.0, 0.0) << "kg";
    EXPECT_EQ(m.joints.size(), 9u);
}

// The wrecking ball stepped through its swing into the wall: each joint's
// two sides, found from the bodies' poses and the builder's geometry (a
// link's joints at its centre -+ (L / 2) axis; the ball's at its start
// offset, carried in its frame), stay together.
TEST(ReadChains, TheWreckingBallsChainHoldsTogetherThroughTheSwingAndTheWall) {
    const SceneDef scene = load_scene(resolve_scene("wrecking-ball"));
    constexpr double L = 0.5;  // m, the scene's link_length
    sim::World world(scene.model);
    const sim::RigidWorld& rigid = *world.rigid();
    std::array<std::uint32_t, 8> links{};
    for (std::size_t i = 0; i < 8; ++i) links[i] = static_cast<std::uint32_t>(body(scene, "link" + std::to_string(i)));
    const auto ball = static_cast<std::uint32_t>(body(scene, "ball"));
    const sim::BodyDef& ball0 = scene.model.rigid.bodies[ball];
    const sim::Vec3 ball_hook =
        ball0.orientation.inverse() * (scene.model.rigid.joints[8].joint.anchor - ball0.position);
    auto end = [&](std::uint32_t k, double side) {
        const sim::BodyState st = rigid.state({k, 0});
        return sim::Vec3(st.position + side * 0.5 * L * (st.orientation * sim::Vec3::UnitZ()));
    };
    auto gap = [&] {
        double worst = (end(links[0], -1) - sim::Vec3(0, 5.2, 0)).norm();
        for (std::size_t i = 0; i + 1 < 8; ++i)
            worst = std::max(worst, (end(links[i], 1) - end(links[i + 1], -1)).norm());
        const sim::BodyState b = rigid.state({ball, 0});
        return std::max(worst, (end(links[7], 1) - (b.position + b.orientation * ball_hook)).norm());
    };
    EXPECT_LT(gap(), 1e-12) << "m, at the start";
    double worst = 0.0;
    for (int f = 0; f < scene.frames; ++f) {
        world.step(scene.step);
        worst = std::max(worst, gap());
    }
    std::printf("[ measured ] largest gap at a joint over the run: %.3g m\n", worst);
    EXPECT_FALSE(world.verdict().exploded());
    EXPECT_LE(worst, 0.005) << "m: the chain holds together through the swing and the wall";
    // The swing did reach the wall: its top middle brick was knocked from its place.
    const std::size_t brick = body(scene, "brick3_1");
    const double moved =
        (rigid.state({static_cast<std::uint32_t>(brick), 0}).position - scene.model.rigid.bodies[brick].position)
            .norm();
    std::printf("[ measured ] the top middle brick moved: %.3g m\n", moved);
    EXPECT_GT(moved, 0.5) << "m";
}

// Bad input: the message names file, line and column, the key and the value.
struct BadChain {
    const char* name;     // the test's name
    const char* replace;  // a line of kBadBase to replace ("" for none)
    const char* with;     // its replacement, or what is appended when `replace` is ""
    const char* where;    // "bad.toml:line:column"
    const char* message;  // the rest of the message (a prefix of it)
};

constexpr const char* kBadBase = R"(description = "x"
[[bodies]]
name = "ball"
shape = "sphere"
size = [0.2, 0, 0]
[[chains]]
name = "link"
end = "ball"
)";

class ReadChainsRefuses : public ::testing::TestWithParam<BadChain> {};

TEST_P(ReadChainsRefuses, NamingFileLineAndValue) {
    const BadChain& bad = GetParam();
    std::string text = kBadBase;
    if (std::string(bad.replace).empty()) {
        text += bad.with;
    } else {
        ASSERT_NE(text.find(bad.replace), std::string::npos) << bad.replace;
        text.replace(text.find(bad.replace), std::string(bad.replace).size(), bad.with);
    }
    try {
        parse_scene(text, "bad.toml");
        FAIL() << "accepted: " << bad.with;
    } catch (const SceneError& e) {
        const std::string expected = std::string(bad.where) + ": " + bad.message;
        EXPECT_EQ(std::string(e.what()).substr(0, expected.size()), expected) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, ReadChainsRefuses,
    ::testing::Values(
        BadChain{"NoLinks", "", "links = 0\n", "bad.toml:9:9", "chains[0].links must be within 1 .. 10000 (got 0)"},
        BadChain{"LinksShorterThanTwoRadii", "", "radius = 0.1\nlink_length = 0.2\n", "bad.toml:10:15",
                 "chains[0].link_length must be more than twice the radius (0.2 m) by at least 0.001 m: the "
                 "capsule is [radius, link_length - 2 radius] (got 0.2)"},
        BadChain{"ZeroDirection", "", "direction = [0, 0, 0]\n", "bad.toml:9:13",
                 "chains[0].direction must be a non-zero direction"},
        BadChain{"NameTakenByABody", "", "[[bodies]]\nname = \"link1\"\n", "bad.toml:7:8",
                 "chains[0].name makes the link 'link1', a name already taken"},
        BadChain{"NameTakenByAChain", "", "[[chains]]\nname = \"link\"\n", "bad.toml:10:8",
                 "chains[1].name makes the link 'link0', a name already taken"},
        BadChain{"UnknownEnd", "", "[[chains]]\nname = \"c\"\nend = \"bal\"\n", "bad.toml:11:7",
                 "chains[1].end names no body (got 'bal')"},
        BadChain{"RepeatedEnd", "", "[[chains]]\nname = \"c\"\nend = \"ball\"\n", "bad.toml:11:7",
                 "chains[1].end names 'ball', already the end of an earlier chain"},
        BadChain{"EndNotABodiesEntry", "", "[[chains]]\nname = \"c\"\nend = \"link0\"\n", "bad.toml:11:7",
                 "chains[1].end must name a [[bodies]] entry (got 'link0', made by a ragdoll or a chain)"},
        BadChain{"EndWithAPosition", "size = [0.2, 0, 0]", "size = [0.2, 0, 0]\nposition = [0, 1, 0]", "bad.toml:6:12",
                 "bodies[0].position must not be given: the body is the end of chains[0], which places it"},
        BadChain{"EndNotASphereWithoutOffset", "shape = \"sphere\"\nsize = [0.2, 0, 0]", "size = [0.4, 0.4, 0.4]",
                 "bad.toml:7:7",
                 "chains[0].end names 'ball', not a plain sphere: give end_offset, the distance in m from the last "
                 "joint to its centre of mass"},
        BadChain{"OffsetWithoutEnd", "", "[[chains]]\nname = \"c\"\nend_offset = 0.5\n", "bad.toml:11:14",
                 "chains[1].end_offset needs end: the body it places"},
        BadChain{"NegativeOffset", "", "end_offset = -1\n", "bad.toml:9:14",
                 "chains[0].end_offset must be within 0 .. "},
        BadChain{"UnknownKey", "", "lenght = 2\n", "bad.toml:9:10", "unknown key 'chains[0].lenght'"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace scenes
