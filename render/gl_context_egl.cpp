// Off-screen contexts through EGL without a window system. llvmpipe (the egl
// backend): Mesa's software device of the device platform
// (EGL_EXT_platform_device, EGL_MESA_device_software), else the surfaceless
// platform (EGL_MESA_platform_surfaceless) where it draws in software. A GPU
// (the gpu backend): the first hardware device that initialises. A
// configless context (EGL_KHR_no_config_context) with no surface: the
// renderer draws into its own framebuffer objects.
#include "render/gl_context_backends.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace render::detail {
namespace {

bool has_extension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t length = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
        const bool starts = p == list || p[-1] == ' ';
        const bool ends = p[length] == ' ' || p[length] == '\0';
        if (starts && ends) return true;
    }
    return false;
}

RenderError egl_error(const std::string& what) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
    return RenderError(ErrorKind::unavailable, "egl: " + what + " (EGL error " + code + ")");
}

using QueryDevices = PFNEGLQUERYDEVICESEXTPROC;
using QueryDeviceString = PFNEGLQUERYDEVICESTRINGEXTPROC;

// EGL_EXT_device_base is the older name of enumeration and query together:
// NVIDIA's 580 driver, alone under glvnd, names only it.
bool can_enumerate_devices(const char* client) {
    return has_extension(client, "EGL_EXT_device_enumeration") || has_extension(client, "EGL_EXT_device_base");
}
bool can_query_devices(const char* client) {
    return has_extension(client, "EGL_EXT_device_query") || has_extension(client, "EGL_EXT_device_base");
}

// Every EGL device, in eglQueryDevicesEXT's order (none where the client
// cannot enumerate them).
std::vector<EGLDeviceEXT> all_devices() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto query_devices = reinterpret_cast<QueryDevices>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (!can_enumerate_devices(client) || query_devices == nullptr) return {};
    EGLint count = 0;
    if (!query_devices(0, nullptr, &count) || count <= 0) return {};
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (!query_devices(count, devices.data(), &count)) return {};
    devices.resize(static_cast<std::size_t>(std::max(count, 0)));
    return devices;
}

EglDevice describe(EGLDeviceEXT device, int index) {
    EglDevice d;
    d.index = index;
    d.name = "device " + std::to_string(index);
    auto query_string = reinterpret_cast<QueryDeviceString>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (query_string == nullptr) return d;
    const char* extensions = query_string(device, EGL_EXTENSIONS);
    d.software = has_extension(extensions, "EGL_MESA_device_software");
    if (has_extension(extensions, "EGL_EXT_device_drm")) {
        if (const char* node = query_string(device, EGL_DRM_DEVICE_FILE_EXT)) d.name = node;
    }
    return d;
}

EGLDisplay device_display(EGLDeviceEXT device) {
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr) return EGL_NO_DISPLAY;
    return get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
}

// llvmpipe through the surfaceless platform, where no software device is
// listed (a Mesa without device enumeration): its display, initialised, when
// it says its device is Mesa's software one, or when it cannot say and its
// vendor is Mesa (the egl backend has set LIBGL_ALWAYS_SOFTWARE, so Mesa
// draws with llvmpipe). Any other vendor's display (NVIDIA's drew on its GPU
// here) is refused, and let go again where this initialised it.
EGLDisplay surfaceless_software_display() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr || !has_extension(client, "EGL_MESA_platform_surfaceless")) {
        return EGL_NO_DISPLAY;
    }
    const EGLDisplay display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) return EGL_NO_DISPLAY;
    const bool initialised_before = eglQueryString(display, EGL_VENDOR) != nullptr;
    EGLint major = 0, minor = 0;
    if (!initialised_before && !eglInitialize(display, &major, &minor)) return EGL_NO_DISPLAY;
    const char* vendor = eglQueryString(display, EGL_VENDOR);
    bool software = vendor != nullptr && std::strstr(vendor, "Mesa") != nullptr;
    auto query_display =
        reinterpret_cast<PFNEGLQUERYDISPLAYATTRIBEXTPROC>(eglGetProcAddress("eglQueryDisplayAttribEXT"));
    EGLAttrib device = 0;
    if (can_query_devices(client) && query_display != nullptr && query_display(display, EGL_DEVICE_EXT, &device) &&
        device != 0) {
        software = describe(reinterpret_cast<EGLDeviceEXT>(device), 0).software;
    }
    if (software) return display;
    if (!initialised_before) eglTerminate(display);
    return EGL_NO_DISPLAY;
}

// llvmpipe: Mesa's software device wherever glvnd lists it, else the
// surfaceless platform's display where it draws in software; none where
// neither does (another vendor's hardware display is never taken for it).
EGLDisplay open_software_display() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (has_extension(client, "EGL_EXT_platform_device")) {
        const std::vector<EGLDeviceEXT> devices = all_devices();
        for (std::size_t i = 0; i < devices.size(); ++i) {
            if (describe(devices[i], static_cast<int>(i)).software) return device_display(devices[i]);
        }
    }
    return surfaceless_software_display();
}

// The first hardware device's display; throws, naming what was found, when
// there is none.
EGLDisplay open_hardware_display() {
    const std::vector<EGLDeviceEXT> devices = all_devices();
    int hardware = 0;
    for (std::size_t i = 0; i < devices.size(); ++i) {
        if (describe(devices[i], static_cast<int>(i)).software) continue;
        ++hardware;
        // The first that initialises (a listed device may have no driver here).
        const EGLDisplay display = device_display(devices[i]);
        EGLint major = 0, minor = 0;
        if (display != EGL_NO_DISPLAY && eglInitialize(display, &major, &minor)) return display;
    }
    throw RenderError(ErrorKind::unavailable,
                      "gpu: no usable hardware EGL device here (" + std::to_string(devices.size()) +
                          " device(s) found, " + std::to_string(hardware) +
                          " hardware); --backend auto falls back to llvmpipe, --backend list shows what was found");
}

class EglContext final : public GlContext {
public:
    explicit EglContext(bool hardware) : GlContext(hardware ? Backend::gpu : Backend::egl) {
        display_ = hardware ? open_hardware_display() : open_software_display();
        if (display_ == EGL_NO_DISPLAY) {
            throw egl_error(hardware ? "no hardware display"
                                     : "no llvmpipe display: neither Mesa's software device nor a software "
                                       "surfaceless display (is libegl-mesa0 installed?)");
        }
        EGLint major = 0, minor = 0;
        if (!eglInitialize(display_, &major, &minor)) throw egl_error("eglInitialize failed");
        const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
        if (!has_extension(extensions, "EGL_KHR_no_config_context") ||
            !has_extension(extensions, "EGL_KHR_surfaceless_context")) {
            throw RenderError(ErrorKind::unavailable,
                              "egl: the display lacks EGL_KHR_no_config_context or EGL_KHR_surfaceless_context");
        }
        if (!eglBindAPI(EGL_OPENGL_API)) throw egl_error("eglBindAPI(EGL_OPENGL_API) failed");
        const EGLint attribs[] = {
            EGL_CONTEXT_MAJOR_VERSION,
            3,
            EGL_CONTEXT_MINOR_VERSION,
            3,
            EGL_CONTEXT_OPENGL_PROFILE_MASK,
            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
            EGL_NONE,
        };
        context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
        if (context_ == EGL_NO_CONTEXT) throw egl_error("eglCreateContext refused a GL 3.3 core context");
        try {
            make_current();
            load_functions(reinterpret_cast<GlProcLoader>(&eglGetProcAddress));
        } catch (...) {
            eglDestroyContext(display_, context_);
            throw;
        }
    }
    ~EglContext() override {
        if (eglGetCurrentContext() == context_)
            eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        // The display is shared by every context on it (EGL returns the same
        // one for the same platform), so it is not terminated here.
    }

    void make_current() override {
        if (eglGetCurrentContext() == context_) return;
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
            throw egl_error("eglMakeCurrent failed");
        }
    }

private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<GlContext> create_egl_context(bool hardware) { return std::make_unique<EglContext>(hardware); }

std::vector<EglDevice> query_egl_devices() {
    std::vector<EglDevice> out;
    const std::vector<EGLDeviceEXT> devices = all_devices();
    for (std::size_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], static_cast<int>(i)));
    return out;
}

}  // namespace render::detail
