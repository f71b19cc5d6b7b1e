// The passes of a frame, in the order Renderer::Impl::draw() runs them:
//
//   shadow_pass ....... the solids' depth from the light, fitted around them
//   begin_main_pass ... bind and clear the target, set the camera's uniforms
//   ground_pass ....... the ground quad with its grid
//   opaque_pass ....... solid meshes (instanced unit meshes, free meshes)
//   impostor_pass ..... solid spheres, ray-cast
//   translucent_pass .. ghosts, blended, after every solid
//   trail_pass ........ ribbons, blended, not writing depth
//   overlay_pass ...... text and plots in pixels, on top of everything (a
//                       frame drawn at a lower scale: over the window, by
//                       blit_to_window)
//   end_main_pass, resolve_msaa
//
// Each pass sets the GL state it needs and puts back what the next one
// expects; each is its own function so that a frame can be timed pass by pass.
#include "render/renderer_impl.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace render {
namespace {

using detail::kInstanceFloats;
using detail::PassItems;
using detail::ShadowLookup;
using detail::Viewpoint;

// Scene bounds of everything that casts a shadow, for fitting the light's view.
struct Bounds {
    Vec3 lo = Vec3::Constant(std::numeric_limits<float>::infinity());
    Vec3 hi = Vec3::Constant(-std::numeric_limits<float>::infinity());
    void add(const Vec3& p, float r) {
        if (!p.allFinite() || !std::isfinite(r)) return;
        lo = lo.cwiseMin(p - Vec3::Constant(r));
        hi = hi.cwiseMax(p + Vec3::Constant(r));
    }
    bool empty() const { return !(hi.x() >= lo.x()); }
};

Bounds caster_bounds(const PassItems& solid) {
    Bounds bounds;
    for (std::size_t i = 0; i < solid.spheres.size(); i += detail::kSphereFloats) {
        const float* s = solid.spheres.data() + i;
        bounds.add(Vec3(s[0], s[1], s[2]), s[3]);
    }
    for (const std::vector<float>* v : {&solid.cylinders, &solid.tubes, &solid.cones, &solid.boxes, &solid.planes}) {
        for (std::size_t i = 0; i < v->size(); i += kInstanceFloats) {
            const Eigen::Map<const Eigen::Matrix4f> m(v->data() + i);
            // The unit meshes lie within [-1, 1]^3: a sphere of radius sqrt(3) around the origin.
            const float reach = std::sqrt(3.0f) * m.block<3, 3>(0, 0).colwise().norm().maxCoeff();
            bounds.add(m.block<3, 1>(0, 3), reach);
        }
    }
    for (std::size_t i = 0; i < solid.mesh_vertices.size(); i += detail::kMeshVertexFloats) {
        bounds.add(Vec3(solid.mesh_vertices[i], solid.mesh_vertices[i + 1], solid.mesh_vertices[i + 2]), 0);
    }
    return bounds;
}

// The direction the light travels, unit; straight down for a zero vector.
Vec3 light_direction(const Light& light) {
    return light.direction.norm() > 0 ? Vec3(light.direction.normalized()) : Vec3(-Vec3::UnitY());
}

// The light's orthographic view, fitted around the casters.
Camera light_camera(const Bounds& bounds, const Vec3& light_dir) {
    const Vec3 centre = 0.5f * (bounds.lo + bounds.hi);
    const float radius = std::max(0.5f * (bounds.hi - bounds.lo).norm(), 1e-3f);
    Camera camera;
    camera.projection = Camera::Projection::orthographic;
    camera.eye = centre - light_dir * (2.0f * radius);
    camera.target = centre;
    camera.up = std::abs(light_dir.y()) < 0.99f ? Vec3::UnitY() : Vec3::UnitZ();
    camera.ortho_height = 2.0f * radius;
    camera.near_plane = 0.5f * radius;
    camera.far_plane = 3.5f * radius;
    return camera;
}

}  // namespace

// --- Shadow map ---------------------------------------------------------------------------

// Drawn only when a caster or the light changed since the map was last
// drawn: the same casters give the same map (a scene at rest, a paused
// viewer, the tiles of one frame).
ShadowLookup Renderer::Impl::shadow_pass(const Light& light, int size) {
    const Bounds bounds = caster_bounds(solid);
    if (!light.shadows || bounds.empty()) return {};
    ensure_shadow_map(size);
    const Vec3 light_dir = light_direction(light);
    if (shadow_valid && light_dir == shadow_light_dir && solid == shadow_casters) {
        stats.shadow_reused = true;
        return shadow_drawn;
    }
    const Camera from_light = light_camera(bounds, light_dir);
    ShadowLookup shadow;
    shadow.on = true;
    shadow.light_view_proj = projection_matrix(from_light, 1.0f) * view_matrix(from_light);
    shadow.texel = from_light.ortho_height / static_cast<float>(size);

    gl.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    gl.Viewport(0, 0, size, size);
    gl.DepthMask(GL_TRUE);
    gl.Clear(GL_DEPTH_BUFFER_BIT);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, 0);  // never sampled while it is being written
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(1.5f, 2.0f);
    const Viewpoint view{shadow.light_view_proj, from_light.eye, light_dir, true};
    const ShadowLookup unshadowed{false, shadow.light_view_proj, shadow.texel};
    for (GLuint program : {programs.mesh, programs.sphere}) set_lighting_uniforms(program, light, view, unshadowed);
    gl.UseProgram(programs.sphere);
    gl.Uniform1f(gl.GetUniformLocation(programs.sphere, "u_pixel_scale"), shadow.texel);
    gl.Uniform1i(gl.GetUniformLocation(programs.sphere, "u_multisample"), 0);
    draw_meshes(solid, true);
    draw_impostors(solid, true);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    shadow_valid = true;
    shadow_casters = solid;
    shadow_light_dir = light_dir;
    shadow_drawn = shadow;
    return shadow;
}

// --- Main passes: into the multisampled target (or straight into the resolve target) ----

void Renderer::Impl::begin_main_pass(const DrawList& list, const Viewpoint& camera, const ShadowLookup& shadow,
                                     float pixel_scale) {
    const bool multisample = samples > 1;
    gl.BindFramebuffer(GL_FRAMEBUFFER, multisample ? msaa_fbo : resolve_fbo);
    gl.Viewport(0, 0, width, height);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    gl.ClearColor(list.background.r, list.background.g, list.background.b, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);  // alpha stays 1: read-back RGBA is opaque
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, shadow.on ? shadow_map : 0);

    for (GLuint program : {programs.mesh, programs.sphere, programs.ground}) {
        set_lighting_uniforms(program, list.light, camera, shadow);
    }
    gl.UseProgram(programs.sphere);
    gl.Uniform1f(gl.GetUniformLocation(programs.sphere, "u_pixel_scale"), pixel_scale);
    gl.Uniform1i(gl.GetUniformLocation(programs.sphere, "u_multisample"), multisample ? 1 : 0);
}

void Renderer::Impl::ground_pass(const DrawList& list) {
    const Ground& g = list.ground;
    if (!g.enabled || !std::isfinite(g.height) || !(g.extent > 0)) return;
    const GLuint program = programs.ground;
    gl.UseProgram(program);
    auto loc = [&](const char* name) { return gl.GetUniformLocation(program, name); };
    gl.Uniform1f(loc("u_height"), g.height);
    gl.Uniform1f(loc("u_extent"), g.extent);
    gl.Uniform1f(loc("u_spacing"), g.grid_spacing > 0 ? g.grid_spacing : 1.0f);
    gl.Uniform1f(loc("u_major"), static_cast<float>(std::max(1, g.major_every)));
    gl.Uniform3f(loc("u_ground_color"), g.color.r, g.color.g, g.color.b);
    gl.Uniform3f(loc("u_line_color"), g.line_color.r, g.line_color.g, g.line_color.b);
    gl.Uniform3f(loc("u_sky_color"), list.background.r, list.background.g, list.background.b);
    gl.BindVertexArray(ground_vao);
    gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    stats.triangles += 2;
    ++stats.draw_calls;
}

// Solids are opaque; with MSAA the impostors' edge coverage goes to the
// samples (alpha to coverage). The meshes draw under the same state (their
// alpha is 1: every sample covered).
void Renderer::Impl::opaque_pass() {
    if (samples > 1) gl.Enable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    draw_meshes(solid, false);
    gl.Disable(GL_SAMPLE_ALPHA_TO_COVERAGE);
}

void Renderer::Impl::impostor_pass() {
    if (samples > 1) gl.Enable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    draw_impostors(solid, false);
    gl.Disable(GL_SAMPLE_ALPHA_TO_COVERAGE);
}

// Ghosts after every solid, blended; they keep writing depth so each shows
// only its front surface.
void Renderer::Impl::translucent_pass() {
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    draw_meshes(ghost, false);
    draw_impostors(ghost, false);
    gl.Disable(GL_BLEND);
}

// Trails: blended, tested against depth but not writing it.
void Renderer::Impl::trail_pass(const Eigen::Matrix4f& view_proj) {
    if (trails.empty()) return;
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.DepthMask(GL_FALSE);
    gl.UseProgram(programs.unlit);
    gl.UniformMatrix4fv(gl.GetUniformLocation(programs.unlit, "u_view_proj"), 1, GL_FALSE, view_proj.data());
    gl.BindVertexArray(trail_vao);
    detail::upload(gl, GL_ARRAY_BUFFER, trail_vertices, trails);
    const std::size_t vertices = trails.size() / detail::kTrailVertexFloats;
    gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices));
    stats.triangles += vertices / 3;
    ++stats.draw_calls;
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_BLEND);
}

// Overlays: pixels, blended on top of everything.
void Renderer::Impl::overlay_pass() {
    const std::vector<detail::OverlayVertex>& vertices = overlay.vertices();
    if (vertices.empty()) return;
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.Disable(GL_DEPTH_TEST);
    const GLuint program = programs.overlay;
    gl.UseProgram(program);
    // Laid out in the frame's pixels as asked (view_width x view_height),
    // into the frame's targets or, for a frame drawn at a lower scale, over
    // the window after the frame is stretched into it (blit_to_window).
    gl.Uniform2f(gl.GetUniformLocation(program, "u_viewport"), static_cast<float>(view_width),
                 static_cast<float>(view_height));
    gl.Uniform1i(gl.GetUniformLocation(program, "u_atlas"), 1);
    gl.Uniform1f(gl.GetUniformLocation(program, "u_on_edge"), Font::kOnEdge / 255.0f);
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_2D, atlas);
    gl.BindVertexArray(overlay_vao);
    detail::upload(gl, GL_ARRAY_BUFFER, overlay_vertices, vertices);
    gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()));
    stats.triangles += vertices.size() / 3;
    ++stats.draw_calls;
    gl.ActiveTexture(GL_TEXTURE0);
    gl.Enable(GL_DEPTH_TEST);
    gl.Disable(GL_BLEND);
}

// Every channel writable again, for the resolve and for whatever draws next.
void Renderer::Impl::end_main_pass() { gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE); }

// The multisampled frame averaged into the single-sample target read_back() reads.
void Renderer::Impl::resolve_msaa() {
    if (samples <= 1) return;
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
    gl.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

// --- What the passes share ------------------------------------------------------------------

void Renderer::Impl::set_lighting_uniforms(GLuint program, const Light& light, const Viewpoint& view,
                                           const ShadowLookup& shadow) {
    gl.UseProgram(program);
    auto loc = [&](const char* name) { return gl.GetUniformLocation(program, name); };
    const Vec3 dir = light_direction(light);
    gl.UniformMatrix4fv(loc("u_view_proj"), 1, GL_FALSE, view.view_proj.data());
    gl.UniformMatrix4fv(loc("u_light_view_proj"), 1, GL_FALSE, shadow.light_view_proj.data());
    gl.Uniform3f(loc("u_light_dir"), dir.x(), dir.y(), dir.z());
    gl.Uniform3f(loc("u_eye"), view.eye.x(), view.eye.y(), view.eye.z());
    gl.Uniform3f(loc("u_forward"), view.forward.x(), view.forward.y(), view.forward.z());
    gl.Uniform1i(loc("u_ortho"), view.ortho ? 1 : 0);
    gl.Uniform1f(loc("u_intensity"), light.intensity);
    gl.Uniform1f(loc("u_ambient"), light.ambient);
    gl.Uniform1f(loc("u_specular"), light.specular);
    gl.Uniform1f(loc("u_shininess"), light.shininess);
    gl.Uniform1i(loc("u_shadows"), shadow.on ? 1 : 0);
    gl.Uniform1f(loc("u_shadow_texel"), shadow.texel);
    gl.Uniform1i(loc("u_shadow_map"), 0);
}

void Renderer::Impl::draw_instanced(const detail::InstancedMesh& mesh, const std::vector<float>& instances) {
    if (instances.empty()) return;
    const auto count = static_cast<GLsizei>(instances.size() / kInstanceFloats);
    gl.BindVertexArray(mesh.vao);
    detail::upload(gl, GL_ARRAY_BUFFER, mesh.instances, instances);
    gl.DrawElementsInstanced(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr, count);
    stats.triangles += mesh.triangles() * static_cast<std::size_t>(count);
    ++stats.draw_calls;
}

// The free meshes, then the unit meshes instanced.
void Renderer::Impl::draw_meshes(const PassItems& items, bool depth_only) {
    gl.UseProgram(programs.mesh);
    gl.Uniform1i(gl.GetUniformLocation(programs.mesh, "u_depth_only"), depth_only ? 1 : 0);
    if (!items.mesh_indices.empty()) {
        gl.BindVertexArray(free_vao);
        detail::upload(gl, GL_ARRAY_BUFFER, free_vertices, items.mesh_vertices);
        detail::upload(gl, GL_ELEMENT_ARRAY_BUFFER, free_indices, items.mesh_indices);
        // The model matrix attributes are not arrays here: a constant identity.
        for (GLuint column = 0; column < 4; ++column) {
            gl.VertexAttrib4f(2 + column, column == 0 ? 1.0f : 0.0f, column == 1 ? 1.0f : 0.0f,
                              column == 2 ? 1.0f : 0.0f, column == 3 ? 1.0f : 0.0f);
        }
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(items.mesh_indices.size()), GL_UNSIGNED_INT, nullptr);
        stats.triangles += items.mesh_indices.size() / 3;
        ++stats.draw_calls;
    }
    draw_instanced(box, items.boxes);
    draw_instanced(plane, items.planes);
    draw_instanced(cylinder, items.cylinders);
    draw_instanced(tube, items.tubes);
    draw_instanced(cone, items.cones);
}

// The spheres: four corners, one instance per sphere.
void Renderer::Impl::draw_impostors(const PassItems& items, bool depth_only) {
    if (items.spheres.empty()) return;
    gl.UseProgram(programs.sphere);
    gl.Uniform1i(gl.GetUniformLocation(programs.sphere, "u_depth_only"), depth_only ? 1 : 0);
    const auto count = static_cast<GLsizei>(items.spheres.size() / detail::kSphereFloats);
    gl.BindVertexArray(quad_vao);
    detail::upload(gl, GL_ARRAY_BUFFER, sphere_instances, items.spheres);
    gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count);
    stats.triangles += 2 * static_cast<std::size_t>(count);
    ++stats.draw_calls;
}

}  // namespace render
