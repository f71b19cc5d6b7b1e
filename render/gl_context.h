// One small GL-context interface, three implementations (STYLE.md habit 8):
//   osmesa  off-screen through Mesa's OSMesa; optional at build time (Mesa
//           25.1 removed it), the default where the build has it
//   egl     off-screen through EGL's surfaceless platform (or the device
//           platform); the default where the build has no OSMesa, and it
//           gives the same llvmpipe frames
//   gpu     off-screen through EGL's device platform on a hardware device
//           (a GPU, through its vendor's libEGL by glvnd); never the goldens'
//           renderer, picked by `auto` where one is found
//   glfw    a window, for `plausible view`; fails cleanly without a display
// backends() is the table of them: the CLI's --backend choices, its help and
// its errors all read it, so a new backend is one row there and one case in
// create_context().
// Each one creates a GL 3.3 core context and loads its own glad function table
// through the backend's GetProcAddress. The renderer draws into its own
// framebuffer objects, so the three differ only in how the context is made and
// where a finished frame goes (nowhere, or the window).
#pragma once

#include "render/error.h"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

struct GladGLContext;  // glad 2 (--mx): one function table per context
struct GLFWwindow;

namespace render {

enum class Backend { osmesa, egl, gpu, glfw };

struct BackendInfo {
    Backend backend;
    std::string_view name;   // as --backend and the fingerprint spell it
    bool offscreen = false;  // draws without a display (the CLI's --backend choices)
    bool built = false;      // compiled into this build (OSMesa is optional)
    std::string_view about;  // one line for --help and error messages
};

// Every backend this program knows, built here or not, in order of preference
// for the default.
std::span<const BackendInfo> backends();
const BackendInfo& backend_info(Backend backend);
std::string_view backend_name(Backend backend);
std::optional<Backend> backend_from_name(std::string_view name);
// The off-screen backend used when none is asked for: the first built one of
// the table, OSMesa where the build has it (the goldens were made with it),
// else EGL. The one place that decides it.
Backend default_backend();
// The built off-screen backends' names, comma-separated ("osmesa, egl, gpu").
std::string offscreen_backend_names();

// The EGL devices this machine has (EGL_EXT_device_enumeration): Mesa's
// software device and any hardware ones, from every vendor library glvnd
// finds. Empty where EGL cannot enumerate devices.
struct EglDevice {
    int index = 0;         // in eglQueryDevicesEXT's order
    bool software = true;  // EGL_MESA_device_software: llvmpipe
    std::string name;      // its DRM node where it has one, else "device N"
};
std::vector<EglDevice> egl_devices();
// The fastest off-screen backend here: gpu where a hardware EGL device is
// found, else default_backend() (llvmpipe). For videos; goldens are checked
// with default_backend().
Backend fastest_backend();
// What `--backend list` prints: each off-screen backend, built or not, and
// the EGL devices found.
std::string describe_backends();

// What made the pixels: golden files store it, and a golden check compares it
// before blaming the simulation for a different picture.
struct Fingerprint {
    std::string backend;          // osmesa, egl, gpu, glfw
    std::string vendor;           // GL_VENDOR
    std::string renderer;         // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;          // GL_VERSION
    std::string cpu_simd;         // the SIMD extensions this CPU has, which llvmpipe's code uses
    int gl_threads = 0;           // llvmpipe rasteriser threads (LP_NUM_THREADS)
    std::string summary() const;  // one line for logs and JSON
};

struct ContextOptions {
    Backend backend = default_backend();
    // Window backend only:
    int window_width = 1280;  // px
    int window_height = 720;  // px
    std::string title = "Plausible";
    bool visible = true;  // false: a hidden window (scripted screenshots)
};

class GlContext {
public:
    virtual ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    Backend backend() const { return backend_; }
    const Fingerprint& fingerprint() const { return fingerprint_; }
    // The GL functions of this context; valid while it is current.
    const GladGLContext& gl() const { return *gl_; }

    virtual void make_current() = 0;

    // Window backend only; the off-screen ones have no window.
    virtual GLFWwindow* window() const { return nullptr; }
    virtual void swap_buffers() {}

protected:
    explicit GlContext(Backend backend);
    using GlProc = void (*)();
    using GlProcLoader = GlProc (*)(const char* name);
    // Loads the GL functions through `loader` (the context must be current),
    // checks for GL 3.3 and records the fingerprint. Throws RenderError.
    void load_functions(GlProcLoader loader);

private:
    Backend backend_;
    Fingerprint fingerprint_;
    std::unique_ptr<GladGLContext> gl_;
};

// Creates and makes current a context of the requested backend. Throws
// RenderError: no_display for a window without a display, unavailable when the
// backend is not in this build or its library cannot make a 3.3 core context
// here.
std::unique_ptr<GlContext> create_context(const ContextOptions& options = {});
// A context of fastest_backend(), or of default_backend() where the gpu one
// cannot be made after all (a device listed but unusable here).
std::unique_ptr<GlContext> create_fastest_context();

}  // namespace render
