// Off-screen contexts through OSMesa (Mesa's gallium llvmpipe in-process).
// The context is made current on a tiny colour buffer: the renderer draws
// into its own framebuffer objects of any size, so this buffer is never read.
#include "render/gl_context_backends.h"

#include <GL/osmesa.h>

#include <vector>

namespace render::detail {
namespace {

class OsmesaContext final : public GlContext {
public:
    OsmesaContext() : GlContext(Backend::osmesa) {
        const int attribs[] = {
            OSMESA_FORMAT,
            OSMESA_RGBA,
            OSMESA_DEPTH_BITS,
            0,
            OSMESA_STENCIL_BITS,
            0,
            OSMESA_ACCUM_BITS,
            0,
            OSMESA_PROFILE,
            OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION,
            3,
            OSMESA_CONTEXT_MINOR_VERSION,
            3,
            0,
        };
        context_ = OSMesaCreateContextAttribs(attribs, nullptr);
        if (context_ == nullptr) {
            throw RenderError(ErrorKind::unavailable,
                              "osmesa: OSMesaCreateContextAttribs refused a GL 3.3 core context");
        }
        make_current();
        load_functions(reinterpret_cast<GlProcLoader>(&OSMesaGetProcAddress));
    }
    ~OsmesaContext() override { OSMesaDestroyContext(context_); }

    void make_current() override {
        if (OSMesaGetCurrentContext() == context_) return;
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kBufferSize, kBufferSize)) {
            throw RenderError(ErrorKind::gl, "osmesa: OSMesaMakeCurrent failed");
        }
    }

private:
    static constexpr int kBufferSize = 4;  // px; only FBOs are drawn to
    OSMesaContext context_ = nullptr;
    std::vector<unsigned char> buffer_ = std::vector<unsigned char>(kBufferSize * kBufferSize * 4);
};

}  // namespace

std::unique_ptr<GlContext> create_osmesa_context() { return std::make_unique<OsmesaContext>(); }

}  // namespace render::detail
