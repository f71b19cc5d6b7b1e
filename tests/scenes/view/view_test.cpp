// `plausible view` end to end: the real command in a real GLFW window on a
// virtual display (Xvfb), driven by input scripts (`view --input`: keys,
// text and mouse events at drawn frames, so that a loaded machine runs the
// same frames: no sleeps, no xdotool), screenshots of the window compared
// with the off-screen render (the default backend) of the same frame, and the
// state it printed compared with the same frames run here.
#include "render/gl_context.h"
#include "render/golden.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scenes/draw/scene_run.h"
#include "scenes/model/scene.h"
#include "scenes/view/frame_budget.h"
#include "sim/integrators.h"
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

using test::Ran;
using test::shell;

// The number after `key` in the viewer's last line ("frame 12", "state 9f...").
std::string field(const std::string& out, const std::string& key) {
    const std::regex pattern(key + " ([0-9a-f]+)");
    std::string last;
    for (auto it = std::sregex_iterator(out.begin(), out.end(), pattern); it != std::sregex_iterator(); ++it) {
        last = (*it)[1];
    }
    return last;
}

class View : public ::testing::Test {
protected:
    // Runs `script` (sh) on a virtual display of its own; $VIEW is the command.
    // In the sanitize build the viewer runs without LeakSanitizer: glfwTerminate
    // unloads Mesa's GLX driver (swrast_dri.so) before exit, so Mesa's
    // per-process allocations show as leaks in an "unknown module" that no
    // suppression can name. AddressSanitizer's other checks stay on.
    // Xvfb runs with -r (no key auto-repeat): nothing presses real keys now,
    // but a repeat would step the viewer once more.
    Ran under_xvfb(const std::string& script) const {
        const fs::path file = dir_ / "script.sh";
        std::ofstream(file) << "export ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\"\n"
                            << "VIEW='" << PLAUSIBLE_EXE << " view'\n"
                            << script;
        return shell("cd '" + dir_.string() + "' && timeout 120 xvfb-run -a -s '-screen 0 1280x800x24 -r' sh '" +
                     file.string() + "'");
    }

    // Runs `view SCENE ARGS --paused --input SCRIPT` on the virtual display
    // and returns what it printed, with its exit status. The script's
    // frames are the window's drawn frames (scenes/view/input_script.h).
    Ran play(const std::string& scene, const std::string& args, const std::string& script) const {
        std::ofstream(dir_ / "input.txt") << script;
        return under_xvfb("$VIEW " + scene + " --paused " + args + " --input input.txt\n");
    }

    // The scene run here for `frames` frames: its state hash and its picture
    // rendered off-screen as the window shows it (same size, 4x MSAA).
    struct Reference {
        std::string hash;
        render::Image image;
    };
    static Reference reference(const std::string& scene_name, int frames, int width, int height) {
        const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene(scene_name));
        scenes::SceneRun run(scene);
        for (int k = 0; k < frames; ++k) run.advance();
        const auto context = render::create_context({});
        render::Renderer renderer(*context);
        return {run.state_hash_hex(),
                renderer.render(run.draw_list(width, height), {.width = width, .height = height, .msaa_samples = 4})};
    }

    // The window's screenshot against the off-screen frame: the golden metric
    // and its default thresholds (3 levels; 5% small, 0.01% large errors).
    static void expect_same_picture(const fs::path& screenshot, const render::Image& expected) {
        ASSERT_TRUE(fs::exists(screenshot)) << screenshot;
        const render::Image actual = render::read_png(screenshot, 3);
        const render::GoldenDiff d = render::compare_golden(actual, expected);
        std::printf("window vs off-screen: max difference %d levels, %.4f%% small, %.4f%% large\n", d.max_d,
                    100 * d.small_share, 100 * d.large_share);
        EXPECT_TRUE(d.pass) << "window screenshot differs from the off-screen render: max " << d.max_d << " levels, "
                            << 100 * d.large_share << "% of pixels over 3 levels";
    }

    test::TempDir temp_{"plausible-view-test"};
    const fs::path& dir_ = temp_.path();
};

TEST_F(View, WithoutADisplayExits2AndSaysHowToGetAPicture) {
    const Ran r = shell("env -u DISPLAY -u WAYLAND_DISPLAY " PLAUSIBLE_EXE " view pendulum");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("no display"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("plausible render"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("plausible video"), std::string::npos) << r.out;
}

TEST_F(View, BadOptionsExit2BeforeAWindowOpens) {
    for (const char* args : {"pendulum --size 10x10", "pendulum --screenshot shot.jpg", "pendulum --exit-after -3",
                             "no-such-scene", "pendulum --dt -1", "pendulum --render-scale 0.3"}) {
        const Ran r = shell("env -u DISPLAY " PLAUSIBLE_EXE " view " + std::string(args));
        EXPECT_EQ(r.status, 2) << args << ": " << r.out;
        EXPECT_EQ(r.out.find("no display"), std::string::npos) << args << ": refused for the display, not the input";
    }
}

// A bad input script is refused before a window opens, naming file and line.
TEST_F(View, ABadInputScriptExits2NamingItsLine) {
    for (const auto& [line, expected] :
         {std::pair{"1 key Right\n0 key Left\n", ":2: a line starts with the frame"},
          std::pair{"3 key Right\n2 key Left\n", ":2: frame 2 comes after frame 3"},
          std::pair{"1 key F13\n", ":1: no key 'F13'"}, std::pair{"1 press thumb\n", ":1: press needs left"},
          std::pair{"1 move 10\n", ":1: move needs X Y"}, std::pair{"1 jump\n", ":1: no event 'jump'"},
          // Found by tools/fuzz/fuzz_input_script: NaN passed the frame's range test, then became an int.
          std::pair{"nan key Right\n", ":1: a line starts with the frame"},
          std::pair{"1 move nan inf\n", ":1: move needs X Y"}}) {
        std::ofstream(dir_ / "bad.txt") << line;
        const Ran r = shell("env -u DISPLAY " PLAUSIBLE_EXE " view pendulum --input " + (dir_ / "bad.txt").string());
        EXPECT_EQ(r.status, 2) << line << r.out;
        EXPECT_NE(r.out.find((dir_ / "bad.txt").string() + expected), std::string::npos) << r.out;
    }
    const Ran r = shell("env -u DISPLAY " PLAUSIBLE_EXE " view pendulum --input /no/such/script.txt");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("/no/such/script.txt: cannot read it"), std::string::npos) << r.out;
    // A device that never ends and a FIFO with no writer: refused, not read
    // or waited on (timeout: a wait would be a hang, not a pass).
    ASSERT_EQ(mkfifo((dir_ / "fifo.txt").c_str(), 0600), 0);
    for (const std::string& script : {std::string("/dev/zero"), (dir_ / "fifo.txt").string()}) {
        const Ran s = shell("env -u DISPLAY timeout 60 " PLAUSIBLE_EXE " view pendulum --input " + script);
        EXPECT_EQ(s.status, 2) << script << ": " << s.out;
        EXPECT_NE(s.out.find(script + ": not a regular file"), std::string::npos) << s.out;
    }
}

// --exit-after N steps one scene frame per window frame: the last one is the
// scene's frame N, bit for bit, and looks as `render` draws it.
TEST_F(View, ExitAfterShowsTheSceneFrameAsTheOffScreenRenderDrawsIt) {
    const Ran r = under_xvfb("$VIEW ragdoll --exit-after 40 --no-panel --size 480x270 --screenshot shot.png\n");
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "40") << r.out;
    const Reference ref = reference("ragdoll", 40, 480, 270);
    EXPECT_EQ(field(r.out, "state"), ref.hash) << r.out;
    expect_same_picture(dir_ / "shot.png", ref.image);
}

// Start paused, step 5, step back 2 (stored states), screenshot (P); resume
// for 60 drawn frames (one step each while scripted), pause, step once more,
// quit: each shown frame is the scene's frame, bits and picture.
TEST_F(View, KeysPauseStepAndStepBackThroughStoredStates) {
    const Ran r = play("pendulum", "--no-panel --size 480x270 --screenshot last.png", R"(
1 key Right
2 key Right
3 key Right
4 key Right
5 key Right
6 key Left
7 key Left
8 key p       # the screenshot of frame 3
9 key space   # runs from this drawn frame on: 60 steps
69 key space
70 key Right
71 key q
)");
    ASSERT_EQ(r.status, 0) << r.out;
    expect_same_picture(dir_ / "view-pendulum-3.png", reference("pendulum", 3, 480, 270).image);
    EXPECT_EQ(field(r.out, "frame"), "64") << "3, then 60 running, then 1: " << r.out;
    const Reference ref = reference("pendulum", 64, 480, 270);
    EXPECT_EQ(field(r.out, "state"), ref.hash) << r.out;
    expect_same_picture(dir_ / "last.png", ref.image);
}

// A running scene is drawn at --render-scale's fraction of the window's
// pixels per side and stretched over the window (dynamic resolution; -1, the
// default, picks the fraction frame by frame); a screenshot (P) taken while
// it runs, and the last frame, are drawn whole: each is the scene's frame as
// the off-screen render draws it at the window's size (no MSAA while running).
// --verbose prints the running frames' parts.
TEST_F(View, AtHalfScaleWhileRunningTheScreenshotAndTheLastFrameAreWhole) {
    const Ran r = play("pendulum", "--no-panel --size 480x270 --render-scale 0.5 --screenshot last.png --verbose", R"(
1 key space   # runs from here: one step a drawn frame
20 key p
30 key q
)");
    ASSERT_EQ(r.status, 0) << r.out;
    int shot_frame = -1;
    for (const auto& entry : fs::directory_iterator(dir_)) {
        std::smatch m;
        const std::string name = entry.path().filename().string();
        if (std::regex_match(name, m, std::regex("view-pendulum-([0-9]+)\\.png"))) shot_frame = std::stoi(m[1]);
    }
    ASSERT_GT(shot_frame, 0) << "no screenshot from P: " << r.out;
    EXPECT_NE(r.out.find("running frames drawn at 50-50%"), std::string::npos) << r.out;
    // Frames 2 to 29 ran, but for the screenshot's (drawn still); each is kept
    // when the next starts.
    std::smatch parts;
    ASSERT_TRUE(std::regex_search(r.out, parts,
                                  std::regex("a running frame, the mean of ([0-9]+), ms: ([0-9.]+) swap to swap; "
                                             "physics ([0-9.]+), draw list [0-9.]+, rendering ([0-9.]+)")))
        << r.out;
    EXPECT_GE(std::stoi(parts[1]), 20) << r.out;
    EXPECT_LE(std::stoi(parts[1]), 28) << r.out;
    const double frame = std::stod(parts[2]), physics = std::stod(parts[3]), rendering = std::stod(parts[4]);
    EXPECT_GT(rendering, 0.0) << r.out;
    EXPECT_GT(frame, physics + rendering) << "ms: a frame is more than its physics and its drawing: " << r.out;
    // The same frames' spread: as many, the median, 95th percentile and
    // worst in order, the worst at least the mean.
    std::smatch spread;
    ASSERT_TRUE(std::regex_search(r.out, spread,
                                  std::regex("running frames, swap to swap, ms: median ([0-9.]+), 95th percentile "
                                             "([0-9.]+), worst ([0-9.]+); ([0-9]+) of ([0-9]+) over the 25 ms budget")))
        << r.out;
    const double median = std::stod(spread[1]), p95 = std::stod(spread[2]), worst = std::stod(spread[3]);
    EXPECT_EQ(spread[5], parts[1]) << r.out;
    EXPECT_LE(std::stoi(spread[4]), std::stoi(spread[5])) << r.out;
    EXPECT_GT(median, 0.0) << r.out;
    EXPECT_LE(median, p95) << r.out;
    EXPECT_LE(p95, worst) << r.out;
    EXPECT_GE(worst + 0.05, frame) << "ms: the worst frame is at least the mean (both rounded): " << r.out;
    auto still = [](int frames) {
        const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("pendulum"));
        scenes::SceneRun run(scene);
        for (int k = 0; k < frames; ++k) run.advance();
        const auto context = render::create_context({});
        render::Renderer renderer(*context);
        return renderer.render(run.draw_list(480, 270), {.width = 480, .height = 270, .msaa_samples = 0});
    };
    expect_same_picture(dir_ / ("view-pendulum-" + std::to_string(shot_frame) + ".png"), still(shot_frame));
    expect_same_picture(dir_ / "last.png", still(std::stoi(field(r.out, "frame"))));
}

// The running scale follows the frames' times: down while a frame (swap to
// swap) is over the budget, by at most a fifth a frame, to the floor; up
// while the work before the swap has room (a tenth a frame, to 1), though
// the frame, waiting for vsync, reads longer; steady in between; still
// frames and a fixed --render-scale are never changed by it.
TEST(FrameBudget, KeepsARunningFrameWithinItsBudget) {
    using scenes::view::FrameBudget;
    constexpr double B = FrameBudget::kBudgetMs;
    FrameBudget budget(-1.0f);
    EXPECT_EQ(budget.scale(false), 1.0f);
    const float start = budget.scale(true);
    budget.frame_took(1.5 * B, 2 * B, true);  // 50 ms a frame: wants sqrt(0.85 / 2) ~ 0.65 of it
    EXPECT_LT(budget.scale(true), start);
    EXPECT_GE(budget.scale(true), 0.8f * start - FrameBudget::kStep);
    for (int k = 0; k < 20; ++k) budget.frame_took(3 * B, 4 * B, true);
    EXPECT_EQ(budget.scale(true), FrameBudget::kMinScale);
    const float low = budget.scale(true);
    budget.frame_took(0.7 * B, 0.9 * B, true);  // within the budget, the work without room: stays
    EXPECT_EQ(budget.scale(true), low);
    budget.frame_took(0.5 * B, 1.1 * B, true);   // over it (the swap's copy), though the work has room: down
    EXPECT_EQ(budget.scale(true), low);          // (at the floor)
    budget.frame_took(0.2 * B, 0.2 * B, false);  // a still frame says nothing
    EXPECT_EQ(budget.scale(true), low);
    budget.frame_took(0.3 * B, 0.67 * B, true);  // 16.7 ms a frame at vsync, 7.5 ms of work: up
    EXPECT_GT(budget.scale(true), low);
    for (int k = 0; k < 20; ++k) budget.frame_took(0.2 * B, 0.67 * B, true);
    EXPECT_EQ(budget.scale(true), 1.0f);
    budget.frame_took(0.8 * B, 1.2 * B, true);  // over the budget at 1: down
    EXPECT_LT(budget.scale(true), 1.0f);
    FrameBudget fixed(0.75f);
    fixed.frame_took(3 * B, 4 * B, true);
    EXPECT_EQ(fixed.scale(true), 0.75f);
}

// I changes the integrator live: three steps with the scene's, three with the
// next in the table, the same bits as that run made here.
TEST_F(View, IChangesTheIntegratorLive) {
    const Ran r = play("oscillator", "--no-panel --size 320x180", R"(
1 key Right
2 key Right
3 key Right
4 key i
5 key Right
6 key Right
7 key Right
8 key q
)");
    ASSERT_EQ(r.status, 0) << r.out;
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("oscillator"));
    scenes::SceneRun run(scene);
    for (int k = 0; k < 3; ++k) run.advance();
    sim::StepSettings step = run.step();
    for (std::size_t k = 0; k < sim::kIntegrators.size(); ++k) {
        if (sim::kIntegrators[k].id == step.integrator) {
            step.integrator = sim::kIntegrators[(k + 1) % sim::kIntegrators.size()].id;
            break;
        }
    }
    run.set_step(step);
    for (int k = 0; k < 3; ++k) run.advance();
    EXPECT_EQ(field(r.out, "frame"), "6") << r.out;
    EXPECT_EQ(field(r.out, "state"), run.state_hash_hex()) << r.out;
}

// A scene parameter changed in the panel rebuilds the scene from its file
// with that value: the cloth's ball shrunk to 0.3 m, then 60 steps, the same
// bits as `--set colliders[0].radius=0.3`. The script finds the panel's
// items by their labels where the panel drew them (any Dear ImGui version's
// layout): it opens "Scene parameters", ctrl+clicks colliders[0].radius's
// slider (which then takes typed text), types 0.3 and Return. (Driven by
// xdotool and sleeps, this test once clicked before the panel was laid out
// on a loaded machine; frames make it wait for exactly what it needs.)
TEST_F(View, APanelSliderRebuildsTheSceneWithItsValue) {
    std::string script = R"(
5 move @Scene parameters      # the panel has its size and place by then
6 press left
7 release left
9 move @colliders[0].radius
10 press left ctrl
11 release left
12 key ctrl+a
13 text 0.3
14 key Return
)";
    for (int k = 0; k < 60; ++k) script += std::to_string(18 + k) + " key Right\n";
    script += "78 key q\n";
    // After 1 s the cloth lies on the ball, so the ball's size is in the bits.
    auto hash_after_60 = [](const std::vector<scenes::Override>& overrides) {
        const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("cloth"), overrides);
        scenes::SceneRun run(scene);
        for (int k = 0; k < 60; ++k) run.advance();
        return run.state_hash_hex();
    };
    const Ran r = play("cloth", "--size 1280x720", script);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "60") << r.out;
    EXPECT_EQ(field(r.out, "state"), hash_after_60({{"colliders[0].radius", "0.3"}}))
        << "not the cloth over a 0.3 m ball: " << r.out;
    EXPECT_NE(field(r.out, "state"), hash_after_60({})) << "the slider changed nothing: " << r.out;
}

// A recording in the viewer: the panel's "recording frame" slider goes to
// frame 150 (the nearest stored state, then steps), and what is shown there
// is the scene's frame 150, bit for bit; replayed, it has not diverged.
TEST_F(View, ARecordingIsScrubbedToAnyFrame) {
    ASSERT_EQ(shell("cd '" + dir_.string() + "' && " PLAUSIBLE_EXE " run pendulum --frames 200 --record p.rec").status,
              0);
    const Ran r = play("p.rec", "--size 1280x720", R"(
5 move @recording frame
6 press left ctrl
7 release left
8 key ctrl+a
9 text 150
10 key Return
13 key q
)");
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "150") << r.out;
    EXPECT_EQ(field(r.out, "state"), reference("pendulum", 150, 16, 16).hash) << r.out;
    EXPECT_NE(r.out.find("identical to the recorded state hashes"), std::string::npos) << r.out;
}

// Left-drag on the pendulum's bob: the mouse spring grabs it and pulls it
// away from where the undisturbed run has it.
TEST_F(View, MouseDragGrabsTheBobAndPullsIt) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("pendulum"));
    std::size_t bob = 0;
    for (std::size_t i = 0; i < scene.model.particles.size(); ++i) {
        if (!scene.model.particles[i].pinned) bob = i;
    }
    const auto pixel = render::project_to_pixel(scenes::render_camera(scene.camera), 480, 270,
                                                scene.model.particles[bob].position.cast<float>());
    ASSERT_TRUE(pixel.has_value());
    const std::string at =
        std::to_string(static_cast<int>(pixel->x())) + " " + std::to_string(static_cast<int>(pixel->y()));
    const std::string away =
        std::to_string(static_cast<int>(pixel->x()) - 120) + " " + std::to_string(static_cast<int>(pixel->y()) - 60);
    std::string script = "1 move " + at + "\n2 press left\n3 move " + away + "\n";
    for (int k = 0; k < 30; ++k) script += std::to_string(4 + k) + " key Right\n";
    script += "34 release left\n35 key q\n";
    const Ran r = play("pendulum", "--no-panel --size 480x270", script);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("grabbed particle " + std::to_string(bob)), std::string::npos) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "30") << r.out;
    EXPECT_NE(field(r.out, "state"), reference("pendulum", 30, 16, 16).hash) << "the drag changed nothing: " << r.out;
}

}  // namespace
