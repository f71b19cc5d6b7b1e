// The backend-independent half of the GL contexts: names, the fingerprint,
// loading the glad function table, and choosing a backend.
#include "render/gl_context.h"

#include "render/gl_context_backends.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace render {

namespace {

// PLAUSIBLE_HAVE_OSMESA: set by render/CMakeLists.txt when pkg-config found
// osmesa (Debian 12 and 13 have it; Mesa 25.1 removed it, so sid has not).
#ifdef PLAUSIBLE_HAVE_OSMESA
constexpr bool kOsmesaBuilt = true;
#else
constexpr bool kOsmesaBuilt = false;
#endif

// OSMesa first: where it is built it stays the default, since the goldens
// were made with it; EGL gives the same llvmpipe frames where it is not.
constexpr BackendInfo kBackends[] = {
    {Backend::osmesa, "osmesa", true, kOsmesaBuilt, "Mesa's OSMesa, llvmpipe"},
    {Backend::egl, "egl", true, true, "EGL surfaceless or device platform, llvmpipe"},
    {Backend::gpu, "gpu", true, true, "EGL device platform on a hardware device, where one is found"},
    {Backend::glfw, "glfw", false, true, "a window, for plausible view"},
};

}  // namespace

std::span<const BackendInfo> backends() { return kBackends; }

const BackendInfo& backend_info(Backend backend) {
    for (const BackendInfo& info : kBackends) {
        if (info.backend == backend) return info;
    }
    throw RenderError(ErrorKind::bad_input, "unknown backend");
}

std::string_view backend_name(Backend backend) { return backend_info(backend).name; }

std::optional<Backend> backend_from_name(std::string_view name) {
    for (const BackendInfo& info : kBackends) {
        if (info.name == name) return info.backend;
    }
    return std::nullopt;
}

Backend default_backend() {
    for (const BackendInfo& info : kBackends) {
        if (info.offscreen && info.built) return info.backend;
    }
    return Backend::egl;  // unreachable: EGL is always built
}

std::string offscreen_backend_names() {
    std::string names;
    for (const BackendInfo& info : kBackends) {
        if (!info.offscreen || !info.built) continue;
        if (!names.empty()) names += ", ";
        names += info.name;
    }
    return names;
}

std::string Fingerprint::summary() const {
    return backend + " | " + renderer + " | GL " + version + " | " + cpu_simd + " | " + std::to_string(gl_threads) +
           " threads";
}

namespace {

// llvmpipe compiles shaders for the SIMD width this CPU offers (LLVM picks
// AVX2 or AVX-512 when present), so the CPU's extensions belong in the record
// of what made a golden image.
std::string cpu_simd_flags() {
    std::string flags;
    auto add = [&](bool has, const char* name) {
        if (!has) return;
        if (!flags.empty()) flags += ' ';
        flags += name;
    };
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    add(__builtin_cpu_supports("sse4.2"), "sse4.2");
    add(__builtin_cpu_supports("avx"), "avx");
    add(__builtin_cpu_supports("avx2"), "avx2");
    add(__builtin_cpu_supports("fma"), "fma");
    add(__builtin_cpu_supports("avx512f"), "avx512f");
#else
    add(true, "non-x86");
#endif
    return flags.empty() ? "none" : flags;
}

std::string gl_string(const GladGLContext& gl, GLenum name) {
    const auto* text = reinterpret_cast<const char*>(gl.GetString(name));
    return text != nullptr ? text : "";
}

}  // namespace

GlContext::GlContext(Backend backend) : backend_(backend) {}

GlContext::~GlContext() = default;

void GlContext::load_functions(GlProcLoader loader) {
    gl_ = std::make_unique<GladGLContext>();
    const int version = gladLoadGLContext(gl_.get(), reinterpret_cast<GLADloadfunc>(loader));
    if (version == 0) {
        throw RenderError(ErrorKind::unavailable,
                          std::string(backend_name(backend_)) + ": could not load the OpenGL functions");
    }
    if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
        throw RenderError(ErrorKind::unavailable, std::string(backend_name(backend_)) +
                                                      ": OpenGL 3.3 core needed, got " +
                                                      std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                                                      std::to_string(GLAD_VERSION_MINOR(version)));
    }
    fingerprint_.backend = backend_name(backend_);
    fingerprint_.vendor = gl_string(*gl_, GL_VENDOR);
    fingerprint_.renderer = gl_string(*gl_, GL_RENDERER);
    fingerprint_.version = gl_string(*gl_, GL_VERSION);
    fingerprint_.cpu_simd = cpu_simd_flags();
    const char* threads = std::getenv("LP_NUM_THREADS");
    fingerprint_.gl_threads = threads != nullptr ? std::atoi(threads) : 0;
}

namespace detail {

void prepare_mesa_environment(bool software) {
    // A fixed rasteriser thread count, decided once per machine (the core
    // count, at most 8) instead of left to the driver. llvmpipe bins triangles
    // into tiles in submission order and each tile is shaded by one thread, so
    // the bytes do not depend on the count (tests/render checks 1 vs 2); fixing
    // it makes the frame time repeatable and the fingerprint honest.
    const unsigned cores = std::clamp(std::thread::hardware_concurrency(), 1u, 8u);
    setenv("LP_NUM_THREADS", std::to_string(cores).c_str(), /*overwrite=*/0);
    // EGL would pick a GPU driver where one exists; golden images are made
    // with llvmpipe, as OSMesa always does. The gpu backend takes back what
    // this set (Mesa reads it as each display is initialised), never what
    // the user set.
    static bool set_here = false;
    if (software && std::getenv("LIBGL_ALWAYS_SOFTWARE") == nullptr) {
        setenv("LIBGL_ALWAYS_SOFTWARE", "1", /*overwrite=*/1);
        set_here = true;
    } else if (!software && set_here) {
        unsetenv("LIBGL_ALWAYS_SOFTWARE");
        set_here = false;
    }
}

}  // namespace detail

std::unique_ptr<GlContext> create_context(const ContextOptions& options) {
    const BackendInfo& info = backend_info(options.backend);
    if (!info.built) {
        throw RenderError(ErrorKind::unavailable, std::string(info.name) +
                                                      ": not in this build (its library was not found when it was "
                                                      "configured); this build has: " +
                                                      offscreen_backend_names());
    }
    detail::prepare_mesa_environment(options.backend != Backend::gpu);
    switch (options.backend) {
        case Backend::osmesa:
#ifdef PLAUSIBLE_HAVE_OSMESA
            return detail::create_osmesa_context();
#else
            break;  // refused above: the table says it is not built
#endif
        case Backend::egl:
            return detail::create_egl_context(false);
        case Backend::gpu:
            return detail::create_egl_context(true);
        case Backend::glfw:
            return detail::create_glfw_context(options);
    }
    throw RenderError(ErrorKind::bad_input, "unknown backend");
}

std::vector<EglDevice> egl_devices() {
    detail::prepare_mesa_environment(false);  // Mesa's hardware devices too
    return detail::query_egl_devices();
}

namespace {

Backend fastest_of(const std::vector<EglDevice>& devices) {
    for (const EglDevice& d : devices) {
        if (!d.software) return Backend::gpu;
    }
    return default_backend();
}

}  // namespace

Backend fastest_backend() { return fastest_of(egl_devices()); }

std::unique_ptr<GlContext> create_fastest_context() {
    if (fastest_backend() == Backend::gpu) {
        try {
            return create_context({.backend = Backend::gpu});
        } catch (const RenderError& e) {
            if (e.kind() != ErrorKind::unavailable) throw;
            // Listed but not usable here (no driver for it, no access to its node): llvmpipe.
        }
    }
    return create_context({.backend = default_backend()});
}

std::string describe_backends() {
    std::string out;
    for (const BackendInfo& info : kBackends) {
        if (!info.offscreen) continue;
        out += std::string(info.name) + (info.built ? "" : " (not in this build)") + ": " + std::string(info.about) +
               (info.backend == default_backend() ? " [default]" : "") + "\n";
    }
    const std::vector<EglDevice> devices = egl_devices();
    out += "EGL devices found: " + std::to_string(devices.size()) + (devices.empty() ? "\n" : "");
    for (const EglDevice& d : devices) {
        out +=
            "\n  " + std::to_string(d.index) + ": " + d.name + (d.software ? " (software, llvmpipe)" : " (hardware)");
    }
    if (!devices.empty()) out += "\n";
    out += "fastest here: " + std::string(backend_name(fastest_of(devices))) + "\n";
    return out;
}

}  // namespace render
