// The malformed scene corpus (tests/data/bad_scenes/): every file makes
// `plausible run FILE --csv OUT` exit 2 with a message that names the file and
// the line, says what was wrong, and writes nothing. And values at the edge of
// what the loader accepts, which run as they say.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct BadScene {
    const char* file;      // under tests/data/bad_scenes/
    int line;              // where the message must point
    const char* expected;  // a fragment of the message
};

// Each file's expected line and message fragment (the corpus has no other
// place for them: some files are empty or binary).
constexpr BadScene kCorpus[] = {
    {"empty.toml", 1, "the file is empty"},
    {"syntax_unterminated_string.toml", 1, "not valid TOML"},
    {"syntax_bad_header.toml", 2, "not valid TOML"},
    {"binary_garbage.toml", 0, "not valid TOML"},
    {"not_utf8.toml", 1, "not valid TOML"},
    // toml++ 3.3's own bugs (docs/design.md, "toml++"): an assertion in a
    // build without NDEBUG, and undefined behaviour in its whitespace test.
    {"toml_bracket_newline.toml", 2, "not valid TOML: Error while parsing key"},
    {"toml_non_ascii_not_whitespace.toml", 2, "not valid TOML: Error while parsing root table"},
    {"missing_description.toml", 1, "description is required"},
    {"no_particles.toml", 1, "a scene needs at least one [[particles]]"},
    {"unknown_top_key.toml", 2, "unknown key 'frame' (did you mean 'frames'?)"},
    {"unknown_spring_key.toml", 11, "unknown key 'forces.springs[0].stiffnes' (did you mean 'stiffness'?)"},
    {"negative_mass.toml", 4, "particles[0].mass must be > 0 and finite, in kg (got -2)"},
    {"zero_mass.toml", 4, "particles[0].mass must be > 0 and finite, in kg (got 0)"},
    {"negative_stiffness.toml", 12, "forces.springs[0].stiffness must be >= 0 and finite, in N/m (got -3)"},
    {"dt_zero.toml", 3, "step.dt must be > 0 and at most 10, in s (got 0)"},
    {"dt_negative.toml", 3, "step.dt must be > 0 and at most 10, in s (got -0.01)"},
    {"dt_nan.toml", 3, "step.dt must be > 0 and at most 10, in s (got nan)"},
    {"position_inf.toml", 3, "particles[0].position[1] must be [x, y, z]"},
    {"velocity_nan.toml", 4, "particles[0].velocity[0] must be [x, y, z]"},
    {"mass_wrong_type.toml", 4, "particles[0].mass must be > 0 and finite, in kg (got the string 'heavy')"},
    {"position_two_components.toml", 3,
     "particles[0].position must be [x, y, z]: three finite numbers in m (got an array of 2)"},
    {"unknown_integrator.toml", 3, "step.integrator must be one of forward_euler"},
    {"substeps_zero.toml", 3, "step.substeps must be within 1 .. 10000 (got 0)"},
    {"spring_missing_particle.toml", 7, "forces.springs[0].b names no particle (got 'ghost')"},
    {"spring_index_out_of_range.toml", 8, "forces.springs[0].b must be a particle index within 0 .. 1 (got 7)"},
    {"spring_to_itself.toml", 7, "forces.springs[0].b must be another particle than a"},
    {"duplicate_name.toml", 6, "particles[1].name must be unique: 'ball' is taken"},
    {"huge_group.toml", 3, "groups[0].count must be within 1 .. 1000000 (got 1000000000)"},
    {"huge_array.toml", 3,
     "particles[0].position must be [x, y, z]: three finite numbers in m (got an array of 100000)"},
    {"checkpoint_beyond_end.toml", 3,
     "checkpoints[2] must be an integer frame within 0 .. frames (60), ascending (got 90)"},
    {"checkpoints_descending.toml", 3,
     "checkpoints[2] must be an integer frame within 0 .. frames (60), ascending (got 20)"},
    {"ghost_missing_particle.toml", 8, "ghosts[0].particle names no particle (got 'bal')"},
    {"ghost_wrong_solution.toml", 11, "ghosts[0].solution 'ballistic' needs uniform gravity and no drag"},
    {"bad_color.toml", 4, "particles[0].color must be \"#rrggbb\" or [r, g, b]"},
    {"watchdog_negative_speed.toml", 3, "watchdog.max_speed must be > 0 and finite, in m/s (got -500)"},
    {"camera_eye_is_target.toml", 4, "camera.target must differ from camera.eye"},
    {"frames_float.toml", 2, "frames must be an integer within 1 .. 10000000 (got 10.5)"},
    {"particles_not_array.toml", 2, "particles must be an array of tables"},
    {"rope_zero_segments.toml", 6, "ropes[0].segments must be within 1 .. 4096 (got 0)"},
    {"collider_unknown_shape.toml", 7, "colliders[0].shape must be one of plane, sphere, box, capsule (got 'torus')"},
    {"cloth_bad_pins.toml", 6, "cloths[0].pins must be one of none, corners, edge, all (got 'top')"},
    {"wind_unknown_body.toml", 8, "forces.wind.bodies[0] names no cloth or soft body (got the string 'flag')"},
    {"restitution_above_one.toml", 7, "collisions.restitution must be within 0 .. 1"},
    {"control_end_before_start.toml", 9, "forces.control[0].end must be after start (got 1)"},
    {"body_negative_mass.toml", 7, "bodies[0].mass must be within 0.001 .. 1e+06, in kg (got -5)"},
    {"body_parts_and_shape.toml", 6, "bodies[0].parts replace shape and size: give one or the other"},
    {"joint_unknown_body.toml", 10, "joints[0].b names no body (got 'frame')"},
    {"joint_unknown_type.toml", 11,
     "joints[0].type must be one of ball, hinge, universal, slider, fixed (got 'spring')"},
    {"ragdoll_negative_height.toml", 5, "ragdolls[0].height must be > 0 and at most 100, in m (got -1.8)"},
    {"rigid_iterations_zero.toml", 7, "rigid.iterations must be within 1 .. 10000 (got 0)"},
    {"chain_link_too_short.toml", 7, "chains[0].link_length must be more than twice the radius (0.2 m)"},
    {"ghost_unknown_body.toml", 11, "ghosts[0].body names no body (got 'hamer')"},
    {"frames_huge_float.toml", 2, "frames must be an integer within 1 .. 10000000 (got 1e+308)"},
    {"checkpoint_huge_float.toml", 3,
     "checkpoints[1] must be an integer frame within 0 .. frames (10), ascending (got 1e+308)"},
    {"ghost_kepler_on_centre.toml", 14,
     "ghosts[0].particle has no closed-form orbit about the centre (kepler: r0 must not be zero)"},
    {"rigid_sleep_time_huge.toml", 8,
     "rigid.sleep_time must be > 0 and at most 1e+06, in s (11.6 days; a longer rest means never: say sleep = false) "
     "(got 1e+300)"},
    {"wind_gust_period_tiny.toml", 8, "forces.wind.gust_period must be within 0.001 .. 1e+06, in s (got 1e-300)"},
    {"trail_frames_huge.toml", 9,
     "view.trail_frames = 1000 behind 1000000 moving particles keeps 6.01e+08 trail points by frame 600"},
    {"newton_gravity_huge_group.toml", 7,
     "forces.newton_gravity on 1000000 particles is O(n²): n (n - 1) / 2 = 499999500000 pairs, evaluated 2 times a "
     "frame"},
};

struct Result {
    int exit_code = -1;
    std::string err;
};

Result run(const std::string& args, const fs::path& dir) {
    const fs::path err = dir / "stderr.txt";
    const std::string command = std::string("'") + PLAUSIBLE_EXE + "' " + args + " 2>'" + err.string() + "' >/dev/null";
    const int status = std::system(command.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(err);
    r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    fs::remove(err);
    return r;
}

class BadSceneCorpus : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneCorpus, ExitsTwoWithFileLineAndWritesNothing) {
    const BadScene& bad = GetParam();
    const fs::path file = fs::path(PLAUSIBLE_SOURCE_DIR) / "tests/data/bad_scenes" / bad.file;
    ASSERT_TRUE(fs::exists(file)) << file;
    const char* root = std::getenv("PLAUSIBLE_TEST_RESULTS");
    const fs::path dir =
        fs::path(root != nullptr ? root : fs::temp_directory_path().string()) / "bad_scenes" / bad.file;
    fs::remove_all(dir);
    fs::create_directories(dir);
    const Result r = run("run '" + file.string() + "' --csv '" + (dir / "out.csv").string() + "'", dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string where = file.string() + ":" + (bad.line > 0 ? std::to_string(bad.line) + ":" : "");
    EXPECT_NE(r.err.find(where), std::string::npos) << "expected '" << where << "' in: " << r.err;
    EXPECT_NE(r.err.find(bad.expected), std::string::npos) << "expected '" << bad.expected << "' in: " << r.err;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0) << "something was written";
    // The same file through render: nothing written there either.
    const Result rendered = run("render '" + file.string() + "' --out '" + (dir / "frames").string() + "'", dir);
    EXPECT_EQ(rendered.exit_code, 2) << rendered.err;
    EXPECT_FALSE(fs::exists(dir / "frames"));
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadSceneCorpus, ::testing::ValuesIn(kCorpus), [](const auto& info) {
    std::string name = info.param.file;
    name = name.substr(0, name.find('.'));
    return name;
});

TEST(BadSceneCorpus, EveryFileOfTheCorpusIsListed) {
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(PLAUSIBLE_SOURCE_DIR) / "tests/data/bad_scenes")) {
        ++files;
        bool listed = false;
        for (const BadScene& b : kCorpus) listed = listed || entry.path().filename() == b.file;
        EXPECT_TRUE(listed) << entry.path() << " has no expectation in kCorpus";
    }
    EXPECT_GE(files, 25u);
}

// Radii of 1e-20 m with particle collisions: the collision grid's cells of
// 2 r over a metre were 5e19 a side, the conversion to an integer overflowed
// and the run died with "cannot create std::vector larger than max_size()"
// (exit 1). Now it runs, and the pair overlapping by half a radius is pushed
// apart along the line of centres, half the overlap each: -0.25 r and 1.75 r.
TEST(EdgeValues, RadiiOf1e20MetreCollideThroughTheCommand) {
    const fs::path dir = fs::temp_directory_path() / "plausible_tiny_radii_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "tiny.toml") << R"(description = "Radii of 1e-20 m, colliding."
frames = 1
[[particles]]
position = [0, 1, 0]
radius = 1e-20
[[particles]]
position = [1.5e-20, 1, 0]
radius = 1e-20
[[particles]]
position = [1, 1, 0]
radius = 1e-20
[collisions]
particles = true
)";
    const Result r = run("run '" + (dir / "tiny.toml").string() + "' --csv '" + (dir / "out.csv").string() + "'", dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream csv(dir / "out.csv");
    std::string line;
    std::map<int, double> x;  // particle -> x at frame 1, m
    while (std::getline(csv, line)) {
        int frame = 0, id = 0;
        double t = 0, px = 0;
        if (std::sscanf(line.c_str(), "%d,%lf,particle,%d,%lf", &frame, &t, &id, &px) == 4 && frame == 1) x[id] = px;
    }
    ASSERT_EQ(x.size(), 3u);
    EXPECT_NEAR(x[0], -0.25e-20, 1e-26) << "m";
    EXPECT_NEAR(x[1], 1.75e-20, 1e-26) << "m";
    EXPECT_EQ(x[2], 1.0) << "m: untouched";
    fs::remove_all(dir);
}

TEST(SetOverrides, BadValuesNameTheOverride) {
    const fs::path dir = fs::temp_directory_path() / "plausible_set_test";
    fs::create_directories(dir);
    Result r = run("run oscillator --set step.dt=-1", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--set step.dt=-1: step.dt must be"), std::string::npos) << r.err;
    r = run("run oscillator --set forces.springs[3].stiffness=1", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("'forces.springs' has 1 entries"), std::string::npos) << r.err;
    r = run("run oscillator --set particles[1].mas=2", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("did you mean 'mass'?"), std::string::npos) << r.err;
    // An array's element is named by the override too, not by line 1 of the file.
    r = run("run oscillator --set 'particles[0].position=[0,1e300,0]'", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("error: --set particles[0].position=[0,1e300,0]: particles[0].position[1] must be"),
              std::string::npos)
        << r.err;
    r = run("run oscillator --integrator rk5", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("step.integrator must be one of"), std::string::npos) << r.err;
    r = run("run no_such_scene", dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("unknown scene 'no_such_scene'"), std::string::npos) << r.err;
    fs::remove_all(dir);
}

// Issue 51, row 2: a rope whose explosion is contained, starting outside the
// world box, was frozen outside it again and again (GBs, then std::bad_alloc).
TEST(SetOverrides, AContainedRopeOutsideTheWorldBoxIsRefused) {
    const fs::path dir = fs::temp_directory_path() / "plausible_contained_outside_test";
    fs::create_directories(dir);
    Result r = run("run rope-stiff --set 'ropes[0].end=[1.2,51,0.5]' --frames 1", dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--set ropes[0].end=[1.2,51,0.5]: ropes[0].end = [1.2, 51, 0.5] is outside the world box "
                         "(watchdog.world_half_extent = 50 m): a rope with contain_explosion = true must start "
                         "inside it"),
              std::string::npos)
        << r.err;
    // The same rope not contained runs, and the watchdog stops it at once (exit 1).
    r = run("run rope-stiff --set 'ropes[0].end=[1.2,51,0.5]' --set ropes[0].contain_explosion=false --frames 1", dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    fs::remove_all(dir);
}

// Issue 51, row 4: values the loader took that ODE's assertions abort on
// (exit 134) are refused, naming the override and the range; the edges of
// those ranges run.
TEST(SetOverrides, ValuesOdeCannotTakeAreRefusedAndTheirEdgesRun) {
    const fs::path dir = fs::temp_directory_path() / "plausible_ode_ranges_test";
    fs::create_directories(dir);
    const std::pair<const char*, const char*> refused[] = {
        {"ragdoll --set 'ragdolls[0].mass=1e-100'",
         "--set ragdolls[0].mass=1e-100: ragdolls[0].mass gives the pelvis 1.42e-101 kg; each bone's mass must be "
         "within 0.001 .. 1e+06 kg"},
        {"stack --set 'bodies[7].mass=1e300'",
         "--set bodies[7].mass=1e300: bodies[7].mass must be within 0.001 .. 1e+06, in kg (got 1e+300)"},
        {"inertia --set 'bodies[2].parts[1].size=[10000,0.3,0]'",
         "--set bodies[2].parts[1].size=[10000,0.3,0]: bodies[2].parts[1].size needs its first 2 entries within 0.001 "
         ".. 1000, in m (got 10000)"},
        {"inertia --set 'bodies[2].parts[1].size=[1000,0.3,0]'",
         "bodies[2].parts give a mass of 9.42e+08 kg; a body's must be within 0.001 .. 1e+06 kg"},
        // The mutation sweep's findings (tests/robustness/mutation_sweep.cpp).
        {"inertia --set 'bodies[1].angular_velocity=[0,1e9,0]'",
         "--set bodies[1].angular_velocity=[0,1e9,0]: bodies[1].angular_velocity[1] must be [x, y, z]: three finite "
         "numbers in deg/s, within +-1e+05 (got 1e+09)"},
        {"ragdoll --set 'ragdolls[0].joint_friction=1e300'",
         "--set ragdolls[0].joint_friction=1e300: ragdolls[0].joint_friction must be within 0 .. 1e+09, in N·m "
         "(got 1e+300)"},
        {"ragdoll-pile --set step.dt=1e-300",
         "--set step.dt=1e-300: step.dt / substeps must be at least 1e-09 s with rigid bodies: ODE divides by the "
         "step (got 1e-300)"},
        {"ragdoll --set 'ragdolls[0].position=[1e9,2.63,0]'",
         "--set ragdolls[0].position=[1e9,2.63,0]: ragdolls[0].position[0] must be [x, y, z]: three finite numbers "
         "in m, within +-1e+08 (got 1e+09)"},
    };
    for (const auto& [args, expected] : refused) {
        const Result r = run("run " + std::string(args) + " --frames 30", dir);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
        EXPECT_NE(r.err.find(expected), std::string::npos) << args << ": expected '" << expected << "' in " << r.err;
    }
    const char* edges[] = {
        "ragdoll --set 'ragdolls[0].position=[9.9e7,2.63,0]'",
        "stack --set 'bodies[7].mass=1e6'",
        "stack --set 'bodies[7].mass=0.001'",
        "inertia --set 'bodies[2].parts[1].size=[30,0.3,0]'",
        "inertia --set 'bodies[2].parts[1].size=[0.001,0.3,0]'",
        // Spun at the edge and stepped 10 s at a time: the gyroscopic RK4 in small steps, no overflow.
        "inertia --set 'bodies[1].angular_velocity=[1e5,1e5,1e5]' --dt 10",
        "ragdoll --set 'ragdolls[0].joint_friction=1e9'",
        "ragdoll-pile --set step.dt=1e-9",
    };
    for (const char* args : edges) {
        const Result r = run("run " + std::string(args) + " --frames 30", dir);
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << args << ": exit " << r.exit_code << ": " << r.err;
    }
    fs::remove_all(dir);
}

// A body that flies past where ODE can place it stops the run (exit 1), even
// with the watchdog off; ODE's hash space aborted on it (exit 134).
TEST(SetOverrides, ABodyBeyondOdesReachStopsTheRunWatchdogOrNot) {
    const fs::path dir = fs::temp_directory_path() / "plausible_ode_reach_test";
    fs::create_directories(dir);
    const Result r =
        run("run stack --set 'bodies[8].position=[9.9e7,1,0]' --set 'bodies[8].velocity=[1e9,0,0]' "
            "--set watchdog.enabled=false --frames 120",
            dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    fs::remove_all(dir);
}

// More frames than one contact sheet can hold (16384 px): refused before a
// frame is written, with the limit; a long list that fits is tiled in rows.
TEST(RenderCommand, FramesThatCannotFitOneSheetAreRefusedUpFront) {
    const fs::path dir = fs::temp_directory_path() / "plausible_render_frames_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string all;
    for (int f = 0; f <= 240; ++f) {
        if (f > 0) all += ',';
        all += std::to_string(f);
    }
    Result r = run("render cloth --size 1280x720 --frames " + all + " --out '" + (dir / "frames").string() + "'", dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("do not fit one contact sheet (at most 126)"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "frames"));
    r = run("render orbit --size 64x36 --frames " + all + " --out '" + (dir / "small").string() + "'", dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "small" / "orbit_sheet.png"));
    fs::remove_all(dir);
}

}  // namespace
