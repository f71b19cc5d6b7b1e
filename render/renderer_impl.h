// The renderer's private parts, shared by the files that make it up (private
// to render/; callers include renderer.h):
//
//   renderer.cpp            the frame as a list of passes, input checks
//   renderer_read.cpp       reading frames back through pixel-buffer objects
//   renderer_shaders.cpp    the GLSL sources, compiled and linked into programs
//   renderer_resources.cpp  GL objects: unit meshes, vertex arrays, the font
//                           atlas, render targets, the shadow map
//   renderer_items.cpp      the draw list flattened into per-pass instance arrays
//   renderer_passes.cpp     the passes: shadow map, ground, opaque meshes, sphere
//                           impostors, translucent ghosts, trails, overlays, resolve
//   camera.cpp              view and projection matrices
//
// The order of a frame's passes is in renderer.cpp (Renderer::Impl::draw).
#pragma once

#include "render/overlay.h"
#include "render/renderer.h"
#include "render/shapes.h"

#include <glad/gl.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace render {
namespace detail {

// --- Programs (renderer_shaders.cpp) ------------------------------------------------

struct Programs {
    GLuint mesh = 0;     // lit, instanced unit meshes and free meshes
    GLuint sphere = 0;   // lit, ray-cast sphere impostors
    GLuint ground = 0;   // lit, the ground with its grid
    GLuint unlit = 0;    // trails
    GLuint overlay = 0;  // text, plots and lines in pixels
};
// Throws RenderError(gl) with the driver's log when one does not compile or link.
Programs link_programs(const GladGLContext& gl);
void delete_programs(const GladGLContext& gl, const Programs& programs);

// --- Buffers (renderer_resources.cpp) -------------------------------------------------

// A unit mesh ready to instance: its vertices, its indices, and a buffer of
// per-instance data (model matrix columns and colour, 20 floats).
struct InstancedMesh {
    GLuint vao = 0, vertices = 0, indices = 0, instances = 0;
    GLsizei index_count = 0;
    std::size_t triangles() const { return static_cast<std::size_t>(index_count) / 3; }
};

constexpr int kInstanceFloats = 20;
constexpr int kSphereFloats = 8;       // x y z r, r g b a
constexpr int kMeshVertexFloats = 10;  // x y z nx ny nz r g b a
constexpr int kTrailVertexFloats = 7;  // x y z r g b a

template <typename T>
void upload(const GladGLContext& gl, GLenum target, GLuint buffer, const std::vector<T>& data) {
    gl.BindBuffer(target, buffer);
    // Orphan then fill: the driver need not wait for the previous frame's use.
    gl.BufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), nullptr, GL_STREAM_DRAW);
    if (!data.empty())
        gl.BufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data(), GL_STREAM_DRAW);
}

// --- Frame items (renderer_items.cpp) -------------------------------------------------

// Everything of one pass (solid or ghost), flattened for instanced drawing.
struct PassItems {
    std::vector<float> spheres;    // x y z r, r g b a
    std::vector<float> cylinders;  // closed cylinders
    std::vector<float> tubes;      // open cylinders (capsule sides)
    std::vector<float> cones;
    std::vector<float> boxes;
    std::vector<float> planes;
    std::vector<float> mesh_vertices;  // x y z nx ny nz r g b a
    std::vector<std::uint32_t> mesh_indices;
    void clear() {
        for (auto* v : {&spheres, &cylinders, &tubes, &cones, &boxes, &planes, &mesh_vertices}) v->clear();
        mesh_indices.clear();
    }
    // Every number the same (a NaN never is: such a list is drawn again).
    bool operator==(const PassItems&) const = default;
};

// Flattens the draw list's shapes into the solid and the ghost pass (both
// cleared first), in the list's order.
void flatten_shapes(const DrawList& list, PassItems& solid, PassItems& ghost);
// The ribbons as triangles (x y z r g b a per vertex), turned toward the eye.
void build_trails(const std::vector<Ribbon>& ribbons, bool ortho, const Vec3& eye, const Vec3& forward,
                  std::vector<float>& trails);

// --- Views (renderer_passes.cpp) --------------------------------------------------------

// Where the lit shaders look from: the camera, or the light for the shadow map.
struct Viewpoint {
    Eigen::Matrix4f view_proj = Eigen::Matrix4f::Identity();
    Vec3 eye = Vec3::Zero();        // m
    Vec3 forward = -Vec3::UnitZ();  // unit, the viewing direction
    bool ortho = false;
};

// The shadow map as the lit shaders read it.
struct ShadowLookup {
    bool on = false;
    Eigen::Matrix4f light_view_proj = Eigen::Matrix4f::Identity();
    float texel = 0;  // m, world size of one shadow-map texel
};

}  // namespace detail

struct Renderer::Impl {
    GlContext& context;
    const GladGLContext& gl;
    const Font& font;

    detail::Programs programs;
    detail::InstancedMesh cylinder, tube, cone, box, plane;
    GLuint quad_vao = 0, quad_vertices = 0, sphere_instances = 0;  // impostors: 4 corners, instanced
    GLuint ground_vao = 0, ground_vertices = 0;
    GLuint free_vao = 0, free_vertices = 0, free_indices = 0;  // meshes of the frame
    GLuint trail_vao = 0, trail_vertices = 0;
    GLuint overlay_vao = 0, overlay_vertices = 0;
    GLuint atlas = 0;

    // Render targets: multisampled colour + depth when MSAA is on, resolved
    // into a single-sample colour + depth target that read_back() reads.
    int width = 0, height = 0, samples = 0;
    // The last frame's size as asked (RenderSettings' width x height): the
    // targets are this at its scale; overlays and the window use this.
    int view_width = 0, view_height = 0;
    // The frame was drawn on fewer pixels than asked (RenderSettings::scale
    // below 1): its overlays are left to blit_to_window.
    bool scaled_down() const { return width != view_width || height != view_height; }
    GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0;
    GLuint resolve_fbo = 0, resolve_color = 0, resolve_depth = 0;
    int shadow_size = 0;
    GLuint shadow_fbo = 0, shadow_map = 0;
    // What the shadow map holds: drawn from these casters along this light
    // (shadow_pass draws it again only when either changed).
    bool shadow_valid = false;
    detail::PassItems shadow_casters;
    Vec3 shadow_light_dir = Vec3::Zero();
    detail::ShadowLookup shadow_drawn;

    // Read-back through pixel-buffer objects (renderer_read.cpp): a read is
    // queued behind the frame into a buffer of its own and collected later,
    // so that the next frame can be drawn meanwhile.
    // A pixel-pack buffer and the bytes of its storage: a read of a size the
    // storage holds reuses it (new storage for each read, 3.7 MB a 720p
    // frame, came as fresh pages: about a thousand page faults a frame).
    struct PackBuffer {
        GLuint buffer = 0;
        std::size_t storage = 0;  // bytes
    };
    struct PendingRead {
        PackBuffer pack;
        int width = 0, height = 0;
    };
    std::vector<PackBuffer> free_buffers;  // not holding a read
    std::deque<PendingRead> queued_reads;  // queue_read_back()'s, oldest first

    detail::PassItems solid, ghost;
    std::vector<float> trails;  // x y z r g b a per vertex, triangles
    // What the last frame was drawn from (draw() skips a frame drawn from the
    // same): its settings, the list's numbers outside the items (camera,
    // light, ground, background), the flattened items, the overlays.
    struct FrameInputs {
        RenderSettings settings;
        std::vector<float> uniforms;
        detail::PassItems solid, ghost;
        std::vector<float> trails;
        std::vector<detail::OverlayVertex> overlay;
    };
    FrameInputs last_inputs;
    detail::OverlayBatch overlay;
    FrameStats stats;
    bool has_frame = false;
    bool time_passes = false;  // Renderer::time_passes

    Impl(GlContext& c, const Font& f) : context(c), gl(c.gl()), font(f), overlay(f) {}

    // renderer.cpp: the frame.
    void draw(const DrawList& list, const RenderSettings& settings);
    void check_driver_limits(const RenderSettings& settings);
    void check_errors(const char* where);
    // pixels: pixel_scale of the frame's targets (the impostors' margin).
    bool same_as_last_frame(const DrawList& list, const RenderSettings& settings, const detail::Viewpoint& camera,
                            float pixels);

    // renderer_read.cpp: reading frames back.
    PendingRead start_read(GLuint framebuffer, const char* what);
    void finish_read(const PendingRead& read, int channels, const char* what, Image& into);

    // renderer_resources.cpp: GL objects.
    void create_resources();
    void create_vertex_arrays();  // impostor quad, ground, free meshes, trails, overlays
    void upload_atlas();
    void destroy_resources();
    void ensure_targets(int w, int h, int s);
    void ensure_shadow_map(int size);

    // renderer_items.cpp: the draw list, flattened.
    void prepare(const DrawList& list, const Vec3& eye, const Vec3& forward);

    // renderer_passes.cpp: the passes, in the order draw() runs them.
    detail::ShadowLookup shadow_pass(const Light& light, int size);
    void begin_main_pass(const DrawList& list, const detail::Viewpoint& camera, const detail::ShadowLookup& shadow,
                         float pixel_scale);
    void ground_pass(const DrawList& list);
    void opaque_pass();
    void impostor_pass();
    void translucent_pass();
    void trail_pass(const Eigen::Matrix4f& view_proj);
    void overlay_pass();
    void end_main_pass();
    void resolve_msaa();

    // What the passes share.
    void set_lighting_uniforms(GLuint program, const Light& light, const detail::Viewpoint& view,
                               const detail::ShadowLookup& shadow);
    void draw_meshes(const detail::PassItems& items, bool depth_only);
    void draw_impostors(const detail::PassItems& items, bool depth_only);
    void draw_instanced(const detail::InstancedMesh& mesh, const std::vector<float>& instances);
};

}  // namespace render
