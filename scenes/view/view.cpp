// `plausible view` (see view.h): the GLFW window, its callbacks and ImGui
// session, and run_viewer's loop. The viewer itself is in viewer.h, its
// panel in panel.cpp, the camera and picking in picking.h.
#include "scenes/view/view.h"

#include "render/gl_context.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scenes/view/viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace scenes {
namespace {

using view::Clock;
using view::Viewer;

// GLFW callbacks reach the viewer through the window's user pointer; ImGui's
// backend installs its own first and chains to these.
Viewer* viewer_of(GLFWwindow* window) { return static_cast<Viewer*>(glfwGetWindowUserPointer(window)); }

// The window's framebuffer in pixels, within what the renderer draws (16 ..
// 8192 px a side; a HiDPI window can be larger, and then shows the picture
// in its bottom-left corner instead of failing).
void framebuffer_size(GLFWwindow* window, int& width, int& height) {
    glfwGetFramebufferSize(window, &width, &height);
    width = std::clamp(width, 16, 8192);
    height = std::clamp(height, 16, 8192);
}

// Runs an input handler; what it throws is reported, never unwound through
// GLFW's C frames (that would end the program).
template <class F>
void guarded(GLFWwindow* window, F&& handle) {
    try {
        handle(*viewer_of(window));
    } catch (const std::exception& e) {
        viewer_of(window)->report(e.what());
    }
}

// The panel takes the mouse only where it is drawn (ImGui's flags are from the
// last frame it drew).
bool panel_has_mouse(GLFWwindow* window) { return viewer_of(window)->panel() && ImGui::GetIO().WantCaptureMouse; }

// Cursor positions are in screen units; the picture is in framebuffer pixels.
void cursor_in_pixels(GLFWwindow* window, double& x, double& y, int& w, int& h) {
    int ww = 0, wh = 0;
    framebuffer_size(window, w, h);
    glfwGetWindowSize(window, &ww, &wh);
    x *= ww > 0 ? static_cast<double>(w) / ww : 1.0;
    y *= wh > 0 ? static_cast<double>(h) / wh : 1.0;
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    // Shortcuts work while the panel has focus, except when it is taking typed text.
    if (action == GLFW_RELEASE || (viewer_of(window)->panel() && ImGui::GetIO().WantTextInput)) return;
    guarded(window, [&](Viewer& v) { v.key(key); });
}

void on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
    if (action == GLFW_PRESS && panel_has_mouse(window)) return;
    double x = 0, y = 0;
    int w = 0, h = 0;
    glfwGetCursorPos(window, &x, &y);
    cursor_in_pixels(window, x, y, w, h);
    guarded(window,
            [&](Viewer& v) { v.mouse_button(button, action == GLFW_PRESS, x, y, w, h, (mods & GLFW_MOD_SHIFT) != 0); });
}

void on_cursor(GLFWwindow* window, double x, double y) {
    int w = 0, h = 0;
    cursor_in_pixels(window, x, y, w, h);
    guarded(window, [&](Viewer& v) { v.mouse_move(x, y, w, h); });
}

void on_scroll(GLFWwindow* window, double /*dx*/, double dy) {
    if (panel_has_mouse(window)) return;
    guarded(window, [&](Viewer& v) { v.scroll(dy); });
}

void validate(const ViewOptions& o) {
    if (o.width < 64 || o.height < 64 || o.width > 7680 || o.height > 4320) {
        throw sim::InputError("view: --size must be within 64x64 .. 7680x4320 (got " + std::to_string(o.width) + "x" +
                              std::to_string(o.height) + ")");
    }
    if (o.exit_after < 0)
        throw sim::InputError("view: --exit-after must be >= 0 (got " + std::to_string(o.exit_after) + ")");
    if (o.msaa_samples != -1 && !render::supported_msaa_samples(o.msaa_samples)) {
        throw sim::InputError(
            "view: --msaa must be 0, 1, 2, 4 or 8, or -1 for 4 when still and off while running (got " +
            std::to_string(o.msaa_samples) + ")");
    }
    if (!o.screenshot.empty() && o.screenshot.extension() != ".png") {
        throw sim::InputError("view: --screenshot must end in .png (got '" + o.screenshot.string() + "')");
    }
}

// ImGui's context and backends for one window, torn down in reverse.
struct ImGuiSession {
    explicit ImGuiSession(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini written into the user's folder
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~ImGuiSession() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

}  // namespace

// --- run_viewer: the loop ----------------------------------------------------------

ViewResult run_viewer(const SceneDef& scene, const std::vector<Override>& overrides, const ViewOptions& options) {
    validate(options);
    Viewer viewer(scene, overrides, options);
    const auto context = render::create_context({.backend = render::Backend::glfw,
                                                 .window_width = options.width,
                                                 .window_height = options.height,
                                                 .title = "Plausible: " + scene.name});
    GLFWwindow* window = context->window();
    render::Renderer renderer(*context);
    glfwSetWindowUserPointer(window, &viewer);
    glfwSetKeyCallback(window, on_key);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);
    glfwSwapInterval(1);
    ImGuiSession imgui(window);

    auto last = Clock::now();
    int shown = 0;
    for (;;) {
        glfwPollEvents();
        const auto now = Clock::now();
        viewer.update(std::chrono::duration<double>(now - last).count());
        last = now;
        const bool done = viewer.quit || glfwWindowShouldClose(window) != 0 ||
                          (options.exit_after > 0 && ++shown >= options.exit_after);

        int width = 0, height = 0;
        framebuffer_size(window, width, height);
        const int msaa = options.msaa_samples >= 0                     ? options.msaa_samples
                         : viewer.running() && options.exit_after == 0 ? 0
                                                                       : 4;
        const auto r0 = Clock::now();
        renderer.draw(viewer.draw_list(width, height), {.width = width, .height = height, .msaa_samples = msaa});
        renderer.blit_to_window();
        const double render_ms = 1e3 * std::chrono::duration<double>(Clock::now() - r0).count();
        if (viewer.panel()) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            viewer.panel_ui();
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        }
        viewer.record_times(render_ms);
        if (viewer.screenshot_now) {
            // P: beside --screenshot (or here), named by scene and frame; a failed
            // write is reported and the session goes on.
            const std::filesystem::path file =
                options.screenshot.parent_path() /
                ("view-" + scene.name + "-" + std::to_string(viewer.run().frame()) + ".png");
            try {
                render::write_png(file, renderer.read_window());
                std::printf("view: screenshot %s\n", file.string().c_str());
                std::fflush(stdout);
            } catch (const std::exception& e) {
                viewer.report(e.what());
            }
            viewer.screenshot_now = false;
        }
        if (done && !options.screenshot.empty()) render::write_png(options.screenshot, renderer.read_window());
        context->swap_buffers();
        if (done) break;
    }
    return {viewer.run().frame(), viewer.run().time(), viewer.run().verdict().exploded(),
            viewer.run().state_hash_hex()};
}

}  // namespace scenes
