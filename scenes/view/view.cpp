// `plausible view` (see view.h): the GLFW window, its callbacks and ImGui
// session, and run_viewer's loop. The viewer itself is in viewer.h, its
// panel in panel.cpp, the camera and picking in picking.h.
#include "scenes/view/view.h"
#include "scenes/common/output_file.h"

#include "render/gl_context.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scenes/view/frame_budget.h"
#include "scenes/view/input_script.h"
#include "scenes/view/viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

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

// A key pressed: to the viewer. Shortcuts work while the panel has focus,
// except when it is taking typed text.
void key_down(GLFWwindow* window, int key) {
    if (viewer_of(window)->panel() && ImGui::GetIO().WantTextInput) return;
    guarded(window, [&](Viewer& v) { v.key(key); });
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    if (action != GLFW_RELEASE) key_down(window, key);
}

// A mouse button at (x, y), window coordinates: to the viewer, unless it is
// pressed on the panel.
void mouse_button(GLFWwindow* window, int button, bool down, double x, double y, bool shift) {
    if (down && panel_has_mouse(window)) return;
    int w = 0, h = 0;
    cursor_in_pixels(window, x, y, w, h);
    guarded(window, [&](Viewer& v) { v.mouse_button(button, down, x, y, w, h, shift); });
}

void on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    mouse_button(window, button, action == GLFW_PRESS, x, y, (mods & GLFW_MOD_SHIFT) != 0);
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
    if (o.render_scale != -1.0 && !(o.render_scale >= view::FrameBudget::kMinScale && o.render_scale <= 1.0)) {
        throw sim::InputError("view: --render-scale must be within 0.375 .. 1, or -1 to keep a running frame within " +
                              std::to_string(static_cast<int>(view::FrameBudget::kBudgetMs)) + " ms (got " +
                              sim::format_value(o.render_scale) + ")");
    }
    if (!o.screenshot.empty() && o.screenshot.extension() != ".png") {
        throw sim::InputError("view: --screenshot must end in .png (got '" + o.screenshot.string() + "')");
    }
}

// Plays an input script (view/input_script.h) frame by frame: to the viewer
// as the window's callbacks deliver input, and to the panel as ImGui's GLFW
// backend would report it (so that it needs no focus, no real cursor and no
// wall clock).
class ScriptPlayer {
public:
    explicit ScriptPlayer(std::vector<view::InputEvent> events) : events_(std::move(events)) {}

    // The events of drawn frame `frame`, to the viewer; the keys of the last
    // frame come up.
    void to_viewer(GLFWwindow* window, int frame) {
        keys_.clear();
        for (const int key : held_) keys_.push_back({key, false});
        held_.clear();
        ctrl_ = shift_ = false;
        for (; next_ < events_.size() && events_[next_].frame == frame; ++next_) play(window, events_[next_]);
    }

    // This frame's cursor, buttons, keys and text, to ImGui: after its GLFW
    // backend's NewFrame (which would report the real cursor), before
    // ImGui::NewFrame.
    void to_panel() {
        ImGuiIO& io = ImGui::GetIO();
#if IMGUI_VERSION_NUM >= 18700
        // Every event of a frame in that frame (ImGui would otherwise defer a
        // click that follows a key, so that ctrl+click would reach it as a
        // plain click a frame later).
        io.ConfigInputTrickleEventQueue = false;
        io.AddMousePosEvent(static_cast<float>(x_), static_cast<float>(y_));
        for (int b = 0; b < 3; ++b) io.AddMouseButtonEvent(b, down_[b]);
#if IMGUI_VERSION_NUM >= 18900
        io.AddKeyEvent(ImGuiMod_Ctrl, ctrl_);
        io.AddKeyEvent(ImGuiMod_Shift, shift_);
#else
        io.AddKeyEvent(ImGuiKey_ModCtrl, ctrl_);
        io.AddKeyEvent(ImGuiKey_ModShift, shift_);
#endif
        for (const auto& [key, down] : keys_) io.AddKeyEvent(imgui_key(key), down);
#else
        io.MousePos = ImVec2(static_cast<float>(x_), static_cast<float>(y_));
        for (int b = 0; b < 3; ++b) io.MouseDown[b] = down_[b];
        io.KeyCtrl = ctrl_;
        io.KeyShift = shift_;
        for (const auto& [key, down] : keys_) io.KeysDown[key] = down;
#endif
        for (const char c : text_) io.AddInputCharacter(static_cast<unsigned char>(c));
        text_.clear();
    }

private:
    void play(GLFWwindow* window, const view::InputEvent& e) {
        using Kind = view::InputEvent::Kind;
        ctrl_ = ctrl_ || e.ctrl;
        shift_ = shift_ || e.shift;
        switch (e.kind) {
            case Kind::key:
                keys_.push_back({e.key, true});
                held_.push_back(e.key);
                key_down(window, e.key);
                break;
            case Kind::text:
                text_ += e.text;
                break;
            case Kind::move: {
                if (!e.text.empty()) {
                    const std::array<float, 4>* item = viewer_of(window)->item(e.text);
                    if (item == nullptr) throw sim::InputError(e.where + ": no panel item '" + e.text + "' drawn yet");
                    x_ = 0.5 * ((*item)[0] + (*item)[2]);
                    y_ = 0.5 * ((*item)[1] + (*item)[3]);
                } else {
                    x_ = e.x, y_ = e.y;
                }
                double x = x_, y = y_;
                int w = 0, h = 0;
                cursor_in_pixels(window, x, y, w, h);
                guarded(window, [&](Viewer& v) { v.mouse_move(x, y, w, h); });
                break;
            }
            case Kind::press:
            case Kind::release:
                down_[e.key] = e.kind == Kind::press;
                mouse_button(window, e.key, down_[e.key], x_, y_, e.shift);
                break;
        }
    }

#if IMGUI_VERSION_NUM >= 18700
    // The keys a script may press (input_script.cpp), as ImGui names them.
    static ImGuiKey imgui_key(int key) {
        if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return static_cast<ImGuiKey>(ImGuiKey_A + (key - GLFW_KEY_A));
        if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return static_cast<ImGuiKey>(ImGuiKey_0 + (key - GLFW_KEY_0));
        switch (key) {
            case GLFW_KEY_SPACE:
                return ImGuiKey_Space;
            case GLFW_KEY_ENTER:
                return ImGuiKey_Enter;
            case GLFW_KEY_RIGHT:
                return ImGuiKey_RightArrow;
            case GLFW_KEY_LEFT:
                return ImGuiKey_LeftArrow;
            case GLFW_KEY_UP:
                return ImGuiKey_UpArrow;
            case GLFW_KEY_DOWN:
                return ImGuiKey_DownArrow;
            case GLFW_KEY_ESCAPE:
                return ImGuiKey_Escape;
            case GLFW_KEY_BACKSPACE:
                return ImGuiKey_Backspace;
            case GLFW_KEY_TAB:
                return ImGuiKey_Tab;
            case GLFW_KEY_PERIOD:
                return ImGuiKey_Period;
            case GLFW_KEY_COMMA:
                return ImGuiKey_Comma;
            case GLFW_KEY_LEFT_BRACKET:
                return ImGuiKey_LeftBracket;
            case GLFW_KEY_RIGHT_BRACKET:
                return ImGuiKey_RightBracket;
            default:
                return ImGuiKey_None;
        }
    }
#endif

    std::vector<view::InputEvent> events_;
    std::size_t next_ = 0;
    double x_ = 0, y_ = 0;  // the cursor, window coordinates
    bool down_[3] = {};     // mouse buttons held
    bool ctrl_ = false, shift_ = false;
    std::vector<std::pair<int, bool>> keys_;  // (GLFW key, down) for the panel this frame
    std::vector<int> held_;                   // pressed this frame, up the next
    std::string text_;                        // typed this frame
};

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

// --- FramePartsClock: --verbose's times ---------------------------------------------

// A running frame's parts as laps of one clock: lap(part) adds the time since
// the last lap to that part of this frame (nullptr: to none); keep() adds the
// frame, with its whole time (swap to swap), to the means. Off, it does nothing.
class FramePartsClock {
public:
    explicit FramePartsClock(bool on) : on_(on) {}
    void start(Clock::time_point now) {
        frame_ = {};
        lap_ = now;
    }
    void lap(double ViewFrameParts::*part) {
        if (!on_) return;
        const auto now = Clock::now();
        if (part != nullptr) frame_.*part += 1e3 * std::chrono::duration<double>(now - lap_).count();
        lap_ = now;
    }
    void keep(double frame_ms, const render::Renderer::PassTimes& passes) {
        if (!on_) return;
        frame_.frame = frame_ms;
        frame_.passes = passes;
        ++sum_.frames;
        add_to(sum_, frame_, 1.0);
    }
    ViewFrameParts means() const {
        ViewFrameParts m;
        m.frames = sum_.frames;
        if (m.frames > 0) add_to(m, sum_, 1.0 / m.frames);
        return m;
    }

private:
    static void add_to(ViewFrameParts& into, const ViewFrameParts& f, double k) {
        for (double ViewFrameParts::*p : {&ViewFrameParts::physics, &ViewFrameParts::draw_list, &ViewFrameParts::blit,
                                          &ViewFrameParts::panel, &ViewFrameParts::swap, &ViewFrameParts::frame}) {
            into.*p += k * f.*p;
        }
        into.passes.add(f.passes, k);
    }
    bool on_;
    Clock::time_point lap_{};
    ViewFrameParts frame_, sum_;
};

FrameSpread spread_of(std::vector<double> ms) {
    FrameSpread s;
    if (ms.empty()) return s;
    std::sort(ms.begin(), ms.end());
    s.frames = static_cast<int>(ms.size());
    s.median = ms[ms.size() / 2];
    s.p95 = ms[static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(ms.size()))) - 1];  // 1 .. size
    s.worst = ms.back();
    s.over_budget = static_cast<int>(
        std::count_if(ms.begin(), ms.end(), [](double t) { return t > view::FrameBudget::kBudgetMs; }));
    return s;
}

}  // namespace

// --- run_viewer: the loop ----------------------------------------------------------

ViewResult run_viewer(const SceneDef& scene, const std::vector<Override>& overrides, const ViewOptions& options) {
    validate(options);
    // A script is read before a window opens: a bad one is refused as any bad option.
    std::optional<ScriptPlayer> script;
    if (!options.input.empty()) script.emplace(view::read_input_script(options.input));
    Viewer viewer(scene, overrides, options);
    const auto context = render::create_context({.backend = render::Backend::glfw,
                                                 .window_width = options.width,
                                                 .window_height = options.height,
                                                 .title = "Plausible: " + scene.name});
    GLFWwindow* window = context->window();
    render::Renderer renderer(*context);
    renderer.time_passes(options.verbose);
    glfwSetWindowUserPointer(window, &viewer);
    glfwSetKeyCallback(window, on_key);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);
    glfwSwapInterval(1);
    ImGuiSession imgui(window);

    auto last = Clock::now(), last_swap = last;
    int shown = 0, drawn = 0;
    view::FrameBudget budget(static_cast<float>(options.render_scale));
    float scale_min = 0.0f, scale_max = 0.0f;  // of the frames drawn running
    FramePartsClock parts(options.verbose);
    std::vector<double> running_ms;  // each frame drawn running, swap to swap
    for (;;) {
        glfwPollEvents();
        if (script) script->to_viewer(window, ++drawn);
        const auto now = Clock::now();
        parts.start(now);
        viewer.update(std::chrono::duration<double>(now - last).count());
        last = now;
        parts.lap(&ViewFrameParts::physics);
        const bool done = viewer.quit || glfwWindowShouldClose(window) != 0 ||
                          (options.exit_after > 0 && ++shown >= options.exit_after);

        int width = 0, height = 0;
        framebuffer_size(window, width, height);
        const int msaa = options.msaa_samples >= 0                     ? options.msaa_samples
                         : viewer.running() && options.exit_after == 0 ? 0
                                                                       : 4;
        // Drawn whole when still, for a screenshot and as the last frame.
        const bool drew_running = viewer.running() && options.exit_after == 0 && !done && !viewer.screenshot_now;
        const float scale = budget.scale(drew_running);
        if (drew_running) {
            scale_min = scale_max == 0.0f ? scale : std::min(scale_min, scale);
            scale_max = std::max(scale_max, scale);
        }
        const auto r0 = Clock::now();
        parts.lap(nullptr);
        const render::DrawList list = viewer.draw_list(width, height);
        parts.lap(&ViewFrameParts::draw_list);
        renderer.draw(list, {.width = width, .height = height, .msaa_samples = msaa, .scale = scale});
        parts.lap(nullptr);
        renderer.blit_to_window();
        if (options.verbose) renderer.finish();  // the blit's time is its own, not the swap's
        parts.lap(&ViewFrameParts::blit);
        const double render_ms = 1e3 * std::chrono::duration<double>(Clock::now() - r0).count();
        if (viewer.panel()) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            if (script) script->to_panel();
            ImGui::NewFrame();
            viewer.panel_ui();
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (options.verbose) renderer.finish();
        }
        parts.lap(&ViewFrameParts::panel);
        viewer.record_times(render_ms, scale);
        if (viewer.screenshot_now) {
            // P: beside --screenshot (or here), named by scene and frame; a failed
            // write is reported and the session goes on.
            const std::filesystem::path file =
                options.screenshot.parent_path() /
                ("view-" + scene.name + "-" + std::to_string(viewer.run().frame()) + ".png");
            try {
                write_output(file, render::encode_png(renderer.read_window()));
                std::printf("view: screenshot %s\n", file.string().c_str());
                std::fflush(stdout);
            } catch (const std::exception& e) {
                viewer.report(e.what());
            }
            viewer.screenshot_now = false;
        }
        if (done && !options.screenshot.empty())
            write_output(options.screenshot, render::encode_png(renderer.read_window()));
        const auto swap_start = Clock::now();
        context->swap_buffers();
        parts.lap(&ViewFrameParts::swap);
        const auto swapped = Clock::now();
        const double frame_ms = 1e3 * std::chrono::duration<double>(swapped - last_swap).count();
        last_swap = swapped;
        budget.frame_took(1e3 * std::chrono::duration<double>(swap_start - now).count(), frame_ms, drew_running);
        if (drew_running) {
            parts.keep(frame_ms, renderer.last_frame().passes);
            running_ms.push_back(frame_ms);
        }
        if (done) break;
    }
    return {viewer.run().frame(),
            viewer.run().time(),
            viewer.run().verdict().exploded(),
            viewer.run().state_hash_hex(),
            viewer.run().diverged_frame(),
            scale_min,
            scale_max,
            parts.means(),
            spread_of(std::move(running_ms))};
}

}  // namespace scenes
