// The three GL-context backends: OSMesa (default), EGL surfaceless, GLFW.
#include "render/gl_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace render {
namespace {

TEST(GlContext, BackendNamesRoundTrip) {
    for (Backend b : {Backend::osmesa, Backend::egl, Backend::glfw}) {
        EXPECT_EQ(backend_from_name(backend_name(b)), b);
    }
    EXPECT_FALSE(backend_from_name("vulkan").has_value());
}

TEST(GlContext, OsmesaGivesACoreContextAndAFingerprint) {
    const auto context = create_context({.backend = Backend::osmesa});
    const Fingerprint& f = context->fingerprint();
    EXPECT_EQ(f.backend, "osmesa");
    EXPECT_NE(f.renderer.find("llvmpipe"), std::string::npos) << f.renderer;
    EXPECT_NE(f.version.find("Core Profile"), std::string::npos) << f.version;
    EXPECT_FALSE(f.cpu_simd.empty());
    EXPECT_GT(f.gl_threads, 0);
    EXPECT_NE(f.summary().find(f.renderer), std::string::npos);
}

TEST(GlContext, EglSurfacelessGivesTheSameRasteriser) {
    std::unique_ptr<GlContext> egl;
    try {
        egl = create_context({.backend = Backend::egl});
    } catch (const RenderError& e) {
        GTEST_SKIP() << "EGL is not available here: " << e.what();
    }
    const auto osmesa = create_context({.backend = Backend::osmesa});
    EXPECT_EQ(egl->fingerprint().backend, "egl");
    // Both must be llvmpipe: golden images are made with it.
    EXPECT_EQ(egl->fingerprint().renderer, osmesa->fingerprint().renderer);
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
