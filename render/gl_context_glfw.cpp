// A window through GLFW, for `plausible view`. Without a display, creating one
// throws RenderError(no_display) with a message that says how to get a
// picture instead; it never crashes and never leaves GLFW half-initialised.
#include "render/gl_context_backends.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

namespace render::detail {
namespace {

// GLFW reports errors through a process-wide callback; the latest message is
// kept to explain a failed glfwInit or glfwCreateWindow.
thread_local std::string glfw_last_error;

void record_glfw_error(int /*code*/, const char* description) {
    glfw_last_error = description != nullptr ? description : "unknown error";
}

// glfwInit/glfwTerminate bracket the lifetime of the process's windows.
int open_windows = 0;

constexpr const char* kInstead =
    "To get pictures without a display, use `plausible render` (PNG frames) or `plausible video` (MP4/GIF); "
    "or run under a virtual display (xvfb-run).";

class GlfwContext final : public GlContext {
public:
    explicit GlfwContext(const ContextOptions& options) : GlContext(Backend::glfw) {
        glfwSetErrorCallback(&record_glfw_error);
        glfw_last_error.clear();
        if (open_windows == 0 && glfwInit() != GLFW_TRUE) {
            throw RenderError(ErrorKind::no_display,
                              "no display: cannot open a window (GLFW: " + glfw_last_error + "). " + kInstead);
        }
        ++open_windows;
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
        glfwWindowHint(GLFW_DEPTH_BITS, 0);  // the renderer's framebuffers have their own depth
        window_ =
            glfwCreateWindow(options.window_width, options.window_height, options.title.c_str(), nullptr, nullptr);
        if (window_ == nullptr) {
            release();
            throw RenderError(ErrorKind::no_display,
                              "cannot open a GL 3.3 core window (GLFW: " + glfw_last_error + "). " + kInstead);
        }
        try {
            make_current();
            load_functions(reinterpret_cast<GlProcLoader>(&glfwGetProcAddress));
        } catch (...) {
            glfwDestroyWindow(window_);
            release();
            throw;
        }
    }
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
        release();
    }

    void make_current() override {
        if (glfwGetCurrentContext() != window_) glfwMakeContextCurrent(window_);
    }
    GLFWwindow* window() const override { return window_; }
    void swap_buffers() override { glfwSwapBuffers(window_); }

private:
    static void release() {
        if (--open_windows == 0) glfwTerminate();
    }
    GLFWwindow* window_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> create_glfw_context(const ContextOptions& options) {
    return std::make_unique<GlfwContext>(options);
}

}  // namespace render::detail
