// The renderer (see renderer.h): a frame as a list of passes, the checks on
// what it is asked to draw, and reading the frame back. The passes, the GL
// objects, the shaders and the flattening of the draw list have their own
// files, listed atop renderer_impl.h.
//
// A frame: clear -> shadow pass (light's view, depth only) -> ground -> opaque
// meshes -> sphere impostors -> ghosts (blended, after all solids) -> trails
// -> overlays -> MSAA resolve. Colours arrive in sRGB; lighting is done in
// linear light and encoded back.
#include "render/renderer_impl.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

namespace render {
namespace {

constexpr int kMaxSize = 8192;      // px per side
constexpr float kMinScale = 0.25f;  // RenderSettings::scale

// Throws RenderError(bad_input) for settings no driver could draw.
void check_settings(const RenderSettings& settings) {
    if (settings.width < 1 || settings.height < 1 || settings.width > kMaxSize || settings.height > kMaxSize) {
        throw RenderError(ErrorKind::bad_input, "image size " + std::to_string(settings.width) + "x" +
                                                    std::to_string(settings.height) + " must be within 1x1 .. " +
                                                    std::to_string(kMaxSize) + "x" + std::to_string(kMaxSize) + " px");
    }
    const int s = settings.msaa_samples;
    if (!supported_msaa_samples(s)) {
        throw RenderError(ErrorKind::bad_input, "MSAA samples must be 0, 1, 2, 4 or 8 (got " + std::to_string(s) + ")");
    }
    if (settings.shadow_map_size < 16 || settings.shadow_map_size > kMaxSize) {
        throw RenderError(ErrorKind::bad_input, "shadow map size must be within 16 .. " + std::to_string(kMaxSize) +
                                                    " texels (got " + std::to_string(settings.shadow_map_size) + ")");
    }
    if (!(settings.scale >= kMinScale && settings.scale <= 1.0f)) {
        char message[80];
        std::snprintf(message, sizeof message, "scale must be within %.2f .. 1 (got %g)", kMinScale, settings.scale);
        throw RenderError(ErrorKind::bad_input, message);
    }
    for (const float j : {settings.jitter_x, settings.jitter_y}) {
        if (!(std::abs(j) <= 1.0f)) {
            throw RenderError(ErrorKind::bad_input, "jitter must be within -1 .. 1 px (got " + std::to_string(j) + ")");
        }
    }
}

void check_camera(const Camera& camera) {
    if (!camera.eye.allFinite() || !camera.target.allFinite() || !((camera.target - camera.eye).norm() > 0) ||
        !(camera.near_plane > 0) || !(camera.far_plane > camera.near_plane) ||
        (camera.projection == Camera::Projection::perspective && !(camera.fov_y_deg > 0 && camera.fov_y_deg < 180)) ||
        (camera.projection == Camera::Projection::orthographic && !(camera.ortho_height > 0))) {
        throw RenderError(ErrorKind::bad_input,
                          "camera needs finite eye != target, 0 < near < far, 0 < fov < 180 degrees, ortho height > 0");
    }
}

// A side of width x height drawn at `scale`, px.
int scaled(int side, float scale) {
    return std::max(1, static_cast<int>(std::lround(static_cast<float>(side) * scale)));
}

detail::Viewpoint camera_viewpoint(const Camera& camera, const RenderSettings& settings) {
    const float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
    const Vec3 forward = (camera.target - camera.eye).normalized();
    Eigen::Matrix4f projection = projection_matrix(camera, aspect);
    if (settings.jitter_x != 0.0f || settings.jitter_y != 0.0f) {
        Eigen::Matrix4f shift = Eigen::Matrix4f::Identity();  // in normalised device coordinates
        shift(0, 3) = 2.0f * settings.jitter_x / static_cast<float>(scaled(settings.width, settings.scale));
        shift(1, 3) = -2.0f * settings.jitter_y / static_cast<float>(scaled(settings.height, settings.scale));
        projection = shift * projection;
    }
    return {projection * view_matrix(camera), camera.eye, forward,
            camera.projection == Camera::Projection::orthographic};
}

// The world size of one pixel at unit distance (perspective) or anywhere
// (orthographic), m: the sphere impostors grow by two of them to hold their
// anti-aliased edge.
float pixel_scale(const Camera& camera, int height) {
    if (camera.projection == Camera::Projection::orthographic) return camera.ortho_height / static_cast<float>(height);
    return 2.0f * std::tan(0.5f * camera.fov_y_deg * std::numbers::pi_v<float> / 180.0f) / static_cast<float>(height);
}

// The list's numbers that reach the shaders outside its items: the camera
// (as the frame's view), the light, the ground, the background.
std::vector<float> frame_uniforms(const DrawList& list, const detail::Viewpoint& camera, float pixel_size) {
    std::vector<float> u(camera.view_proj.data(), camera.view_proj.data() + 16);
    for (const Vec3* v : {&camera.eye, &camera.forward, &list.light.direction})
        u.insert(u.end(), {v->x(), v->y(), v->z()});
    const Light& l = list.light;
    const Ground& g = list.ground;
    u.insert(u.end(), {camera.ortho ? 1.0f : 0.0f, pixel_size, l.intensity, l.ambient, l.specular, l.shininess,
                       l.shadows ? 1.0f : 0.0f, g.enabled ? 1.0f : 0.0f, g.height, g.extent, g.grid_spacing,
                       static_cast<float>(g.major_every)});
    for (const Color* c : {&g.color, &g.line_color, &list.background}) u.insert(u.end(), {c->r, c->g, c->b, c->a});
    return u;
}

// The passes' clock (Renderer::time_passes): lap(t) waits for the GPU and
// adds the time since the last lap to t, ms; off, it does nothing.
struct PassClock {
    const GladGLContext& gl;
    bool on;
    std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
    void lap(double& ms) {
        if (!on) return;
        gl.Finish();
        const auto now = std::chrono::steady_clock::now();
        ms += 1e3 * std::chrono::duration<double>(now - last).count();
        last = now;
    }
};

}  // namespace

void Renderer::Impl::draw(const DrawList& list, const RenderSettings& settings) {
    check_settings(settings);
    check_camera(list.camera);
    context.make_current();
    check_driver_limits(settings);
    const int target_width = scaled(settings.width, settings.scale),
              target_height = scaled(settings.height, settings.scale);
    ensure_targets(target_width, target_height, settings.msaa_samples > 1 ? settings.msaa_samples : 0);
    view_width = settings.width, view_height = settings.height;
    stats = {};
    if (time_passes) gl.Finish();  // the last frame's work is not this one's
    PassClock clock{gl, time_passes};
    PassTimes& t = stats.passes;
    const detail::Viewpoint camera = camera_viewpoint(list.camera, settings);
    prepare(list, camera.eye, camera.forward);
    clock.lap(t.prepare);
    const float pixels = pixel_scale(list.camera, target_height);
    if (same_as_last_frame(list, settings, camera, pixels)) {
        stats.frame_reused = true;  // the targets hold it still (a paused viewer, a scene at rest)
        return;
    }
    has_frame = false;  // until this one is drawn whole: a failed frame is never reused or read

    gl.Disable(GL_CULL_FACE);  // thin cloth and open tubes are seen from both sides
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    const detail::ShadowLookup shadow = shadow_pass(list.light, settings.shadow_map_size);
    clock.lap(t.shadow);
    begin_main_pass(list, camera, shadow, pixels);
    ground_pass(list);
    clock.lap(t.ground);
    opaque_pass();
    clock.lap(t.opaque);
    impostor_pass();
    clock.lap(t.impostors);
    translucent_pass();
    clock.lap(t.translucent);
    trail_pass(camera.view_proj);
    clock.lap(t.trails);
    // Scaled down, overlays are drawn over the window by blit_to_window, at
    // its pixels: text and plots stay sharp while the scene is softer.
    if (!scaled_down()) overlay_pass();
    clock.lap(t.overlays);
    end_main_pass();
    resolve_msaa();
    clock.lap(t.resolve);
    gl.BindVertexArray(0);
    try {
        check_errors("drawing a frame");
    } catch (const RenderError&) {
        shadow_valid = false;  // the map may be part-drawn too
        throw;
    }
    has_frame = true;
}

// True when the targets hold a frame drawn from exactly these inputs (a NaN
// anywhere never compares equal: such a frame is drawn again); else they
// become the last frame's.
bool Renderer::Impl::same_as_last_frame(const DrawList& list, const RenderSettings& settings,
                                        const detail::Viewpoint& camera, float pixels) {
    std::vector<float> uniforms = frame_uniforms(list, camera, pixels);
    FrameInputs& last = last_inputs;
    if (has_frame && settings == last.settings && uniforms == last.uniforms && solid == last.solid &&
        ghost == last.ghost && trails == last.trails && overlay.vertices() == last.overlay) {
        return true;
    }
    last.settings = settings;
    last.uniforms = std::move(uniforms);
    last.solid = solid;
    last.ghost = ghost;
    last.trails = trails;
    last.overlay = overlay.vertices();
    return false;
}

// Throws RenderError(bad_input) for MSAA or a size beyond this driver.
void Renderer::Impl::check_driver_limits(const RenderSettings& settings) {
    const int s = settings.msaa_samples;
    GLint max_samples = 0, max_size = 0;
    gl.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
    gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (s > max_samples) {
        throw RenderError(ErrorKind::bad_input, "MSAA " + std::to_string(s) + "x is beyond this driver's " +
                                                    std::to_string(max_samples) + "x");
    }
    if (settings.width > max_size || settings.height > max_size) {
        throw RenderError(ErrorKind::bad_input, "image size beyond this driver's " + std::to_string(max_size) + " px");
    }
}

void Renderer::Impl::check_errors(const char* where) {
    const GLenum error = gl.GetError();
    if (error != GL_NO_ERROR) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04X", error);
        throw RenderError(ErrorKind::gl, std::string("OpenGL error ") + code + " while " + where);
    }
}

Renderer::Renderer(GlContext& context, const Font& font) : impl_(std::make_unique<Impl>(context, font)) {
    context.make_current();
    impl_->create_resources();
}

Renderer::~Renderer() {
    impl_->context.make_current();
    impl_->destroy_resources();
}

void Renderer::draw(const DrawList& list, const RenderSettings& settings) { impl_->draw(list, settings); }

Image Renderer::render(const DrawList& list, const RenderSettings& settings, int channels) {
    draw(list, settings);
    return read_back(channels);
}

void Renderer::blit_to_window() {
    Impl& r = *impl_;
    if (r.context.window() == nullptr)
        throw RenderError(ErrorKind::bad_input, "blit_to_window: this context has no window");
    if (!r.has_frame) return;
    r.context.make_current();
    r.gl.BindFramebuffer(GL_READ_FRAMEBUFFER, r.resolve_fbo);
    r.gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    // A frame drawn at a lower scale is stretched over the window, filtered.
    const bool same = r.width == r.view_width && r.height == r.view_height;
    r.gl.BlitFramebuffer(0, 0, r.width, r.height, 0, 0, r.view_width, r.view_height, GL_COLOR_BUFFER_BIT,
                         same ? GL_NEAREST : GL_LINEAR);
    r.gl.BindFramebuffer(GL_FRAMEBUFFER, 0);  // what draws on top (a UI) draws into the window
    if (r.scaled_down()) {
        r.gl.Viewport(0, 0, r.view_width, r.view_height);
        r.overlay_pass();
        r.gl.BindVertexArray(0);
    }
}

void Renderer::present() {
    if (impl_->context.window() == nullptr)
        throw RenderError(ErrorKind::bad_input, "present: this context has no window");
    blit_to_window();
    impl_->context.swap_buffers();
}

void Renderer::finish() {
    impl_->context.make_current();
    impl_->gl.Finish();
}

Renderer::FrameStats Renderer::last_frame() const { return impl_->stats; }

void Renderer::time_passes(bool on) { impl_->time_passes = on; }

}  // namespace render
