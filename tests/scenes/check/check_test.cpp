// Golden checks prove they catch what they exist to catch: an exploding
// variant of a shipped scene fails with a verdict and a diff; one pixel of
// motion fails the image metric while the same state passes; the same scene
// twice in one process gives the same hashes and bytes.
#include "scenes/check/check.h"

#include "render/font.h"
#include "scenes/draw/scene_run.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace scenes {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path results(const std::string& name) {
    const char* root = std::getenv("PLAUSIBLE_TEST_RESULTS");
    const fs::path dir = fs::path(root != nullptr ? root : fs::temp_directory_path().string()) / "check_test" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

class CheckTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        context_ = render::create_context({.backend = render::default_backend()}).release();
        renderer_ = new render::Renderer(*context_);
    }
    static void TearDownTestSuite() {
        delete renderer_;
        delete context_;
    }
    static render::GlContext* context_;
    static render::Renderer* renderer_;
};
render::GlContext* CheckTest::context_ = nullptr;
render::Renderer* CheckTest::renderer_ = nullptr;

TEST_F(CheckTest, ForwardEulerAtEightTimesTheStepExplodesAndFails) {
    const fs::path report = results("perturbed");
    const fs::path golden = report / "golden-untouched";
    fs::create_directories(golden);
    fs::copy(default_golden_dir() / "oscillator.png", golden / "oscillator.png");
    fs::copy(default_golden_dir() / "oscillator.json", golden / "oscillator.json");
    CheckOptions options;
    options.update = UpdateMode::changed;  // even when asked, an exploded scene is never blessed
    options.golden_dir = golden;
    options.report_dir = report;
    const auto r =
        check_scenes({"oscillator"}, {{"step.dt", "0.13333333333333333"}, {"step.integrator", "\"forward_euler\""}},
                     options, *renderer_, context_->fingerprint());
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].status, SceneCheck::Status::exploded) << r[0].message;
    EXPECT_NE(r[0].message.find("oscillator: exploded at frame"), std::string::npos) << r[0].message;
    ASSERT_FALSE(r[0].actual_png.empty());
    ASSERT_FALSE(r[0].diff_png.empty()) << "the exploded strip keeps the golden's layout, so it has a diff";
    EXPECT_TRUE(fs::is_regular_file(report / r[0].actual_png));
    EXPECT_TRUE(fs::is_regular_file(report / r[0].diff_png));
    ASSERT_TRUE(r[0].image.has_value());
    EXPECT_FALSE(r[0].image->pass) << r[0].image->summary;
    EXPECT_TRUE(fs::exists(report / "index.html"));
    EXPECT_EQ(render::read_png(golden / "oscillator.png", 3).pixels,
              render::read_png(default_golden_dir() / "oscillator.png", 3).pixels)
        << "the golden was not rewritten";
}

TEST_F(CheckTest, OnePixelOfMotionFailsTheSameStatePasses) {
    const SceneDef scene = load_scene(resolve_scene("ballistic"));
    SceneRun run(scene);
    for (int i = 0; i < 20; ++i) run.advance();
    const int w = 320, h = 240;
    const render::RenderSettings settings{.width = w, .height = h};
    render::DrawList list = run.draw_list(w, h);
    const render::Image frozen = renderer_->render(list, settings);
    EXPECT_TRUE(render::compare_golden(renderer_->render(run.draw_list(w, h), settings), frozen).pass);
    // Move the first sphere by one pixel's worth of world: its distance from
    // the eye times the angle one pixel spans.
    render::Sphere& s = list.spheres.front();
    const float distance = (s.center - list.camera.eye).norm();
    const float pixel = distance * 2.0f * std::tan(0.5f * list.camera.fov_y_deg * 3.14159265f / 180.0f) / h;  // m
    s.center.x() += pixel;
    const render::GoldenDiff d = render::compare_golden(renderer_->render(list, settings), frozen);
    EXPECT_FALSE(d.pass) << d.summary;
}

TEST_F(CheckTest, SameSceneTwiceInOneProcessGivesTheSameHashesAndBytes) {
    for (const std::string name : {"orbit", "pendulum", "stack"}) {
        const SceneDef scene = load_scene(resolve_scene(name));
        const Filmstrip a = render_filmstrip(scene, *renderer_);
        const Filmstrip b = render_filmstrip(scene, *renderer_);
        EXPECT_EQ(a.hashes, b.hashes) << name;
        EXPECT_EQ(a.image.pixels, b.image.pixels) << name;
        EXPECT_FALSE(a.verdict.exploded()) << a.verdict.message(name);
    }
}

// A scratch golden directory holding copies of the shipped goldens of `names`.
fs::path golden_copy(const fs::path& dir, const std::vector<std::string>& names) {
    fs::create_directories(dir);
    for (const std::string& name : names) {
        for (const char* ext : {".png", ".json"}) {
            fs::copy_file(default_golden_dir() / (name + ext), dir / (name + ext));
        }
    }
    return dir;
}

// Paints a side x side px red square (default 40: 1600 pixels with a large
// error, about 0.3% of a four-tile strip, above the default 0.01%) into a
// golden image, its corner at (100, 100).
void tamper(const fs::path& png, int side = 40) {
    render::Image image = render::read_png(png, 3);
    for (int y = 100; y < 100 + side; ++y) {
        for (int x = 100; x < 100 + side; ++x) {
            std::uint8_t* p = image.at(x, y);
            p[0] = 255;
            p[1] = 0;
            p[2] = 0;
        }
    }
    std::ofstream(png, std::ios::binary) << render::encode_png(image);
}

json read_json(const fs::path& file) {
    std::ifstream in(file);
    return json::parse(in);
}

void write_json(const fs::path& file, const json& j) { std::ofstream(file) << j.dump(2) << "\n"; }

// A scratch golden directory with goldens of `names` drawn by this renderer
// (not the shipped ones, which another Mesa draws a little differently), for
// tests that count differing pixels.
fs::path golden_fresh(const fs::path& dir, const std::vector<std::string>& names, render::Renderer& renderer,
                      const render::Fingerprint& fingerprint) {
    CheckOptions options{.update = UpdateMode::missing, .golden_dir = dir, .report_dir = dir / "report"};
    for (const SceneCheck& c : check_scenes(names, {}, options, renderer, fingerprint)) {
        EXPECT_EQ(c.status, SceneCheck::Status::updated) << c.scene << ": " << c.message;
    }
    return dir;
}

TEST_F(CheckTest, PerSceneThresholdsNeedAReasonAndAreApplied) {
    const fs::path report = results("thresholds");
    const fs::path golden = golden_fresh(report / "golden", {"ballistic"}, *renderer_, context_->fingerprint());
    tamper(golden / "ballistic.png");
    CheckOptions options{.update = UpdateMode::none, .golden_dir = golden, .report_dir = report};

    auto r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    ASSERT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;
    EXPECT_EQ(r[0].message.rfind("rendering changed, physics identical", 0), 0u) << r[0].message;
    ASSERT_TRUE(r[0].image.has_value());
    EXPECT_EQ(r[0].image->large_pixels, 1600u) << "40 x 40 px painted over";
    EXPECT_EQ(r[0].image->large_box.x0, 100);
    EXPECT_EQ(r[0].image->large_box.y1, 140) << "half-open box";

    // Looser thresholds without a reason are refused...
    json j = read_json(golden / "ballistic.json");
    j["thresholds"]["large_share"] = 0.01;
    write_json(golden / "ballistic.json", j);
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::error);
    EXPECT_NE(r[0].message.find("\"thresholds_reason\" is missing"), std::string::npos) << r[0].message;

    // ...and with one they apply: 0.3% of large errors is now within 1%.
    j["thresholds_reason"] = "test: a 40 px square is tolerated";
    write_json(golden / "ballistic.json", j);
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
}

// Physics only: nothing rendered, the state hashes judged alone. A painted
// golden image does not matter; a changed step does; goldens are never
// written.
TEST(CheckPhysics, JudgesTheStateHashesAloneAndWritesNoGolden) {
    const fs::path report = results("physics-only");
    const fs::path golden = golden_copy(report / "golden", {"ballistic"});
    tamper(golden / "ballistic.png");
    CheckOptions options{.update = UpdateMode::none, .golden_dir = golden, .report_dir = report};

    auto r = check_physics({"ballistic"}, {}, options);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
    EXPECT_FALSE(r[0].image.has_value()) << "no image compared";
    EXPECT_TRUE(r[0].actual_png.empty());
    EXPECT_TRUE(fs::exists(report / "report.json"));

    r = check_physics({"ballistic"}, {{"step.dt", "0.01"}}, options);
    EXPECT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;
    EXPECT_EQ(r[0].message.rfind("physics changed at checkpoint 1", 0), 0u) << r[0].message;

    options.update = UpdateMode::changed;
    EXPECT_THROW(check_physics({"ballistic"}, {}, options), sim::InputError);
}

// check --shard I/N: the N parts cover every scene once, in order, their
// sizes within one of each other (some empty when N exceeds the scenes);
// a shard's report holds its scenes alone and says which part it is.
TEST(CheckShard, TheShardsCoverEverySceneOnceInEqualParts) {
    const std::vector<std::string> all = catalog();
    for (int n : {1, 2, 3, 4, 7, 21, 30}) {
        std::vector<std::string> joined;
        std::size_t smallest = all.size(), largest = 0;
        for (int i = 1; i <= n; ++i) {
            const std::vector<std::string> part = shard_of(all, i, n);
            joined.insert(joined.end(), part.begin(), part.end());
            smallest = std::min(smallest, part.size());
            largest = std::max(largest, part.size());
        }
        EXPECT_EQ(joined, all) << n << " shards";
        EXPECT_LE(largest - smallest, 1u) << n << " shards";
    }
    for (auto [i, n] : {std::pair{0, 3}, std::pair{4, 3}, std::pair{1, 0}, std::pair{-1, -1}}) {
        EXPECT_THROW(shard_of(all, i, n), sim::InputError) << i << "/" << n;
    }

    const fs::path report = results("shard");
    CheckOptions options{.report_dir = report, .shard = {.index = 2, .count = 3, .of = 6}};
    const std::vector<std::string> six = {"ballistic", "oscillator", "orbit", "pendulum", "rope-stiff", "explosion"};
    const auto r = check_physics(shard_of(six, 2, 3), {}, options);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].scene, "orbit");
    EXPECT_EQ(r[1].scene, "pendulum");
    std::ifstream in(report / "report.json");
    const json j = json::parse(in);
    EXPECT_EQ(j.at("scenes").size(), 2u);
    EXPECT_EQ(j.at("shard").at("index"), 2);
    EXPECT_EQ(j.at("shard").at("count"), 3);
}

// A golden drawn by another renderer (another Mesa, LLVM or GPU) is judged
// with ten times the large-error share, and the verdict says so; by this
// renderer, with the golden's own thresholds.
TEST_F(CheckTest, AGoldenFromAnotherRendererIsJudgedWithItsTolerance) {
    const fs::path report = results("other-renderer");
    const fs::path golden = golden_fresh(report / "golden", {"ballistic"}, *renderer_, context_->fingerprint());
    tamper(golden / "ballistic.png", 10);  // 100 px: about 0.02%, over 0.01% and within 0.1%
    CheckOptions options{.update = UpdateMode::none, .golden_dir = golden, .report_dir = report};
    auto r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;
    EXPECT_EQ(r[0].message.find("another renderer"), std::string::npos) << r[0].message;

    // Another backend on the same Mesa draws the same pixels: the golden's
    // tolerance, and a failure names both fingerprints.
    json j = read_json(golden / "ballistic.json");
    const json drawn_here = j;
    j["fingerprint"]["summary"] = "egl-test | " + context_->fingerprint().renderer;
    write_json(golden / "ballistic.json", j);
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;
    EXPECT_NE(
        r[0].message.find("the renderer differs from the golden's (egl-test | " + context_->fingerprint().renderer +
                          " in the golden, " + context_->fingerprint().summary() + " here)"),
        std::string::npos)
        << r[0].message;
    j = drawn_here;

    j["fingerprint"]["version"] = "4.5 (Core Profile) Mesa 99.0.0-test";
    write_json(golden / "ballistic.json", j);
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
    EXPECT_NE(r[0].message.find("drawn by another renderer than the golden's"), std::string::npos) << r[0].message;
    // What differs, the golden's and this renderer's (the renderer string is the same: not named)
    EXPECT_NE(r[0].message.find("(GL_VERSION 4.5 (Core Profile) Mesa 99.0.0-test in the golden, " +
                                context_->fingerprint().version + " here)"),
              std::string::npos)
        << r[0].message;
    EXPECT_EQ(r[0].message.find("GL_RENDERER"), std::string::npos) << r[0].message;
    EXPECT_NE(r[0].message.find("up to 0.1%"), std::string::npos) << r[0].message;

    tamper(golden / "ballistic.png");  // 1600 px, 0.3%: over another renderer's tolerance too
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;
}

// A golden made on another architecture: its hashes cannot be the same bits
// (another libm, an ODE built with fused multiply-adds), so check judges by
// the image alone and says so, instead of crying "physics changed"; a
// physics-only check, which has nothing else to judge by, refuses.
TEST_F(CheckTest, AGoldenFromAnotherArchitectureIsJudgedByItsImageAlone) {
    const fs::path report = results("other-arch");
    const fs::path golden = golden_copy(report / "golden", {"ballistic"});
    json j = read_json(golden / "ballistic.json");
    ASSERT_FALSE(j.value("arch", "").empty()) << "goldens record the architecture they were made on";
    j["arch"] = "aarch64-test";
    j["checkpoints"][1]["state_hash"] = "0123456789abcdef";  // a hash the other machine would have made
    write_json(golden / "ballistic.json", j);
    CheckOptions options{.update = UpdateMode::none, .golden_dir = golden, .report_dir = report};

    auto r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
    EXPECT_NE(r[0].message.find("not comparable across architectures"), std::string::npos) << r[0].message;
    EXPECT_NE(r[0].message.find("aarch64-test"), std::string::npos) << r[0].message;
    EXPECT_EQ(read_json(report / "report.json")["scenes"][0]["hashes_compared"], false);

    tamper(golden / "ballistic.png");  // the image still judges
    r = check_scenes({"ballistic"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::fail) << r[0].message;

    r = check_physics({"ballistic"}, {}, options);
    EXPECT_EQ(r[0].status, SceneCheck::Status::error) << r[0].message;
    EXPECT_NE(r[0].message.find("run the full check"), std::string::npos) << r[0].message;
}

TEST_F(CheckTest, UpdateChangedRewritesOnlyTheFailingScenes) {
    const fs::path report = results("update-changed");
    const fs::path golden =
        golden_fresh(report / "golden", {"ballistic", "pendulum"}, *renderer_, context_->fingerprint());
    const std::vector<std::uint8_t> fresh_pendulum = render::read_png(golden / "pendulum.png", 3).pixels;
    tamper(golden / "pendulum.png");
    json reasoned = read_json(golden / "pendulum.json");
    reasoned["thresholds"]["small_share"] = 0.06;
    reasoned["thresholds_reason"] = "test: kept across a rewrite";
    write_json(golden / "pendulum.json", reasoned);
    const auto untouched_png = fs::last_write_time(golden / "ballistic.png");
    const auto untouched_json = fs::last_write_time(golden / "ballistic.json");

    // `missing` leaves a failing golden alone (and fails).
    CheckOptions options{.update = UpdateMode::missing, .golden_dir = golden, .report_dir = report};
    auto r = check_scenes({"ballistic", "pendulum"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
    EXPECT_EQ(r[1].status, SceneCheck::Status::fail) << r[1].message;

    options.update = UpdateMode::changed;
    r = check_scenes({"ballistic", "pendulum"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass) << r[0].message;
    EXPECT_EQ(r[1].status, SceneCheck::Status::updated) << r[1].message;
    EXPECT_EQ(fs::last_write_time(golden / "ballistic.png"), untouched_png) << "a passing golden is not rewritten";
    EXPECT_EQ(fs::last_write_time(golden / "ballistic.json"), untouched_json);
    // The rewritten golden is what this renderer drew before (rendering is
    // deterministic), and the scene's own thresholds and reason survive.
    EXPECT_EQ(render::read_png(golden / "pendulum.png", 3).pixels, fresh_pendulum);
    const json after = read_json(golden / "pendulum.json");
    EXPECT_EQ(after["thresholds_reason"], "test: kept across a rewrite");
    EXPECT_EQ(after["thresholds"]["small_share"], 0.06);

    options.update = UpdateMode::none;
    r = check_scenes({"ballistic", "pendulum"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::pass);
    EXPECT_EQ(r[1].status, SceneCheck::Status::pass) << r[1].message;
}

TEST_F(CheckTest, AMissingGoldenIsNotAPassAndUpdateMissingWritesIt) {
    const fs::path report = results("missing");
    const fs::path golden = report / "golden";
    fs::create_directories(golden);
    CheckOptions options{.update = UpdateMode::none, .golden_dir = golden, .report_dir = report};
    auto r = check_scenes({"orbit"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::missing);
    EXPECT_FALSE(fs::exists(golden / "orbit.png")) << "nothing is blessed without --update";
    options.update = UpdateMode::missing;
    r = check_scenes({"orbit"}, {}, options, *renderer_, context_->fingerprint());
    EXPECT_EQ(r[0].status, SceneCheck::Status::updated);
    EXPECT_EQ(read_json(golden / "orbit.json")["checkpoints"],
              read_json(default_golden_dir() / "orbit.json")["checkpoints"]);
}

}  // namespace
}  // namespace scenes
