// The renderer's GL objects: the unit meshes ready to instance, the vertex
// arrays each pass draws from, the font atlas, the render targets (resized
// with the image) and the shadow map (resized with its setting). Its own file:
// what is made once, or again only when a size changes, apart from what is
// done every frame.
#include "render/renderer_impl.h"

#include <string>

namespace render {
namespace detail {
namespace {

void float_attribute(const GladGLContext& gl, GLuint location, int size, int stride_floats, int offset_floats,
                     GLuint divisor) {
    gl.EnableVertexAttribArray(location);
    gl.VertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, stride_floats * static_cast<GLsizei>(sizeof(float)),
                           reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset_floats) * sizeof(float)));
    gl.VertexAttribDivisor(location, divisor);
}

// A new vertex array and its vertex buffer, both left bound.
void bind_new_array(const GladGLContext& gl, GLuint& vao, GLuint& vertices) {
    gl.GenVertexArrays(1, &vao);
    gl.GenBuffers(1, &vertices);
    gl.BindVertexArray(vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, vertices);
}

InstancedMesh make_instanced(const GladGLContext& gl, const UnitMesh& mesh) {
    InstancedMesh m;
    bind_new_array(gl, m.vao, m.vertices);
    gl.GenBuffers(1, &m.indices);
    gl.GenBuffers(1, &m.instances);
    gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(float)), mesh.vertices.data(),
                  GL_STATIC_DRAW);
    float_attribute(gl, 0, 3, 6, 0, 0);
    float_attribute(gl, 1, 3, 6, 3, 0);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.indices);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                  mesh.indices.data(), GL_STATIC_DRAW);
    m.index_count = static_cast<GLsizei>(mesh.indices.size());
    gl.BindBuffer(GL_ARRAY_BUFFER, m.instances);
    for (GLuint column = 0; column < 4; ++column) float_attribute(gl, 2 + column, 4, kInstanceFloats, 4 * column, 1);
    float_attribute(gl, 6, 4, kInstanceFloats, 16, 1);
    gl.BindVertexArray(0);
    return m;
}

void destroy(const GladGLContext& gl, InstancedMesh& m) {
    gl.DeleteVertexArrays(1, &m.vao);
    const GLuint buffers[] = {m.vertices, m.indices, m.instances};
    gl.DeleteBuffers(3, buffers);
}

}  // namespace
}  // namespace detail

using detail::bind_new_array;
using detail::float_attribute;
using detail::kMeshVertexFloats;
using detail::kSphereFloats;
using detail::kTrailVertexFloats;

void Renderer::Impl::create_resources() {
    programs = detail::link_programs(gl);

    cylinder = detail::make_instanced(gl, detail::unit_cylinder(true));
    tube = detail::make_instanced(gl, detail::unit_cylinder(false));
    cone = detail::make_instanced(gl, detail::unit_cone());
    box = detail::make_instanced(gl, detail::unit_box());
    plane = detail::make_instanced(gl, detail::unit_quad());

    create_vertex_arrays();
    upload_atlas();
    check_errors("creating the renderer");
}

void Renderer::Impl::create_vertex_arrays() {
    // Sphere impostors: a triangle strip over four corners, one instance per sphere.
    const float corners[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    bind_new_array(gl, quad_vao, quad_vertices);
    gl.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    float_attribute(gl, 0, 2, 2, 0, 0);
    gl.GenBuffers(1, &sphere_instances);
    gl.BindBuffer(GL_ARRAY_BUFFER, sphere_instances);
    float_attribute(gl, 1, 4, kSphereFloats, 0, 1);
    float_attribute(gl, 2, 4, kSphereFloats, 4, 1);

    // The ground: the unit quad's vertices, scaled in the shader.
    const float ground[] = {-1, 0, -1, 1, 0, -1, -1, 0, 1, 1, 0, 1};
    bind_new_array(gl, ground_vao, ground_vertices);
    gl.BufferData(GL_ARRAY_BUFFER, sizeof ground, ground, GL_STATIC_DRAW);
    float_attribute(gl, 0, 3, 3, 0, 0);

    // Free meshes: position, normal, colour per vertex; the model matrix
    // attributes stay disabled and read a constant identity.
    bind_new_array(gl, free_vao, free_vertices);
    float_attribute(gl, 0, 3, kMeshVertexFloats, 0, 0);
    float_attribute(gl, 1, 3, kMeshVertexFloats, 3, 0);
    float_attribute(gl, 6, 4, kMeshVertexFloats, 6, 0);
    gl.GenBuffers(1, &free_indices);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, free_indices);

    // Trails: position and colour per vertex.
    bind_new_array(gl, trail_vao, trail_vertices);
    float_attribute(gl, 0, 3, kTrailVertexFloats, 0, 0);
    float_attribute(gl, 1, 4, kTrailVertexFloats, 3, 0);

    // Overlays: detail::OverlayVertex, in pixels.
    bind_new_array(gl, overlay_vao, overlay_vertices);
    constexpr int kOverlayFloats = sizeof(detail::OverlayVertex) / sizeof(float);
    float_attribute(gl, 0, 2, kOverlayFloats, 0, 0);
    float_attribute(gl, 1, 2, kOverlayFloats, 2, 0);
    float_attribute(gl, 2, 4, kOverlayFloats, 4, 0);
    float_attribute(gl, 3, 2, kOverlayFloats, 8, 0);
    gl.BindVertexArray(0);
}

void Renderer::Impl::upload_atlas() {
    // The font atlas: one channel, sampled with bilinear filtering.
    gl.GenTextures(1, &atlas);
    gl.BindTexture(GL_TEXTURE_2D, atlas);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, font.atlas_width(), font.atlas_height(), 0, GL_RED, GL_UNSIGNED_BYTE,
                  font.atlas().data());
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void Renderer::Impl::destroy_resources() {
    detail::delete_programs(gl, programs);
    for (detail::InstancedMesh* m : {&cylinder, &tube, &cone, &box, &plane}) detail::destroy(gl, *m);
    const GLuint vaos[] = {quad_vao, ground_vao, free_vao, trail_vao, overlay_vao};
    gl.DeleteVertexArrays(5, vaos);
    const GLuint buffers[] = {quad_vertices, sphere_instances, ground_vertices, free_vertices,
                              free_indices,  trail_vertices,   overlay_vertices};
    gl.DeleteBuffers(7, buffers);
    gl.DeleteTextures(1, &atlas);
    for (const PendingRead& read : queued_reads) free_buffers.push_back(read.pack);
    queued_reads.clear();
    for (const PackBuffer& pack : free_buffers) gl.DeleteBuffers(1, &pack.buffer);
    free_buffers.clear();
    ensure_targets(0, 0, 0);
    ensure_shadow_map(0);
}

void Renderer::Impl::ensure_targets(int w, int h, int s) {
    if (w == width && h == height && s == samples) return;
    if (msaa_fbo != 0) {
        gl.DeleteFramebuffers(1, &msaa_fbo);
        const GLuint rbs[] = {msaa_color, msaa_depth};
        gl.DeleteRenderbuffers(2, rbs);
        msaa_fbo = msaa_color = msaa_depth = 0;
    }
    if (resolve_fbo != 0) {
        gl.DeleteFramebuffers(1, &resolve_fbo);
        const GLuint rbs[] = {resolve_color, resolve_depth};
        gl.DeleteRenderbuffers(2, rbs);
        resolve_fbo = resolve_color = resolve_depth = 0;
    }
    width = w, height = h, samples = s;
    has_frame = false;
    if (w == 0) return;
    auto make = [&](GLuint& fbo, GLuint& color, GLuint& depth, int n) {
        gl.GenFramebuffers(1, &fbo);
        gl.GenRenderbuffers(1, &color);
        gl.GenRenderbuffers(1, &depth);
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
        gl.BindRenderbuffer(GL_RENDERBUFFER, color);
        gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, n, GL_RGBA8, w, h);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
        gl.BindRenderbuffer(GL_RENDERBUFFER, depth);
        gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, n, GL_DEPTH_COMPONENT24, w, h);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw RenderError(ErrorKind::gl, "framebuffer " + std::to_string(w) + "x" + std::to_string(h) + " with " +
                                                 std::to_string(n) + " samples is incomplete (status " +
                                                 std::to_string(status) + ")");
        }
    };
    make(resolve_fbo, resolve_color, resolve_depth, 0);
    if (s > 1) make(msaa_fbo, msaa_color, msaa_depth, s);
}

void Renderer::Impl::ensure_shadow_map(int size) {
    if (size == shadow_size) return;
    shadow_valid = false;
    if (shadow_fbo != 0) {
        gl.DeleteFramebuffers(1, &shadow_fbo);
        gl.DeleteTextures(1, &shadow_map);
        shadow_fbo = shadow_map = 0;
    }
    shadow_size = size;
    if (size == 0) return;
    gl.GenTextures(1, &shadow_map);
    gl.BindTexture(GL_TEXTURE_2D, shadow_map);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, nullptr);
    // Hardware comparison with bilinear filtering: each lookup is a 2x2 PCF.
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    gl.GenFramebuffers(1, &shadow_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_map, 0);
    gl.DrawBuffer(GL_NONE);
    gl.ReadBuffer(GL_NONE);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw RenderError(ErrorKind::gl, "shadow map framebuffer is incomplete");
    }
}

}  // namespace render
