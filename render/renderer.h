// The renderer: draws a DrawList into an off-screen framebuffer of any size
// with any GL context (OSMesa, EGL or a GLFW window) and reads it back as an
// Image, or shows it in the window. Spheres are ray-cast impostors (two
// triangles each, exact silhouettes and depth), capsules are a tube plus two
// impostors, everything else is an instanced unit mesh; one directional light
// with a shadow map, Blinn-Phong, optional MSAA; overlays in screen space.
//
// The same draw list and settings give the same bytes on every run on one
// machine: no time, no randomness, fixed draw order (the order of the list).
#pragma once

#include "render/draw_list.h"
#include "render/font.h"
#include "render/gl_context.h"
#include "render/image.h"

#include <cstddef>
#include <memory>
#include <optional>

namespace render {

class Renderer {
public:
    // The context must outlive the renderer. The font's atlas is uploaded once.
    explicit Renderer(GlContext& context, const Font& font = Font::default_font());
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Draws the list. Throws RenderError(bad_input) for a size outside
    // 1..8192 px or beyond the driver's limit, or an MSAA sample count other
    // than 0, 1, 2, 4 or 8 (or beyond GL_MAX_SAMPLES); RenderError(gl) when
    // the driver reports an error.
    void draw(const DrawList& list, const RenderSettings& settings);
    // The last frame drawn, 3 (RGB) or 4 (RGBA, alpha 255) channels, top row first.
    Image read_back(int channels = 3);
    // The same without waiting for the frame: its read is queued behind it
    // (into a pixel-buffer object), so that the next frame can be drawn while
    // the renderer (llvmpipe's threads, a GPU) finishes this one;
    // take_read_back() then returns the oldest queued frame, waiting for it if
    // it must. At most kMaxQueuedReads frames are queued.
    static constexpr std::size_t kMaxQueuedReads = 4;
    void queue_read_back();
    Image take_read_back(int channels = 3);
    // The same into `into`, whose storage is reused where it holds the frame
    // (a video takes one frame after another into the same image).
    void take_read_back(Image& into, int channels = 3);
    std::size_t queued_read_backs() const;
    // draw() then read_back().
    Image render(const DrawList& list, const RenderSettings& settings, int channels = 3);
    // Waits until the GPU (llvmpipe's threads) has finished the frame: for
    // timing a frame without reading it back.
    void finish();
    // Window contexts: copies the last frame into the window's back buffer
    // (drawn at the window's framebuffer size: 1:1, or scaled up, filtered,
    // from a frame drawn at a RenderSettings::scale below 1, its overlays then
    // drawn over it at the window's pixels) and swaps buffers.
    void present();
    // The same without the swap, for a UI drawn on top before the caller swaps;
    // leaves the window's framebuffer bound.
    void blit_to_window();
    // The window's back buffer as it is now (the frame and whatever was drawn
    // on top), at the last frame's size: a screenshot, taken before the swap.
    Image read_window(int channels = 3);

    // A frame's time pass by pass, ms, while time_passes(true): each pass
    // then waits for the GPU (llvmpipe's threads: glFinish) before its clock
    // is read, so that its time is its own. The frame runs a little slower
    // so, and nothing overlaps: for choosing what to speed up, not for the
    // frame rate.
    struct PassTimes {
        double prepare = 0;      // the draw list flattened and uploaded
        double shadow = 0;       // the shadow map
        double ground = 0;       // begin (targets, clear, uniforms) and the ground
        double opaque = 0;       // solid meshes
        double impostors = 0;    // ray-cast spheres
        double translucent = 0;  // ghosts
        double trails = 0;       // ribbons
        double overlays = 0;     // text and plots
        double resolve = 0;      // MSAA resolve
        double read_back = 0;    // read_back() or take_read_back(), when called
        double total() const {
            return prepare + shadow + ground + opaque + impostors + translucent + trails + overlays + resolve +
                   read_back;
        }
        // Adds another frame's times, each times scale (for sums and means).
        void add(const PassTimes& o, double scale = 1.0) {
            prepare += scale * o.prepare, shadow += scale * o.shadow, ground += scale * o.ground;
            opaque += scale * o.opaque, impostors += scale * o.impostors, translucent += scale * o.translucent;
            trails += scale * o.trails, overlays += scale * o.overlays, resolve += scale * o.resolve;
            read_back += scale * o.read_back;
        }
    };
    struct FrameStats {
        std::size_t triangles = 0;  // including the shadow pass
        std::size_t draw_calls = 0;
        bool shadow_reused = false;  // the shadow map was the last frame's (no caster moved)
        bool frame_reused = false;   // the whole frame was the last one's (the same list and settings)
        PassTimes passes;            // all zero unless time_passes(true)
    };
    FrameStats last_frame() const;
    void time_passes(bool on);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Camera matrices as the renderer uses them (OpenGL conventions: right-handed
// view space looking down -z, clip depth -1..1).
Eigen::Matrix4f view_matrix(const Camera& camera);
Eigen::Matrix4f projection_matrix(const Camera& camera, float aspect);
// The pixel (x right, y down, pixel centres at +0.5) where a world point lands
// in an image of the given size; empty behind the camera.
std::optional<Vec2> project_to_pixel(const Camera& camera, int width, int height, const Vec3& point);

}  // namespace render
