// `plausible video` end to end through the real ffmpeg: an MP4 that ffprobe
// reads as H.264, yuv420p, BT.709, with the frame count and duration asked
// for; a GIF with its frames; a --compare video whose tiles show different
// integrators; bad options refused before anything is written.
#include "scenes/video/video.h"
#include "scenes/common/output_file.h"
#include "scenes/model/scene.h"
#include "sim/error.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command) {
    std::string out;
    FILE* p = popen(command.c_str(), "r");
    if (p == nullptr) return out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
    return out;
}

// ffprobe's value of one stream or format entry.
std::string probe(const fs::path& file, const std::string& entry) {
    std::string out = run("ffprobe -v error -count_frames -select_streams v:0 -show_entries " + entry +
                          " -of default=noprint_wrappers=1:nokey=1 '" + file.string() + "'");
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

class Video : public ::testing::Test {
protected:
    // A video of `file` in the test's folder.
    scenes::VideoOptions options(const std::string& file, int width, int height, int fps, double seconds) const {
        scenes::VideoOptions o;
        o.output = dir_ / file;
        o.width = width;
        o.height = height;
        o.fps = fps;
        o.seconds = seconds;
        return o;
    }
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("plausible-video-test-" + std::to_string(getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(Video, AnMp4IsH264Yuv420pBt709WithTheFramesAskedFor) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("oscillator"));
    const scenes::VideoOptions o = options("oscillator.mp4", 320, 240, 30, 1.0);
    const scenes::VideoStats stats = scenes::write_video(scene, {}, o);
    EXPECT_EQ(stats.frames, 30);
    ASSERT_TRUE(fs::exists(o.output));
    EXPECT_EQ(probe(o.output, "stream=codec_name"), "h264");
    EXPECT_EQ(probe(o.output, "stream=pix_fmt"), "yuv420p");
    EXPECT_EQ(probe(o.output, "stream=color_space"), "bt709");
    EXPECT_EQ(probe(o.output, "stream=width"), "320");
    EXPECT_EQ(probe(o.output, "stream=nb_read_frames"), "30");
    EXPECT_NEAR(std::stod(probe(o.output, "format=duration")), 1.0, 0.05) << "s";
    for (const auto& entry : fs::directory_iterator(dir_)) {
        EXPECT_EQ(entry.path().filename(), "oscillator.mp4") << "nothing else left behind";
    }
}

TEST_F(Video, AGifHasItsFrames) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("ballistic"));
    const scenes::VideoOptions o = options("ballistic.gif", 160, 120, 10, 1.0);
    scenes::write_video(scene, {}, o);
    EXPECT_EQ(probe(o.output, "stream=codec_name"), "gif");
    EXPECT_EQ(probe(o.output, "stream=nb_read_frames"), "10");
}

// Pixels that differ (by more than 40 levels) between the left and right
// tiles of the last frame of a 320x180 two-tile --compare video of the orbit.
long tiles_differ(const fs::path& file) {
    const std::string rgb =
        run("ffmpeg -v error -sseof -0.2 -i '" + file.string() + "' -frames:v 1 -f rawvideo -pix_fmt rgb24 -");
    EXPECT_EQ(rgb.size(), 320u * 180u * 3u);
    if (rgb.size() != 320u * 180u * 3u) return -1;
    auto pixel = [&](int x, int y, int c) { return static_cast<unsigned char>(rgb[(y * 320 + x) * 3 + c]); };
    EXPECT_LT(pixel(160, 10, 0), 60) << "outside the tiles (above them): the background";
    long differ = 0;
    for (int y = 45; y < 120; ++y) {  // two 160x90 tiles side by side, centred vertically; not their --set labels
        for (int x = 0; x < 160; ++x) {
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(pixel(x, y, c) - pixel(x + 160, y, c)));
            if (d > 40) ++differ;
        }
    }
    return differ;
}

// Two tiles: integrators, or --set variants (the same integrator at two step sizes).
TEST_F(Video, CompareShowsOneTilePerIntegratorOrVariant) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("orbit"));
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"forward_euler", "symplectic_euler"}, "forward Euler's planet is elsewhere than symplectic Euler's"},
        {{"step.dt=0.002", "step.dt=0.1"}, "the planet at dt = 0.1 s is elsewhere than at 0.002 s"}};
    for (const auto& [tiles, why] : cases) {
        scenes::VideoOptions o = options("compare.mp4", 320, 180, 10, 3.0);
        o.compare = tiles;
        // No title, numbers or plot: what differs between the tiles is where the planet is.
        scenes::write_video(scene, {{"view.hud", "false"}, {"view.energy_plot", "false"}}, o);
        EXPECT_GT(tiles_differ(o.output), 50) << why << " after 3 s";
    }
}

// The ffmpeg process writing `name` (its command line holds the temporary
// file's name), or 0.
pid_t ffmpeg_writing(const std::string& name) {
    for (const auto& entry : fs::directory_iterator("/proc")) {
        const std::string pid = entry.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string comm, cmdline;
        std::getline(std::ifstream(entry.path() / "comm"), comm);
        std::getline(std::ifstream(entry.path() / "cmdline"), cmdline, '\x01');
        if (comm == "ffmpeg" && cmdline.find(name) != std::string::npos) return static_cast<pid_t>(std::stoi(pid));
    }
    return 0;
}

// ffmpeg killed while frames are still coming: the next write fails (a broken
// pipe, not a SIGPIPE that kills us), the error says so, and neither the video
// nor its temporary or log file is left behind.
TEST_F(Video, FfmpegKilledMidwayIsAnErrorAndLeavesNoFile) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("oscillator"));
    const scenes::VideoOptions o = options("killed.mp4", 320, 180, 30, 60.0);  // 1800 frames: ample time to kill
    std::atomic<bool> finished{false};
    std::atomic<pid_t> killed{0};
    std::thread killer([&] {
        for (int k = 0; k < 3000 && !finished; ++k) {
            if (const pid_t pid = ffmpeg_writing("killed.mp4.tmp-" + std::to_string(getpid())); pid != 0) {
                std::this_thread::sleep_for(std::chrono::milliseconds(200));  // a few frames in
                ::kill(pid, SIGKILL);
                killed = pid;
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    std::string message;
    try {
        scenes::write_video(scene, {}, o);
    } catch (const std::runtime_error& e) {
        message = e.what();
    }
    finished = true;
    killer.join();
    ASSERT_NE(killed.load(), 0) << "never saw the ffmpeg process";
    EXPECT_NE(message.find("ffmpeg"), std::string::npos) << "no error, or one that does not name ffmpeg: " << message;
    std::printf("error after ffmpeg was killed: %s\n", message.c_str());
    EXPECT_FALSE(fs::exists(o.output));
    for (const auto& entry : fs::directory_iterator(dir_)) ADD_FAILURE() << "left behind: " << entry.path();
}

// The same through the command: exit 2, a message naming the problem, no file.
TEST_F(Video, TheCommandExits2OnBadArgumentsWithoutAFile) {
    const std::string out = (dir_ / "v.mp4").string();
    for (const std::string& args :
         {"oscillator -o " + out + " --size 321x180", "oscillator -o " + out + " --compare rk4,runge_kutta",
          "oscillator -o " + (dir_ / "nowhere" / "v.mp4").string(), "oscillator -o " + out + " --fps 0",
          "no-such-scene -o " + out, "oscillator -o " + out + " --backend vulkan"}) {
        const std::string result = run(std::string(PLAUSIBLE_EXE) + " video " + args + " 2>&1; echo \"status=$?\"");
        EXPECT_NE(result.find("status=2"), std::string::npos) << args << ": " << result;
        EXPECT_NE(result.find("error"), std::string::npos) << args << ": " << result;
    }
    EXPECT_TRUE(fs::is_empty(dir_)) << "no file written";
}

// --backend list says what this machine has, scene or not, and exits 0;
// auto (the default) takes it: here llvmpipe unless a GPU is found.
TEST_F(Video, BackendListShowsTheBackendsAndTheEglDevicesFound) {
    for (const std::string command : {"video --backend list", "render --backend list", "check --backend list"}) {
        const std::string result = run(std::string(PLAUSIBLE_EXE) + " " + command + " 2>&1; echo \"status=$?\"");
        EXPECT_NE(result.find("status=0"), std::string::npos) << command << ": " << result;
        for (const char* fragment : {"osmesa", "egl:", "gpu:", "EGL devices found: ", "fastest here: "}) {
            EXPECT_NE(result.find(fragment), std::string::npos) << command << ": " << fragment << " in " << result;
        }
    }
    EXPECT_TRUE(fs::is_empty(dir_)) << "no file written";
}

// A GPU's frame is judged against the shipped (llvmpipe) goldens, never
// written as one: check --update with the gpu backend exits 2 before drawing.
TEST_F(Video, CheckRefusesToBlessTheShippedGoldensWithTheGpuBackend) {
    const std::string report = (dir_ / "report").string();
    const std::string result =
        run(std::string(PLAUSIBLE_EXE) + " check oscillator --backend gpu --update all --report " + report +
            " 2>&1; echo \"status=$?\"");
    EXPECT_NE(result.find("status=2"), std::string::npos) << result;
    EXPECT_NE(result.find("would bless a GPU's frames"), std::string::npos) << result;
    EXPECT_TRUE(fs::is_empty(dir_)) << "no report written";
}

TEST_F(Video, BadOptionsAreRefusedWithoutAFile) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("oscillator"));
    auto refused = [&](scenes::VideoOptions o, const std::string& fragment) {
        try {
            scenes::write_video(scene, {}, o);
        } catch (const sim::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
            return;
        } catch (const scenes::OutputError& e) {  // the output path's (exit 2 too)
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
            return;
        }
        ADD_FAILURE() << "accepted: " << fragment;
    };
    const scenes::VideoOptions o = options("bad.mp4", 1280, 720, 30, 0.5);
    scenes::VideoOptions odd = o;
    odd.width = 321;
    refused(odd, "--size must be even");
    scenes::VideoOptions unknown = o;
    unknown.compare = {"rk4", "runge_kutta"};
    refused(unknown, "unknown integrator 'runge_kutta'");
    scenes::VideoOptions variant = o;
    variant.compare = {"step.dt=0.01", "step.nosuch=1"};
    refused(variant, "--compare step.nosuch=1");
    scenes::VideoOptions nowhere = o;
    nowhere.output = dir_ / "no" / "such" / "folder" / "v.mp4";
    refused(nowhere, "folder is not a folder");
    scenes::VideoOptions avi = o;
    avi.output = dir_ / "bad.avi";
    refused(avi, "must end in .mp4 or .gif");
    // Without --seconds the video shows the whole scene, held to the same
    // hour: 1e7 frames of 10 s once made 1.2e10 video frames at 30 fps,
    // more than an int holds, and a video of one frame.
    scenes::SceneDef endless = scene;
    endless.frames = 10'000'000;
    endless.step.dt = 10.0;
    try {
        scenes::write_video(endless, {}, options("endless.mp4", 64, 36, 30, 0.0));
        ADD_FAILURE() << "accepted a scene of 1e8 s without --seconds";
    } catch (const sim::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("runs 1e+08 s (10000000 frames of 10 s); a video shows at most 3600 s: "
                                             "give --seconds"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(fs::is_empty(dir_)) << "no file written";
}

}  // namespace
