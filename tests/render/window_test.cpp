// The renderer in a window (GLFW, on the virtual display ctest starts for it
// with xvfb-run): a frame drawn at a lower RenderSettings::scale is stretched
// over the window, and its overlays are drawn over it at the window's pixels,
// as sharp as in a frame drawn whole (the viewer's dynamic resolution keeps
// its text readable).
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <cstdlib>

namespace render {
namespace {

constexpr int kWidth = 320, kHeight = 240;  // px, the window

// A white scene with a red ball on the left, and a line of text on the right.
DrawList ball_and_text() {
    DrawList list;
    list.ground.enabled = false;
    list.background = Color{1, 1, 1, 1};
    list.camera.eye = Vec3(0, 0, 5);
    list.camera.target = Vec3::Zero();
    list.spheres.push_back(Sphere{Vec3(-1.2f, 0, 0), 0.6f, Look{Color{0.8f, 0.1f, 0.1f, 1}}});
    list.texts.push_back(Text{"Plausible 42", Vec2(180, 100), 20.0f, Color{0, 0, 0, 1}});
    return list;
}

// LeakSanitizer names a leak's owner by the library its stack lies in, but
// glfwTerminate unloads the GL driver and the X libraries before the check:
// pin every loaded library (RTLD_NODELETE) so tools/lsan.supp can name them.
void keep_libraries_loaded() {
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) {
            if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0')
                dlopen(info->dlpi_name, RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
            return 0;
        },
        nullptr);
}

// The window as drawn at `scale`: the frame stretched into it, overlays on top.
Image in_window(Renderer& renderer, const DrawList& list, float scale) {
    renderer.draw(list, {.width = kWidth, .height = kHeight, .scale = scale});
    renderer.blit_to_window();
    return renderer.read_window(3);
}

TEST(Window, AScaledFrameKeepsItsTextAsSharpAsAWholeOne) {
    if (std::getenv("DISPLAY") == nullptr) GTEST_SKIP() << "no display: ctest runs this under xvfb-run";
    const auto context = create_context({.backend = Backend::glfw, .window_width = kWidth, .window_height = kHeight});
    Renderer renderer(*context);
    keep_libraries_loaded();
    const DrawList list = ball_and_text();
    const Image whole = in_window(renderer, list, 1.0f);
    const Image half = in_window(renderer, list, 0.5f);
    ASSERT_EQ(half.width, kWidth);
    ASSERT_EQ(half.height, kHeight);
    // Right half (the text over white): the text as drawn whole, but for a
    // level or a few at some glyph edges (the window's rows run the other way
    // from a framebuffer object's, so llvmpipe's derivatives, and fwidth's
    // smoothing, pair pixels differently); stretched from half scale instead,
    // its strokes would smear by a hundred levels. Left half (the ball):
    // softer, so pixels differ.
    int text_dark = 0, text_differ = 0, text_max = 0, ball_differ = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const auto a = whole.pixel(x, y), b = half.pixel(x, y);
            const int d = std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
            if (x >= kWidth / 2) {
                text_dark += a.r < 128;
                text_differ += d > 0;
                text_max = std::max(text_max, d);
            } else {
                ball_differ += d > 0;
            }
        }
    }
    EXPECT_GT(text_dark, 50) << "the text's dark pixels in the whole frame";
    EXPECT_LE(text_max, 16) << "levels (0..255): the largest difference in the text between scale 1 and 0.5";
    EXPECT_LE(text_differ, text_dark / 4) << "pixels of the text differing at all between scale 1 and 0.5";
    EXPECT_GT(ball_differ, 20) << "pixels of the ball (left half) differing: was the frame drawn at half scale?";
}

}  // namespace
}  // namespace render
