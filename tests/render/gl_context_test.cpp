// The GL-context backends: OSMesa (the default where the build has it), EGL
// surfaceless (the default where it has not), EGL on a hardware device (gpu),
// GLFW.
#include "render/gl_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace render {
namespace {

bool osmesa_built() { return backend_info(Backend::osmesa).built; }

constexpr const char* kNoOsmesa =
    "this build has no OSMesa (not found when it was configured, or -DPLAUSIBLE_OSMESA=OFF; Mesa 25.1 removed it)";

TEST(GlContext, BackendNamesRoundTrip) {
    for (const BackendInfo& info : backends()) {
        EXPECT_EQ(backend_from_name(backend_name(info.backend)), info.backend);
        EXPECT_EQ(&backend_info(info.backend), &info);
    }
    EXPECT_FALSE(backend_from_name("vulkan").has_value());
}

TEST(GlContext, DefaultIsOsmesaWhereBuiltElseEgl) {
    const Backend expected = osmesa_built() ? Backend::osmesa : Backend::egl;
    EXPECT_EQ(default_backend(), expected);
    EXPECT_EQ(ContextOptions{}.backend, expected);
    EXPECT_EQ(offscreen_backend_names(), osmesa_built() ? "osmesa, egl, gpu" : "egl, gpu");
    EXPECT_FALSE(backend_info(Backend::glfw).offscreen);
}

TEST(GlContext, OsmesaGivesACoreContextAndAFingerprint) {
    if (!osmesa_built()) GTEST_SKIP() << kNoOsmesa;
    const auto context = create_context({.backend = Backend::osmesa});
    const Fingerprint& f = context->fingerprint();
    EXPECT_EQ(f.backend, "osmesa");
    EXPECT_NE(f.renderer.find("llvmpipe"), std::string::npos) << f.renderer;
    EXPECT_NE(f.version.find("Core Profile"), std::string::npos) << f.version;
    EXPECT_FALSE(f.cpu_simd.empty());
    EXPECT_GT(f.gl_threads, 0);
    EXPECT_NE(f.summary().find(f.renderer), std::string::npos);
}

TEST(GlContext, AnUnbuiltBackendIsRefusedNamingTheBuiltOnes) {
    if (osmesa_built()) GTEST_SKIP() << "every backend is built here (the build found OSMesa)";
    try {
        create_context({.backend = Backend::osmesa});
        FAIL() << "an OSMesa context from a build without OSMesa";
    } catch (const RenderError& e) {
        EXPECT_EQ(e.kind(), ErrorKind::unavailable);
        EXPECT_NE(std::string(e.what()).find("this build has: egl"), std::string::npos) << e.what();
    }
}

// EGL gives llvmpipe, the rasteriser of the goldens; where the build has
// OSMesa too, the very same one. EGL may be missing only where it is not the
// default (then OSMesa carries the tests).
TEST(GlContext, EglSurfacelessGivesTheSameRasteriser) {
    std::unique_ptr<GlContext> egl;
    try {
        egl = create_context({.backend = Backend::egl});
    } catch (const RenderError& e) {
        if (default_backend() == Backend::egl) throw;
        GTEST_SKIP() << "EGL is not available here: " << e.what();
    }
    const Fingerprint& f = egl->fingerprint();
    EXPECT_EQ(f.backend, "egl");
    EXPECT_NE(f.renderer.find("llvmpipe"), std::string::npos) << f.renderer;
    EXPECT_NE(f.version.find("Core Profile"), std::string::npos) << f.version;
    if (!osmesa_built()) return;
    const auto osmesa = create_context({.backend = Backend::osmesa});
    EXPECT_EQ(f.renderer, osmesa->fingerprint().renderer);
}

// The EGL devices found decide the fastest backend: gpu where one is
// hardware, else the goldens' llvmpipe. Where there is none, asking for gpu
// is refused saying what was found; where there is one (a GPU machine), it
// gives a context whose fingerprint says gpu and is not llvmpipe's.
TEST(GlContext, GpuIsTheFastestWhereAHardwareDeviceIsFoundAndRefusedElsewhere) {
    const std::vector<EglDevice> devices = egl_devices();
    bool hardware = false;
    for (const EglDevice& d : devices) {
        EXPECT_FALSE(d.name.empty());
        hardware = hardware || !d.software;
    }
    EXPECT_EQ(fastest_backend(), hardware ? Backend::gpu : default_backend());
    const std::string listed = describe_backends();
    for (const char* name : {"osmesa", "egl", "gpu", "EGL devices found: ", "fastest here: "}) {
        EXPECT_NE(listed.find(name), std::string::npos) << name << " in:\n" << listed;
    }
    if (!hardware) {
        try {
            create_context({.backend = Backend::gpu});
            FAIL() << "a gpu context without a hardware device";
        } catch (const RenderError& e) {
            EXPECT_EQ(e.kind(), ErrorKind::unavailable);
            EXPECT_NE(std::string(e.what()).find("no usable hardware EGL device"), std::string::npos) << e.what();
        }
        return;
    }
    const auto gpu = create_context({.backend = Backend::gpu});
    EXPECT_EQ(gpu->fingerprint().backend, "gpu");
    EXPECT_EQ(gpu->fingerprint().renderer.find("llvmpipe"), std::string::npos) << gpu->fingerprint().renderer;
}

// Runs a body with DISPLAY and WAYLAND_DISPLAY unset, restoring them after.
class NoDisplay {
public:
    NoDisplay() {
        for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"}) {
            const char* value = std::getenv(name);
            saved_.push_back({name, value != nullptr ? std::optional<std::string>(value) : std::nullopt});
            unsetenv(name);
        }
    }
    ~NoDisplay() {
        for (const auto& [name, value] : saved_) {
            if (value) setenv(name.c_str(), value->c_str(), 1);
        }
    }

private:
    std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

TEST(GlContext, GlfwWithoutADisplayRefusesWithAMessage) {
    const NoDisplay no_display;
    try {
        create_context({.backend = Backend::glfw});
        FAIL() << "a window was created without a display";
    } catch (const RenderError& e) {
        EXPECT_EQ(e.kind(), ErrorKind::no_display);
        const std::string message = e.what();
        EXPECT_NE(message.find("no display"), std::string::npos) << message;
        EXPECT_NE(message.find("plausible render"), std::string::npos) << message;
    }
    // A second attempt fails the same way: nothing was left half-initialised.
    EXPECT_THROW(create_context({.backend = Backend::glfw}), RenderError);
}

}  // namespace
}  // namespace render
