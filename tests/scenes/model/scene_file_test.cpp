// Scene files: a good scene parses into what it says, overrides go through
// the same checks, ghosts come out as the closed forms of the scene's own
// parameters, and the shipped catalogue loads.
#include "scenes/model/scene.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>

namespace scenes {
namespace {

constexpr const char* kSpring = R"(
description = "A mass on a spring."
frames = 120
checkpoints = [0, 60, 120]
[step]
integrator = "rk4"
dt = 0.01
substeps = 2
[[particles]]
name = "anchor"
position = [0, 1, 0]
pinned = true
[[particles]]
name = "bob"
position = [0.5, 1, 0]
velocity = [0, 0.2, 0]
mass = 2
color = "#ff8000"
[[forces.springs]]
a = "anchor"
b = 1
rest_length = 0
stiffness = 8
[[ghosts]]
particle = "bob"
solution = "oscillator"
anchor = "anchor"
)";

TEST(SceneFile, ParsesWhatItSays) {
    const SceneDef s = parse_scene(kSpring, "spring.toml");
    EXPECT_EQ(s.name, "spring");
    EXPECT_EQ(s.frames, 120);
    EXPECT_EQ(s.checkpoints, (std::vector<int>{0, 60, 120}));
    EXPECT_EQ(s.step.integrator, sim::Integrator::rk4);
    EXPECT_DOUBLE_EQ(s.step.dt, 0.01);
    EXPECT_EQ(s.step.substeps, 2);
    ASSERT_EQ(s.model.particles.size(), 2u);
    EXPECT_TRUE(s.model.particles[0].pinned);
    EXPECT_DOUBLE_EQ(s.model.particles[1].mass, 2.0);
    EXPECT_FLOAT_EQ(s.looks[1].color.g, 128.0f / 255.0f);
    EXPECT_EQ(s.particle_names[1], "bob");
    EXPECT_EQ(s.systems(), (std::vector<std::string>{"particles", "springs", "watchdog"}));
}

// The objects `check` names: bodies, emitters, named particles (a group's
// members as one), rigid bodies with their ragdoll; unnamed particles none.
TEST(SceneFile, ObjectsAreTheNamedThingsInSceneOrder) {
    const SceneDef s = parse_scene(R"(
description = "One of each kind of object."
[[particles]]
name = "lone"
position = [0, 1, 0]
[[particles]]
position = [0, 2, 0]
[[groups]]
name = "drops"
count = 3
start = [0, 3, 0]
[[ropes]]
name = "line"
start = [0, 5, 0]
end = [1, 5, 0]
segments = 4
[[emitters]]
name = "jet"
count = 10
[[bodies]]
name = "crate"
shape = "box"
size = [1, 1, 1]
position = [3, 1, 0]
[[ragdolls]]
name = "r0"
position = [5, 1, 0]
)",
                                   "objects.toml");
    const std::vector<SceneObject> objects = scene_objects(s);
    std::vector<std::string> names;
    for (const SceneObject& o : objects) names.push_back(o.name);
    ASSERT_GE(names.size(), 7u);
    EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 6),
              (std::vector<std::string>{"line", "jet", "lone", "drops", "crate", "r0.pelvis"}));
    EXPECT_EQ(objects[1].count, 10u) << "the emitter's particles";
    EXPECT_EQ(objects[3].count, 3u) << "drops[0] .. drops[2], one object";
    EXPECT_EQ(objects[0].count, 5u) << "a rope of 4 segments has 5 particles";
    EXPECT_TRUE(objects[4].rigid);
    EXPECT_EQ(objects[4].group, "");
    for (std::size_t k = 5; k < objects.size(); ++k) {
        EXPECT_EQ(objects[k].group, "r0") << objects[k].name;
        EXPECT_TRUE(objects[k].rigid);
    }
}

TEST(SceneFile, OscillatorGhostIsTheClosedFormAboutTheAnchor) {
    const SceneDef s = parse_scene(kSpring, "spring.toml");
    ASSERT_EQ(s.ghosts.size(), 1u);
    const Ghost& g = s.ghosts[0];
    EXPECT_EQ(g.particle, 1u);
    // ω = sqrt(k/m) = 2 rad/s: x(t) = anchor + x0 cos ωt + v0/ω sin ωt, independently of the loader's derivation.
    for (double t : {0.0, 0.3, 1.7}) {
        const sim::Vec3 expected =
            sim::Vec3(0, 1, 0) + sim::Vec3(0.5, 0, 0) * std::cos(2 * t) + sim::Vec3(0, 0.2, 0) / 2.0 * std::sin(2 * t);
        EXPECT_LT((g.exact(t).x - expected).norm(), 1e-12) << "m, at t = " << t << " s";
    }
}

TEST(SceneFile, OverridesGoThroughTheSameChecks) {
    const SceneDef s =
        parse_scene(kSpring, "spring.toml",
                    {{"step.dt", "0.005"}, {"forces.springs[0].stiffness", "50"}, {"watchdog.max_speed", "7"}});
    EXPECT_DOUBLE_EQ(s.step.dt, 0.005);
    EXPECT_DOUBLE_EQ(std::get<sim::Springs>(s.model.forces[0]).list[0].k, 50.0);
    EXPECT_DOUBLE_EQ(s.watchdog.max_speed, 7.0);
    try {
        parse_scene(kSpring, "spring.toml", {parse_override("particles[1].mass=-1")});
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_STREQ(e.what(), "--set particles[1].mass=-1: particles[1].mass must be > 0 and finite, in kg (got -1)");
    }
    EXPECT_THROW(parse_override("step.dt"), SceneError);
    EXPECT_THROW(parse_scene(kSpring, "spring.toml", {{"step.integrator", "rk4"}}), SceneError) << "unquoted string";
}

TEST(SceneFile, ErrorsNameFileLineAndColumn) {
    try {
        parse_scene("description = \"x\"\n[[particles]]\nposition = [0, 0, 0]\nmass = -3\n", "dir/bad.toml");
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_STREQ(e.what(), "dir/bad.toml:4:8: particles[0].mass must be > 0 and finite, in kg (got -3)");
    }
}

// toml++ 3.3 asks "is this non-ASCII whitespace?" of the first character
// after a line-ending backslash, and for code points in U+00A1..U+0499 (and
// three other ranges) that are not whitespace its answer is undefined
// behaviour (upstream issue #190; docs/design.md, "toml++"). Debian's
// library answers "no": the characters are kept, as TOML says.
TEST(SceneFile, NonAsciiAfterALineEndingBackslashIsKept) {
    const SceneDef s = parse_scene(
        "description = \"\"\"Kept: \\\n  \xc2\xa7 and \\\n\t\xc3\xa9 and \\\n\xd0\xb6 too.\"\"\"\n"
        "[[particles]]\nposition = [0, 0, 0]\n",
        "unicode.toml");
    EXPECT_EQ(s.description, "Kept: \xc2\xa7 and \xc3\xa9 and \xd0\xb6 too.") << "U+00A7, U+00E9, U+0436";
}

TEST(SceneFile, AHeavyBodyOnALightOneWarnsForTheIterativeSolverOnly) {
    const std::string chain =
        "description = \"x\"\n"
        "[[bodies]]\nname = \"link\"\nmass = 2\n"
        "[[bodies]]\nname = \"ball\"\nshape = \"sphere\"\nsize = [0.3, 0, 0]\nmass = 200\nposition = [0, -1, 0]\n"
        "[[joints]]\ntype = \"ball\"\na = \"link\"\nb = \"ball\"\nanchor = [0, -0.5, 0]\n";
    const SceneDef iterative = parse_scene(chain, "chain.toml");
    ASSERT_EQ(iterative.warnings.size(), 1u);
    EXPECT_NE(iterative.warnings[0].find("chain.toml:11:1: link (2 kg) and ball (200 kg)"), std::string::npos)
        << iterative.warnings[0];
    EXPECT_NE(iterative.warnings[0].find("100:1"), std::string::npos) << iterative.warnings[0];
    const SceneDef exact = parse_scene(chain + "[rigid]\nquickstep = false\n", "chain.toml");
    EXPECT_TRUE(exact.warnings.empty()) << "ODE's exact solver does not mind the ratio";
}

// --frames N (--set frames=N) shortens a run: the checkpoints past N are
// dropped, and the last frame is one when none is left. In the file itself a
// checkpoint past `frames` stays an error.
TEST(SceneFile, ShorteningARunKeepsTheCheckpointsItReaches) {
    const std::string text =
        "description = \"d\"\nframes = 60\ncheckpoints = [0, 30, 60]\n[[particles]]\nposition = [0, 1, 0]\n";
    EXPECT_EQ(parse_scene(text, "short.toml", {{"frames", "40"}}).checkpoints, (std::vector<int>{0, 30}));
    EXPECT_EQ(
        parse_scene("description = \"d\"\nframes = 60\ncheckpoints = [30, 60]\n[[particles]]\nposition = [0, 1, 0]\n",
                    "short.toml", {{"frames", "10"}})
            .checkpoints,
        (std::vector<int>{10}));
    EXPECT_THROW(
        parse_scene("description = \"d\"\nframes = 20\ncheckpoints = [0, 30]\n[[particles]]\nposition = [0, 1, 0]\n",
                    "bad.toml"),
        SceneError);
}

TEST(SceneFile, ShippedCatalogueLoads) {
    const auto names = catalog();
    ASSERT_GE(names.size(), 4u);
    // The first is the default demo: every kind of system at once.
    EXPECT_EQ(names.front(), "showcase");
    const SceneDef showcase = load_scene(resolve_scene("showcase"));
    const auto heads = std::count_if(showcase.body_names.begin(), showcase.body_names.end(),
                                     [](const std::string& n) { return n.size() > 5 && n.ends_with(".head"); });
    EXPECT_GE(heads, 2) << "ragdolls (bones are named <ragdoll>.<bone>)";
    EXPECT_FALSE(showcase.model.emitters.empty()) << "a particle effect";
    auto has = [&](BodyLook::Kind kind) {
        return std::any_of(showcase.bodies.begin(), showcase.bodies.end(),
                           [&](const BodyLook& b) { return b.kind == kind; });
    };
    EXPECT_TRUE(has(BodyLook::Kind::rope) && has(BodyLook::Kind::cloth)) << "a rope and a cloth";
    for (const std::string& name : names) {
        const SceneDef s = load_scene(resolve_scene(name));
        EXPECT_EQ(s.name, name);
        EXPECT_FALSE(s.description.empty());
        const bool has_closed_form = name == "orbit" || name == "ballistic" || name == "oscillator" ||
                                     name == "pendulum" || name == "barycenter";
        EXPECT_EQ(!s.ghosts.empty(), has_closed_form) << name << ": the scenes with a closed form show it";
        for (const Ghost& g : s.ghosts) {
            const sim::Vec3 x0 = g.body >= 0 ? s.model.rigid.bodies[static_cast<std::size_t>(g.body)].position
                                             : s.model.particles[g.particle].position;
            EXPECT_LT((g.exact(0.0).x - x0).norm(), 1e-9) << name << ": the ghost starts on its particle or body, m";
        }
    }
    EXPECT_THROW(resolve_scene("nope"), SceneError);
}

}  // namespace
}  // namespace scenes
