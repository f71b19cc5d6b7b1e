// Golden checks prove they catch what they exist to catch: an exploding
// variant of a shipped scene fails with a verdict and a diff; one pixel of
// motion fails the image metric while the same state passes; the same scene
// twice in one process gives the same hashes and bytes.
#include "scenes/check.h"

#include "render/font.h"
#include "scenes/scene_run.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace scenes {
namespace {

namespace fs = std::filesystem;

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
        context_ = render::create_context({.backend = render::Backend::osmesa}).release();
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
    const auto r = check_scenes({"oscillator"}, {{"step.dt", "0.13333333333333333"}, {"step.integrator", "\"forward_euler\""}},
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
    for (const std::string name : {"orbit", "pendulum"}) {
        const SceneDef scene = load_scene(resolve_scene(name));
        const Filmstrip a = render_filmstrip(scene, *renderer_);
        const Filmstrip b = render_filmstrip(scene, *renderer_);
        EXPECT_EQ(a.hashes, b.hashes) << name;
        EXPECT_EQ(a.image.pixels, b.image.pixels) << name;
        EXPECT_FALSE(a.verdict.exploded()) << a.verdict.message(name);
    }
}

}  // namespace
}  // namespace scenes
