// The renderer, on the default off-screen backend (OSMesa where the build has
// it, else EGL; EGL compared with OSMesa where both are): pixels asserted
// against predictions computed here, determinism, bad input, and the lecture
// scene written to PNG for a person to look at.
#include "render/renderer.h"

#include "render/font.h"
#include "render/image.h"
#include "tests/render/draw_lists.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace render {
namespace {

namespace fs = std::filesystem;

// A result worth looking at, as a PNG (tests write it plainly).
void save_png(const fs::path& path, const Image& image) { std::ofstream(path, std::ios::binary) << encode_png(image); }

// Where the test leaves its pictures: $PLAUSIBLE_TEST_RESULTS/render.
fs::path results_dir() {
    const char* root = std::getenv("PLAUSIBLE_TEST_RESULTS");
    fs::path dir = fs::path(root != nullptr ? root : fs::temp_directory_path().string()) / "render";
    fs::create_directories(dir);
    return dir;
}

// The pixel a world point projects to, derived here from the camera's basis
// (not from the renderer's matrices): x_c, y_c, z_c are the point's
// coordinates along the camera's right, up and forward axes; the image plane
// at unit distance spans tan(fov/2) vertically.
Vec2 expected_pixel(const Camera& c, int w, int h, const Vec3& p) {
    const Vec3 forward = (c.target - c.eye).normalized();
    const Vec3 right = forward.cross(c.up).normalized();
    const Vec3 up = right.cross(forward);
    const Vec3 d = p - c.eye;
    const float half_h = std::tan(0.5f * c.fov_y_deg * std::numbers::pi_v<float> / 180.0f);
    const float half_w = half_h * static_cast<float>(w) / static_cast<float>(h);
    const float nx = d.dot(right) / d.dot(forward) / half_w;  // -1..1 across the image
    const float ny = d.dot(up) / d.dot(forward) / half_h;
    return Vec2((nx * 0.5f + 0.5f) * static_cast<float>(w), (0.5f - ny * 0.5f) * static_cast<float>(h));
}

Rgba8 at(const Image& image, const Vec2& p) {
    return image.pixel(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())));
}

float luminance(Rgba8 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

std::uint8_t to8(float v) { return static_cast<std::uint8_t>(std::lround(v * 255.0f)); }

class RendererTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        context_ = create_context({.backend = default_backend()}).release();
        renderer_ = new Renderer(*context_);
    }
    static void TearDownTestSuite() {
        delete renderer_;
        delete context_;
    }
    static DrawList empty_scene() {
        DrawList list;
        list.ground.enabled = false;
        list.camera.eye = Vec3(0, 0, 5);
        list.camera.target = Vec3::Zero();
        return list;
    }
    static GlContext* context_;
    static Renderer* renderer_;
};
GlContext* RendererTest::context_ = nullptr;
Renderer* RendererTest::renderer_ = nullptr;

TEST_F(RendererTest, ClearColourFillsAnEmptyScene) {
    DrawList list = empty_scene();
    list.background = Color{0.2f, 0.4f, 0.6f, 1};
    const Image image = renderer_->render(list, {.width = 64, .height = 48});
    ASSERT_EQ(image.width, 64);
    ASSERT_EQ(image.height, 48);
    for (const auto& [x, y] : {std::pair{0, 0}, {63, 0}, {0, 47}, {63, 47}, {32, 24}}) {
        EXPECT_EQ(image.pixel(x, y), (Rgba8{to8(0.2f), to8(0.4f), to8(0.6f), 255})) << "at " << x << "," << y;
    }
}

TEST_F(RendererTest, SphereShowsItsColourAtItsProjectedCentreAndNothingElsewhere) {
    DrawList list = empty_scene();
    list.camera.eye = Vec3(1.0f, 0.8f, 5.0f);
    list.camera.target = Vec3(0.3f, 0.0f, 0.0f);
    list.light.shadows = false;
    list.light.direction = list.camera.target - list.camera.eye;  // lit from the camera: the centre is brightest
    list.light.specular = 0;  // no white highlight at the centre: the pixel is the sphere's own colour
    const Vec3 centre(0.9f, 0.3f, -0.5f);
    list.spheres.push_back(Sphere{centre, 0.4f, Look{Color{0.9f, 0.1f, 0.1f, 1}}});
    const int w = 160, h = 120;
    const Image image = renderer_->render(list, {.width = w, .height = h});

    const Rgba8 c = at(image, expected_pixel(list.camera, w, h, centre));
    EXPECT_GT(c.r, 150) << "red channel at the projected centre";
    EXPECT_LT(c.g, 90);
    EXPECT_LT(c.b, 90);
    // Beyond the sphere's radius (0.4 m, about 15 px here) the sky is untouched.
    const Rgba8 sky{to8(list.background.r), to8(list.background.g), to8(list.background.b), 255};
    EXPECT_EQ(at(image, expected_pixel(list.camera, w, h, centre + Vec3(0.0f, 0.9f, 0.0f))), sky);
    EXPECT_EQ(at(image, expected_pixel(list.camera, w, h, centre - Vec3(1.0f, 0.0f, 0.0f))), sky);
    EXPECT_EQ(image.pixel(2, 2), sky);
}

TEST_F(RendererTest, ShadowOnTheGroundIsDarkerThanLitGround) {
    DrawList list;
    list.camera.eye = Vec3(0.0f, 4.0f, 6.0f);
    list.camera.target = Vec3(0.0f, 0.0f, 0.0f);
    list.ground.line_color = list.ground.color;  // no grid lines where the pixels are read
    list.light.direction = Vec3(1.0f, -1.0f, 0.0f);
    // A sphere 1.5 m up: the light travels 1 m sideways per metre down, so its
    // shadow falls 1.5 m to the right of the point below it.
    list.spheres.push_back(Sphere{Vec3(-0.75f, 1.5f, 0.0f), 0.5f, Look{Color{0.5f, 0.5f, 0.5f, 1}}});
    const int w = 200, h = 150;
    const Image image = renderer_->render(list, {.width = w, .height = h});
    const Rgba8 shadow = at(image, expected_pixel(list.camera, w, h, Vec3(0.75f, 0.0f, 0.0f)));
    const Rgba8 lit = at(image, expected_pixel(list.camera, w, h, Vec3(2.0f, 0.0f, 1.0f)));
    EXPECT_LT(luminance(shadow), luminance(lit) - 30.0f)
        << "shadow luminance " << luminance(shadow) << ", lit ground " << luminance(lit) << " (8-bit levels)";
}

// The shadow map is drawn again only when a caster or the light changed:
// a list that differs elsewhere (its text) reuses it, and gives what a fresh
// renderer draws; a moved caster or a turned light too (the shadow moves
// with it).
TEST_F(RendererTest, TheShadowMapIsReusedOnlyWhileNoCasterMoved) {
    DrawList list = testing::lecture_scene();
    const RenderSettings settings{.width = 240, .height = 180, .msaa_samples = 4};
    const Image first = renderer_->render(list, settings);
    EXPECT_FALSE(renderer_->last_frame().shadow_reused);
    DrawList retitled = list;
    retitled.texts.front().text = "another title";
    const Image again = renderer_->render(retitled, settings);
    EXPECT_TRUE(renderer_->last_frame().shadow_reused);
    EXPECT_FALSE(renderer_->last_frame().frame_reused);
    {
        Renderer fresh(*context_);
        EXPECT_EQ(again.pixels, fresh.render(retitled, settings).pixels) << "as a fresh renderer draws it";
    }

    ASSERT_FALSE(list.spheres.empty());
    DrawList moved = list;
    moved.spheres.front().center += Vec3(0.4f, 0.0f, 0.3f);
    DrawList turned = list;
    turned.light.direction = Vec3(1.0f, -1.0f, 0.2f);
    for (const DrawList* changed : {&moved, &turned}) {
        const Image image = renderer_->render(*changed, settings);
        EXPECT_FALSE(renderer_->last_frame().shadow_reused);
        Renderer fresh(*context_);
        EXPECT_EQ(image.pixels, fresh.render(*changed, settings).pixels) << "as a fresh renderer draws it";
        EXPECT_NE(image.pixels, first.pixels);
    }
}

TEST_F(RendererTest, GhostIsLighterThanItsSolidTwinAndSeeThrough) {
    DrawList list = empty_scene();  // the default light sky
    list.light.shadows = false;
    list.light.direction = Vec3(0, 0, -1);
    const Color blue{0.1f, 0.2f, 0.7f, 1};
    list.spheres.push_back(Sphere{Vec3(-1.2f, 0.6f, 0), 0.5f, Look{blue, false}});
    list.spheres.push_back(Sphere{Vec3(0.0f, 0.6f, 0), 0.5f, Look{blue, true}});
    // A second ghost in front of a dark green wall: what is behind shows through.
    list.spheres.push_back(Sphere{Vec3(1.2f, 0.6f, 0), 0.5f, Look{blue, true}});
    list.boxes.push_back(Box{Vec3(1.2f, 0.6f, -1.5f), Vec3(0.8f, 0.8f, 0.1f), Eigen::Quaternionf::Identity(),
                             Look{Color{0.1f, 0.5f, 0.1f, 1}}});
    const int w = 240, h = 120;
    const Image image = renderer_->render(list, {.width = w, .height = h});
    const Rgba8 solid = at(image, expected_pixel(list.camera, w, h, Vec3(-1.2f, 0.6f, 0)));
    const Rgba8 ghost = at(image, expected_pixel(list.camera, w, h, Vec3(0.0f, 0.6f, 0)));
    const Rgba8 ghost_over_wall = at(image, expected_pixel(list.camera, w, h, Vec3(1.2f, 0.6f, 0)));
    EXPECT_GT(luminance(ghost), luminance(solid) + 20.0f)
        << "ghost " << luminance(ghost) << " vs solid " << luminance(solid) << " (8-bit luminance)";
    EXPECT_GT(ghost.b, ghost.r) << "a ghost keeps its hue";
    // Over the wall, the wall's red-less green comes through the ghost.
    EXPECT_LT(ghost_over_wall.r + 40, ghost.r)
        << "ghost over sky r " << int(ghost.r) << ", over the wall " << int(ghost_over_wall.r) << " (8-bit levels)";
}

TEST_F(RendererTest, TextPixelsStayInsideTheTextBox) {
    DrawList list = empty_scene();
    list.background = Color{1, 1, 1, 1};
    const Text text{"Plausible 42", Vec2(20, 30), 24.0f, Color{0, 0, 0, 1}};
    list.texts.push_back(text);
    const Image image = renderer_->render(list, {.width = 240, .height = 90});
    const TextBox box = Font::default_font().measure(text.text, text.size);
    int inside = 0, outside = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.pixel(x, y).r > 200) continue;  // background
            const bool in = x >= 20 - 2 && x <= 20 + box.width + 2 && y >= 30 - 2 && y <= 30 + box.height + 2;
            (in ? inside : outside)++;
        }
    }
    EXPECT_GT(inside, 100) << "dark pixels inside the " << box.width << " x " << box.height << " px box";
    EXPECT_EQ(outside, 0) << "dark pixels outside the text box";
}

TEST_F(RendererTest, TheSameListGivesTheSameBytes) {
    for (int samples : {0, 4}) {
        DrawList list = testing::lecture_scene();
        testing::place_plot(list, 320, 240);
        const RenderSettings settings{.width = 320, .height = 240, .msaa_samples = samples};
        const Image a = renderer_->render(list, settings);
        renderer_->render(testing::sphere_field(50), settings);  // something else in between
        const Image b = renderer_->render(list, settings);
        EXPECT_EQ(a.pixels, b.pixels) << "MSAA " << samples;
    }
}

// Timing a frame pass by pass (video --verbose, bench_render) changes no
// pixel, and gives each pass that drew something a time; off, none.
TEST_F(RendererTest, PassTimesAreMeasuredOnlyWhenAskedAndChangeNoPixel) {
    DrawList list = testing::lecture_scene();
    testing::place_plot(list, 320, 240);
    const RenderSettings settings{.width = 320, .height = 240, .msaa_samples = 4};
    const Image plain = renderer_->render(list, settings);
    EXPECT_EQ(renderer_->last_frame().passes.total(), 0.0) << "not timed unless asked";
    renderer_->render(testing::sphere_field(20), settings);  // else the frame and its shadows are reused
    renderer_->time_passes(true);
    const Image timed = renderer_->render(list, settings);
    const Renderer::PassTimes t = renderer_->last_frame().passes;
    renderer_->time_passes(false);
    EXPECT_EQ(timed.pixels, plain.pixels) << "timing changes no pixel";
    for (const auto& [name, ms] :
         {std::pair{"shadow", t.shadow}, std::pair{"ground", t.ground}, std::pair{"impostors", t.impostors},
          std::pair{"overlays", t.overlays}, std::pair{"resolve", t.resolve}, std::pair{"read-back", t.read_back}}) {
        EXPECT_GT(ms, 0.0) << name << " (ms)";
    }
    renderer_->render(list, settings);
    EXPECT_EQ(renderer_->last_frame().passes.total(), 0.0) << "off again";
}

// A frame drawn from exactly the last frame's list and settings is not drawn
// again (a paused viewer, a scene at rest): the targets still hold it, and
// reading it back gives its bytes. Any difference draws it again: a colour,
// a text, the camera, the settings.
TEST_F(RendererTest, AnIdenticalFrameIsNotDrawnAgain) {
    DrawList list = testing::lecture_scene();
    testing::place_plot(list, 240, 180);
    const RenderSettings settings{.width = 240, .height = 180, .msaa_samples = 4};
    const Image first = renderer_->render(list, settings);
    EXPECT_FALSE(renderer_->last_frame().frame_reused);
    const Image again = renderer_->render(list, settings);
    EXPECT_TRUE(renderer_->last_frame().frame_reused);
    EXPECT_EQ(renderer_->last_frame().draw_calls, 0u);
    EXPECT_EQ(again.pixels, first.pixels);
    renderer_->draw(list, settings);
    renderer_->queue_read_back();
    EXPECT_EQ(renderer_->take_read_back().pixels, first.pixels) << "queued";

    DrawList background = list, text = list, camera = list;
    background.background.g += 0.01f;
    text.texts.back().text += "0";
    camera.camera.eye.x() += 0.05f;
    RenderSettings no_msaa = settings;
    no_msaa.msaa_samples = 0;
    for (const auto& [what, changed, s] :
         {std::tuple{"background", &background, settings}, std::tuple{"text", &text, settings},
          std::tuple{"camera", &camera, settings}, std::tuple{"settings", &list, no_msaa}}) {
        renderer_->render(list, settings);
        const Image image = renderer_->render(*changed, s);
        EXPECT_FALSE(renderer_->last_frame().frame_reused) << what;
        EXPECT_NE(image.pixels, first.pixels) << what;
    }
}

// A read queued behind its frame (video: frame k is taken while frame k + 1
// is drawn) gives the bytes read_back gives, frames come out oldest first
// even when their sizes differ, RGB and RGBA agree, and misuse is refused.
TEST_F(RendererTest, QueuedReadBacksGiveTheFramesInOrder) {
    DrawList lecture = testing::lecture_scene();
    testing::place_plot(lecture, 320, 240);
    const DrawList spheres = testing::sphere_field(50);
    const RenderSettings small{.width = 320, .height = 240, .msaa_samples = 4};
    const RenderSettings odd{.width = 161, .height = 97, .msaa_samples = 0};  // rows of any length
    const Image a = renderer_->render(lecture, small);
    const Image b = renderer_->render(spheres, odd);
    const Image a4 = renderer_->render(lecture, small, 4);

    renderer_->draw(lecture, small);
    renderer_->queue_read_back();
    renderer_->draw(spheres, odd);
    renderer_->queue_read_back();
    renderer_->draw(lecture, small);
    renderer_->queue_read_back();
    EXPECT_EQ(renderer_->queued_read_backs(), 3u);
    const Image first = renderer_->take_read_back();
    const Image second = renderer_->take_read_back();
    const Image third = renderer_->take_read_back(4);
    EXPECT_EQ(renderer_->queued_read_backs(), 0u);
    EXPECT_EQ(first.pixels, a.pixels) << "the oldest first";
    EXPECT_EQ(second.width, 161);
    EXPECT_EQ(second.height, 97);
    EXPECT_EQ(second.pixels, b.pixels);
    EXPECT_EQ(third.channels, 4);
    EXPECT_EQ(third.pixels, a4.pixels);
    for (std::size_t i = 0; i < a.pixels.size() / 3; ++i) {
        ASSERT_EQ(a4.pixels[4 * i], a.pixels[3 * i]) << "pixel " << i << ": RGBA's red is RGB's";
        ASSERT_EQ(a4.pixels[4 * i + 2], a.pixels[3 * i + 2]) << "pixel " << i << ": blue";
        ASSERT_EQ(a4.pixels[4 * i + 3], 255) << "pixel " << i << ": opaque";
    }

    EXPECT_THROW(renderer_->take_read_back(), RenderError) << "nothing queued";
    EXPECT_THROW(renderer_->take_read_back(2), RenderError) << "2 channels";
    for (std::size_t i = 0; i < Renderer::kMaxQueuedReads; ++i) renderer_->queue_read_back();
    EXPECT_THROW(renderer_->queue_read_back(), RenderError) << "beyond kMaxQueuedReads";
    while (renderer_->queued_read_backs() > 0) renderer_->take_read_back();
}

// A video reads frame after frame into one image through the same pixel
// buffers: each keeps its storage where it holds the next frame and grows
// where it does not (a buffer kept at a small frame's size would fail a
// larger read), and the image keeps its pixels' storage at the same size.
TEST_F(RendererTest, ReadBacksIntoOneImageReuseItsStorage) {
    const DrawList spheres = testing::sphere_field(50);
    const RenderSettings small{.width = 160, .height = 120, .msaa_samples = 4};
    const RenderSettings large{.width = 320, .height = 240, .msaa_samples = 4};
    const Image a = renderer_->render(spheres, small);
    const Image b = renderer_->render(spheres, large);

    Image into;
    for (const auto& [what, settings, expected] :
         {std::tuple{"small", small, &a}, std::tuple{"large after small", large, &b},
          std::tuple{"small after large", small, &a}, std::tuple{"small again", small, &a}}) {
        renderer_->draw(spheres, settings);
        renderer_->queue_read_back();
        const std::uint8_t* before = into.pixels.data();
        renderer_->take_read_back(into);
        EXPECT_EQ(into.width, settings.width) << what;
        EXPECT_EQ(into.height, settings.height) << what;
        EXPECT_EQ(into.pixels, expected->pixels) << what;
        if (std::string(what) == "small again") {
            EXPECT_EQ(into.pixels.data(), before) << "the image's storage kept";
        }
    }
}

TEST_F(RendererTest, RefusesBadSizesAndSampleCounts) {
    const DrawList list = empty_scene();
    for (const auto& [w, h] : {std::pair{0, 10}, {10, 0}, {-4, 10}, {9000, 10}}) {
        try {
            renderer_->draw(list, {.width = w, .height = h});
            FAIL() << w << "x" << h << " was accepted";
        } catch (const RenderError& e) {
            EXPECT_EQ(e.kind(), ErrorKind::bad_input);
            EXPECT_NE(std::string(e.what()).find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(renderer_->draw(list, {.width = 10, .height = 10, .msaa_samples = 3}), RenderError);
    EXPECT_THROW(renderer_->draw(list, {.width = 10, .height = 10, .msaa_samples = 16}), RenderError);
    DrawList bad_camera = list;
    bad_camera.camera.target = bad_camera.camera.eye;
    EXPECT_THROW(renderer_->draw(bad_camera, {.width = 10, .height = 10}), RenderError);
    // Odd sizes are fine (videos round to even sizes themselves).
    EXPECT_EQ(renderer_->render(list, {.width = 33, .height = 17}).width, 33);
}

// RenderSettings::scale (a viewer's dynamic resolution) draws the scene on
// fewer pixels: the frame read back is the scene drawn at that size (the
// same bytes as a frame asked at that size); its overlays are left out of it,
// for blit_to_window to draw over the window at the size asked (that half is
// tests/render/window_test.cpp); and a scale outside 0.25 .. 1 is refused.
TEST_F(RendererTest, AScaledFrameIsTheSceneDrawnOnFewerPixels) {
    DrawList scene = testing::lecture_scene();
    scene.texts.clear();
    scene.plots.clear();
    const Image half = renderer_->render(scene, {.width = 320, .height = 240, .scale = 0.5f});
    EXPECT_EQ(half.width, 160);
    EXPECT_EQ(half.height, 120);
    EXPECT_EQ(half.pixels, renderer_->render(scene, {.width = 160, .height = 120}).pixels);

    DrawList list = empty_scene();
    list.background = Color{1, 1, 1, 1};
    list.texts.push_back(Text{"Plausible 42", Vec2(100, 60), 24.0f, Color{0, 0, 0, 1}});
    const Image whole = renderer_->render(list, {.width = 320, .height = 240});
    const Image image = renderer_->render(list, {.width = 320, .height = 240, .scale = 0.5f});
    auto dark = [](const Image& im) {
        int n = 0;
        for (int y = 0; y < im.height; ++y) {
            for (int x = 0; x < im.width; ++x) n += im.pixel(x, y).r <= 200;
        }
        return n;
    };
    EXPECT_GT(dark(whole), 100) << "dark pixels of the text at scale 1";
    EXPECT_EQ(dark(image), 0) << "dark pixels in the half-scale scene: its text is the window's to draw";

    for (const float scale : {0.2f, 1.5f, std::nanf("")}) {
        EXPECT_THROW(renderer_->draw(list, {.width = 64, .height = 64, .scale = scale}), RenderError) << scale;
    }
}

TEST_F(RendererTest, NonFiniteItemsAreSkippedNotDrawn) {
    DrawList list = empty_scene();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    list.spheres.push_back(Sphere{Vec3(nan, 0, 0), 0.5f, Look{}});
    list.cylinders.push_back(Cylinder{Vec3(0, 0, 0), Vec3(0, nan, 0), 0.1f, Look{}});
    const Image image = renderer_->render(list, {.width = 32, .height = 32});
    const Image clear = renderer_->render(empty_scene(), {.width = 32, .height = 32});
    EXPECT_EQ(image.pixels, clear.pixels);
}

TEST_F(RendererTest, OrthographicCameraMapsMetresToPixelsLinearly) {
    DrawList list = empty_scene();
    list.camera.projection = Camera::Projection::orthographic;
    list.camera.ortho_height = 4.0f;  // m: 120 px tall image, 30 px per metre
    list.light.shadows = false;
    list.light.specular = 0;
    list.light.direction = Vec3(0, 0, -1);
    const int w = 160, h = 120;
    // A 2D scene in the xy-plane: the camera looks down -z, so x right, y up.
    const Vec3 centre(1.5f, -0.5f, 0.0f);
    list.spheres.push_back(Sphere{centre, 0.3f, Look{Color{0.1f, 0.8f, 0.1f, 1}}});
    const Image image = renderer_->render(list, {.width = w, .height = h});
    const float px_per_m = static_cast<float>(h) / list.camera.ortho_height;
    const Vec2 expected(0.5f * w + centre.x() * px_per_m, 0.5f * h - centre.y() * px_per_m);  // (125, 75)
    const Rgba8 c = at(image, expected);
    EXPECT_GT(c.g, 150) << "green at the predicted pixel " << expected.transpose();
    EXPECT_LT(c.r, 90);
    // The silhouette's radius is 0.3 m = 9 px whatever the depth: 11 px out is sky.
    const Rgba8 sky{to8(list.background.r), to8(list.background.g), to8(list.background.b), 255};
    EXPECT_EQ(at(image, expected + Vec2(11, 0)), sky);
    EXPECT_EQ(at(image, expected - Vec2(0, 11)), sky);
    EXPECT_NE(at(image, expected + Vec2(7, 0)), sky);
}

// Bytes do not depend on llvmpipe's thread count. Mesa reads LP_NUM_THREADS
// once per process, so each count renders in a child process (this binary,
// running only the helper below) that writes its frame to a PNG.
TEST(RendererHelper, WriteLectureFrame) {
    const char* out = std::getenv("PLAUSIBLE_FRAME_OUT");
    if (out == nullptr) GTEST_SKIP() << "only run as a child of FrameBytesDoNotDependOnThreadCount";
    const auto context = create_context({.backend = default_backend()});
    Renderer renderer(*context);
    DrawList list = testing::lecture_scene();
    testing::place_plot(list, 320, 240);
    save_png(out, renderer.render(list, {.width = 320, .height = 240, .msaa_samples = 4}));
}

TEST(RendererThreads, FrameBytesDoNotDependOnThreadCount) {
    const fs::path dir = results_dir();
    const fs::path self = fs::read_symlink("/proc/self/exe");
    std::vector<Image> frames;
    for (int threads : {1, 2}) {
        const fs::path png = dir / ("lecture_threads_" + std::to_string(threads) + ".png");
        fs::remove(png);
        const std::string command = "PLAUSIBLE_FRAME_OUT='" + png.string() +
                                    "' LP_NUM_THREADS=" + std::to_string(threads) + " '" + self.string() +
                                    "' --gtest_filter=RendererHelper.WriteLectureFrame >/dev/null";
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
        frames.push_back(read_png(png, 3));
    }
    EXPECT_EQ(frames[0].pixels, frames[1].pixels) << "1 and 2 rasteriser threads gave different bytes";
}

// The "done when": one of everything, written to PNG through OSMesa
// and through EGL, and the two frames within the golden tolerance.
TEST_F(RendererTest, LectureSceneThroughOsmesaAndEgl) {
    if (!backend_info(Backend::osmesa).built) {
        GTEST_SKIP() << "this build has no OSMesa (Mesa 25.1 removed it): EGL has nothing to be compared with; "
                        "the other renderer tests run on EGL";
    }
    const int w = 960, h = 540;
    DrawList list = testing::lecture_scene();
    testing::place_plot(list, w, h);
    const RenderSettings settings{.width = w, .height = h, .msaa_samples = 4};
    const Image osmesa = renderer_->render(list, settings);
    const fs::path png = results_dir() / "lecture_osmesa.png";
    save_png(png, osmesa);
    EXPECT_EQ(read_png(png, 3).pixels, osmesa.pixels) << png;
    const RenderSettings golden{.width = 320, .height = 240};
    DrawList small = testing::lecture_scene();
    testing::place_plot(small, 320, 240);
    small.plots.clear();
    save_png(results_dir() / "lecture_osmesa_320x240_nomsaa.png", renderer_->render(small, golden));

    std::unique_ptr<GlContext> egl;
    try {
        egl = create_context({.backend = Backend::egl});
    } catch (const RenderError& e) {
        GTEST_SKIP() << "EGL is not available here: " << e.what();
    }
    Renderer egl_renderer(*egl);
    for (const RenderSettings& s : {settings, golden}) {
        const Image a = renderer_->render(list, s);
        const Image b = egl_renderer.render(list, s);
        const ImageDiff diff = diff_images(b, a, 3);
        // The golden tolerance: channels within 3 levels on all but 5% of pixels.
        EXPECT_LE(diff.share_over, 0.05) << "EGL vs OSMesa at " << s.width << "x" << s.height << ": "
                                         << diff.pixels_over << " pixels differ by more than 3 levels (max "
                                         << diff.max_channel_diff << ")";
        std::printf("EGL vs OSMesa %dx%d MSAA %d: max channel difference %d, %.4f%% of pixels over 3 levels\n", s.width,
                    s.height, s.msaa_samples, diff.max_channel_diff, 100.0 * diff.share_over);
    }
    save_png(results_dir() / "lecture_egl.png", egl_renderer.render(list, settings));
}

}  // namespace
}  // namespace render
