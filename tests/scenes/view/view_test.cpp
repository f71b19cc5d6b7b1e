// `plausible view` end to end: the real command in a real GLFW window on a
// virtual display (Xvfb), keys and mouse sent by xdotool, screenshots of the
// window compared with the off-screen render (the default backend) of the same
// frame, and the state it printed compared with the same frames run here.
#include "render/gl_context.h"
#include "render/golden.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scenes/draw/scene_run.h"
#include "scenes/model/scene.h"
#include "sim/integrators.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Ran {
    int status = -1;  // exit status
    std::string out;  // stdout and stderr
};

Ran shell(const std::string& command) {
    Ran r;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (p == nullptr) return r;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, n);
    const int status = pclose(p);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

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
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("plausible-view-test-" + std::to_string(getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Runs `script` (sh) on a virtual display of its own; $VIEW is the command.
    // In the sanitize build the viewer runs without LeakSanitizer: glfwTerminate
    // unloads Mesa's GLX driver (swrast_dri.so) before exit, so Mesa's
    // per-process allocations show as leaks in an "unknown module" that no
    // suppression can name. AddressSanitizer's other checks stay on.
    // Xvfb runs with -r (no key auto-repeat): on a loaded machine xdotool's
    // press and release of a key can be far enough apart for the server to
    // repeat it, and the viewer steps on every repeat (a held Right keeps
    // stepping), which made a 60-press script run 61 frames.
    Ran under_xvfb(const std::string& script) const {
        const fs::path file = dir_ / "script.sh";
        std::ofstream(file) << "export ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\"\n"
                            << "VIEW='" << PLAUSIBLE_EXE << " view'\n"
                            << script;
        return shell("cd '" + dir_.string() + "' && timeout 120 xvfb-run -a -s '-screen 0 1280x800x24 -r' sh '" +
                     file.string() + "'");
    }

    // Starts `view SCENE ARGS --paused` on the virtual display, focuses its
    // window ($win), runs `actions` (xdotool lines), presses Q and returns
    // what the viewer printed, with its exit status.
    Ran drive(const std::string& scene, const std::string& args, const std::string& actions) const {
        return under_xvfb("$VIEW " + scene + " --paused " + args + " > out.txt 2>&1 &\n" +
                          "pid=$!\n"
                          "win=$(xdotool search --sync --name 'Plausible: " +
                          scene +
                          "' | head -1)\n"
                          "xdotool windowfocus --sync \"$win\"\n"
                          "sleep 0.3\n" +
                          actions +
                          "\nxdotool key q\n"
                          "wait $pid\n"
                          "status=$?\n"
                          "cat out.txt\n"
                          "exit $status\n");
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

    fs::path dir_;
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
                             "no-such-scene", "pendulum --dt -1"}) {
        const Ran r = shell("env -u DISPLAY " PLAUSIBLE_EXE " view " + std::string(args));
        EXPECT_EQ(r.status, 2) << args << ": " << r.out;
        EXPECT_EQ(r.out.find("no display"), std::string::npos) << args << ": refused for the display, not the input";
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

// Start paused, step 5, step back 2 (stored states), screenshot (P); resume,
// pause, step once more, quit: each shown frame is the scene's frame, bits
// and picture.
TEST_F(View, KeysPauseStepAndStepBackThroughStoredStates) {
    const Ran r = drive("pendulum", "--no-panel --size 480x270 --screenshot last.png", R"(
for k in 1 2 3 4 5; do xdotool key Right; sleep 0.05; done
xdotool key Left; sleep 0.05; xdotool key Left; sleep 0.05
xdotool key p; sleep 0.3
xdotool key space; sleep 1.0; xdotool key space; sleep 0.1
xdotool key Right; sleep 0.1
)");
    ASSERT_EQ(r.status, 0) << r.out;
    expect_same_picture(dir_ / "view-pendulum-3.png", reference("pendulum", 3, 480, 270).image);
    const int last = std::stoi(field(r.out, "frame").empty() ? "0" : field(r.out, "frame"));
    EXPECT_GT(last, 4) << "Space resumed for 1 s and Right stepped once more: " << r.out;
    const Reference ref = reference("pendulum", last, 480, 270);
    EXPECT_EQ(field(r.out, "state"), ref.hash) << r.out;
    expect_same_picture(dir_ / "last.png", ref.image);
}

// I changes the integrator live: three steps with the scene's, three with the
// next in the table, the same bits as that run made here.
TEST_F(View, IChangesTheIntegratorLive) {
    const Ran r = drive("oscillator", "--no-panel --size 320x180", R"(
for k in 1 2 3; do xdotool key Right; sleep 0.05; done
xdotool key i; sleep 0.05
for k in 1 2 3; do xdotool key Right; sleep 0.05; done
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
// bits as `--set colliders[0].radius=0.3`. The clicks are where Debian's
// Dear ImGui 1.86 lays the panel out in a 1280x720 window: "Scene
// parameters", then colliders[0].radius's slider (Ctrl+click types a value;
// Return is held, as ImGui 1.86 misses a press and release in one frame).
// Each action waits for the panel to be drawn again (seconds: a sanitized or
// loaded viewer draws slowly): on such a machine the ctrl+click once landed
// before the opened section was laid out, so the field never took the keys
// and the '.' of "0.3" reached the viewer as its step key (the default cloth
// at frame 61 for 60 presses of Right).
// DISABLED (2026-12-02): in fresh-clone CI runs the click still misses the
// panel (frame 61, 2 runs of the last 4, both tries), which fails the whole
// suite; it needs a readiness signal from the viewer, not longer sleeps.
// Run it by hand: --gtest_also_run_disabled_tests.
TEST_F(View, DISABLED_APanelSliderRebuildsTheSceneWithItsValue) {
    // The script, with its waits scaled by `slow`. xdotool cannot ask the
    // viewer whether the panel has been laid out, so on a loaded machine a
    // click can still land early: then the run is tried once more with
    // twice the waits, and the assertions below judge that second run.
    auto script = [](double slow) {
        auto wait = [slow](double s) { return " sleep " + std::to_string(s * slow) + "\n"; };
        return "xdotool mousemove --window \"$win\" 960 284 click 1;" + wait(2.0) +
               "xdotool mousemove --window \"$win\" 980 498;" + wait(1.0) + "xdotool keydown ctrl;" + wait(0.2) +
               "xdotool click 1;" + wait(0.2) + "xdotool keyup ctrl;" + wait(1.0) + "xdotool key ctrl+a;" + wait(0.3) +
               "xdotool type \"0.3\";" + wait(0.1) + "xdotool keydown Return;" + wait(0.15) + "xdotool keyup Return;" +
               wait(0.5) + "for k in $(seq 60); do xdotool key Right; sleep 0.02; done\n";
    };
    // After 1 s the cloth lies on the ball, so the ball's size is in the bits.
    auto hash_after_60 = [](const std::vector<scenes::Override>& overrides) {
        const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("cloth"), overrides);
        scenes::SceneRun run(scene);
        for (int k = 0; k < 60; ++k) run.advance();
        return run.state_hash_hex();
    };
    const std::string expected = hash_after_60({{"colliders[0].radius", "0.3"}});
    Ran r = drive("cloth", "--size 1280x720", script(1.0));
    if (r.status != 0 || field(r.out, "frame") != "60" || field(r.out, "state") != expected) {
        r = drive("cloth", "--size 1280x720", script(2.0));
    }
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "60") << r.out;
    EXPECT_EQ(field(r.out, "state"), expected) << "not the cloth over a 0.3 m ball: " << r.out;
    EXPECT_NE(field(r.out, "state"), hash_after_60({})) << "the slider changed nothing: " << r.out;
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
    const Ran r = drive("pendulum", "--no-panel --size 480x270", R"(
xdotool mousemove --window "$win" )" + at + R"(; sleep 0.2
xdotool mousedown 1; sleep 0.2
xdotool mousemove --window "$win" )" + away + R"(; sleep 0.2
for k in $(seq 30); do xdotool key Right; sleep 0.02; done
xdotool mouseup 1; sleep 0.1
)");
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("grabbed particle " + std::to_string(bob)), std::string::npos) << r.out;
    EXPECT_EQ(field(r.out, "frame"), "30") << r.out;
    EXPECT_NE(field(r.out, "state"), reference("pendulum", 30, 16, 16).hash) << "the drag changed nothing: " << r.out;
}

}  // namespace
