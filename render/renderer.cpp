// The renderer (see renderer.h).
//
// Contents
//   1. Shaders ............ GLSL 3.30 core: lighting, lit meshes, sphere
//                           impostors, ground grid, unlit trails, overlays
//   2. GL helpers ......... compile, link, buffers, vertex attributes
//   3. Frame preparation .. the draw list flattened into instance arrays
//   4. Passes ............. shadow map, solids, ghosts, trails, overlays
//   5. Camera maths
//
// A frame: clear -> shadow pass (light's view, depth only) -> solid pass ->
// ghost pass (blended, after all solids) -> trails -> overlays -> MSAA resolve.
// Colours arrive in sRGB; lighting is done in linear light and encoded back.
#include "render/renderer.h"

#include "render/overlay.h"
#include "render/shapes.h"

#include <glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace render {
namespace {

// --- 1. Shaders -----------------------------------------------------------------

constexpr const char* kVersion = "#version 330 core\n";

// Lighting shared by every lit shader: Blinn-Phong from one directional light,
// hemispherical ambient, and a shadow-map lookup (normal offset against acne,
// four bilinear PCF taps for a soft edge).
constexpr const char* kLighting = R"(
uniform vec3 u_light_dir;       // unit, the direction the light travels
uniform vec3 u_eye;             // m, camera position
uniform vec3 u_forward;         // unit, camera viewing direction
uniform bool u_ortho;
uniform float u_intensity;
uniform float u_ambient;
uniform float u_specular;
uniform float u_shininess;
uniform bool u_shadows;
uniform mat4 u_light_view_proj;
uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_texel;   // m, world size of one shadow-map texel

vec3 to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 to_srgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

float shadow_factor(vec3 world, vec3 n) {
    if (!u_shadows) return 1.0;
    vec4 ls = u_light_view_proj * vec4(world + n * (1.5 * u_shadow_texel), 1.0);
    vec3 c = ls.xyz / ls.w * 0.5 + 0.5;
    if (c.x < 0.0 || c.x > 1.0 || c.y < 0.0 || c.y > 1.0) return 1.0;
    float depth = min(c.z, 1.0) - 0.0008;
    float texel = 1.0 / float(textureSize(u_shadow_map, 0).x);
    float lit = 0.0;
    lit += texture(u_shadow_map, vec3(c.xy + vec2(-0.75, -0.75) * texel, depth));
    lit += texture(u_shadow_map, vec3(c.xy + vec2(0.75, -0.75) * texel, depth));
    lit += texture(u_shadow_map, vec3(c.xy + vec2(-0.75, 0.75) * texel, depth));
    lit += texture(u_shadow_map, vec3(c.xy + vec2(0.75, 0.75) * texel, depth));
    return lit * 0.25;
}

vec3 shade(vec3 base_srgb, vec3 world, vec3 n, float specular_scale) {
    vec3 base = to_linear(base_srgb);
    vec3 v = u_ortho ? -u_forward : normalize(u_eye - world);
    if (dot(n, v) < 0.0) n = -n;  // both faces lit (cloth)
    vec3 l = -u_light_dir;
    float ndl = max(dot(n, l), 0.0);
    float lit = ndl > 0.0 ? shadow_factor(world, n) : 1.0;
    float spec = ndl > 0.0 ? pow(max(dot(n, normalize(l + v)), 0.0), u_shininess) * u_specular * specular_scale : 0.0;
    float sky = 0.5 + 0.5 * n.y;  // hemisphere: full ambient facing up, 60% facing down
    vec3 color = base * u_ambient * mix(0.6, 1.0, sky) + lit * (base * u_intensity * ndl + vec3(spec));
    return to_srgb(color);
}
)";

// Instanced unit meshes (cylinders, cones, boxes, planes) and free meshes.
constexpr const char* kMeshVertex = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_model0;
layout(location = 3) in vec4 a_model1;
layout(location = 4) in vec4 a_model2;
layout(location = 5) in vec4 a_model3;
layout(location = 6) in vec4 a_color;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
void main() {
    mat4 model = mat4(a_model0, a_model1, a_model2, a_model3);
    vec4 world = model * vec4(a_position, 1.0);
    v_world = world.xyz;
    v_normal = transpose(inverse(mat3(model))) * a_normal;
    v_color = a_color;
    gl_Position = u_view_proj * world;
}
)";

constexpr const char* kMeshFragment = R"(
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
uniform bool u_depth_only;
out vec4 o_color;
void main() {
    if (u_depth_only) { o_color = vec4(0.0); return; }
    o_color = vec4(shade(v_color.rgb, v_world, normalize(v_normal), 1.0), v_color.a);
}
)";

// Spheres as ray-cast impostors: a square facing the eye, in the plane through
// the centre perpendicular to the line of sight, just large enough to hold
// the silhouette (the tangent cone's circle, radius r d / sqrt(d^2 - r^2)) plus
// two pixels. The fragment shader intersects the view ray with the sphere,
// writes the true depth, and turns the distance to the silhouette into
// coverage: alpha-to-coverage with MSAA, a blend for ghosts, a hard cut
// otherwise.
constexpr const char* kSphereVertex = R"(
layout(location = 0) in vec2 a_corner;
layout(location = 1) in vec4 a_sphere;  // centre (m), radius (m)
layout(location = 2) in vec4 a_color;
uniform mat4 u_view_proj;
uniform float u_pixel_scale;  // m per pixel at unit distance (perspective) or overall (orthographic)
out vec3 v_world;
flat out vec4 v_sphere;
flat out vec4 v_color;
void main() {
    vec3 c = a_sphere.xyz;
    float r = a_sphere.w;
    vec3 n;
    float s;
    float pixel;
    if (u_ortho) {
        n = -u_forward;
        s = r;
        pixel = u_pixel_scale;
    } else {
        vec3 to_eye = u_eye - c;
        float d = max(length(to_eye), 1e-6);
        n = to_eye / d;
        s = d > 1.001 * r ? r * d / sqrt(d * d - r * r) : 30.0 * r;
        pixel = u_pixel_scale * d;
    }
    vec3 u = normalize(cross(abs(n.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), n));
    vec3 v = cross(n, u);
    vec3 p = c + (a_corner.x * u + a_corner.y * v) * (s + 2.0 * pixel);
    v_world = p;
    v_sphere = a_sphere;
    v_color = a_color;
    gl_Position = u_view_proj * vec4(p, 1.0);
}
)";

constexpr const char* kSphereFragment = R"(
in vec3 v_world;
flat in vec4 v_sphere;
flat in vec4 v_color;
uniform mat4 u_view_proj;
uniform bool u_depth_only;
uniform bool u_multisample;
out vec4 o_color;
void main() {
    vec3 c = v_sphere.xyz;
    float r = v_sphere.w;
    vec3 rd = u_ortho ? u_forward : normalize(v_world - u_eye);
    vec3 ro = u_ortho ? v_world - u_forward * (2.0 * r) : u_eye;
    vec3 oc = ro - c;
    float b = dot(oc, rd);
    float q = sqrt(max(dot(oc, oc) - b * b, 0.0));  // distance from the centre to the ray, m
    float coverage = clamp((r - q) / max(fwidth(q), 1e-9) + 0.5, 0.0, 1.0);
    bool ghost = v_color.a < 1.0;
    if (coverage <= 0.0 || (!u_multisample && !ghost && coverage < 0.5)) discard;
    float t = -b - sqrt(max(r * r - q * q, 0.0));
    vec3 hit = ro + t * rd;
    vec4 clip = u_view_proj * vec4(hit, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
    if (u_depth_only) { o_color = vec4(0.0); return; }
    vec3 color = shade(v_color.rgb, hit, (hit - c) / r, 1.0);
    o_color = vec4(color, ghost ? v_color.a * coverage : (u_multisample ? coverage : 1.0));
}
)";

// The ground: a large quad with a grid drawn in the shader (lines one pixel
// wide whatever the distance, fading where the cells get smaller than a few
// pixels), lit and shadowed like everything else, fading into the sky far off.
constexpr const char* kGroundVertex = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform float u_height;
uniform float u_extent;
out vec3 v_world;
void main() {
    v_world = vec3(a_position.x * u_extent, u_height, a_position.z * u_extent);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}
)";

constexpr const char* kGroundFragment = R"(
in vec3 v_world;
uniform float u_spacing;
uniform float u_major;
uniform float u_extent;
uniform vec3 u_ground_color;
uniform vec3 u_line_color;
uniform vec3 u_sky_color;
out vec4 o_color;
float grid_line(vec2 coord, float width_px) {
    vec2 w = fwidth(coord);
    vec2 d = abs(fract(coord - 0.5) - 0.5) / max(w, vec2(1e-6));
    float line = 1.0 - clamp(min(d.x, d.y) - 0.5 * width_px + 0.5, 0.0, 1.0);
    return line * (1.0 - smoothstep(0.15, 0.45, max(w.x, w.y)));
}
void main() {
    vec2 coord = v_world.xz / u_spacing;
    float minor = grid_line(coord, 1.0) * 0.45;
    float major = grid_line(coord / u_major, 1.6) * 0.85;
    vec3 base = mix(u_ground_color, u_line_color, max(minor, major));
    vec3 color = shade(base, v_world, vec3(0.0, 1.0, 0.0), 0.3);
    float far = u_ortho ? 0.0 : smoothstep(0.45 * u_extent, 0.95 * u_extent, length(v_world - u_eye));
    o_color = vec4(mix(color, u_sky_color, far), 1.0);
}
)";

// Trails: camera-facing bands built on the CPU, unlit, blended.
constexpr const char* kUnlitVertex = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_view_proj;
out vec4 v_color;
void main() {
    v_color = a_color;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";

constexpr const char* kUnlitFragment = R"(
in vec4 v_color;
out vec4 o_color;
void main() { o_color = v_color; }
)";

// Overlays in pixels: fills, lines with a one-pixel fade at their edges, and
// glyphs thresholded from the signed-distance atlas.
constexpr const char* kOverlayVertex = R"(
layout(location = 0) in vec2 a_position;  // px, origin top-left
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_color;
layout(location = 3) in vec2 a_edge;      // distance from the line's centre, half width (px)
uniform vec2 u_viewport;
out vec2 v_uv;
out vec4 v_color;
out vec2 v_edge;
void main() {
    v_uv = a_uv;
    v_color = a_color;
    v_edge = a_edge;
    gl_Position = vec4(a_position.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_position.y / u_viewport.y * 2.0, 0.0, 1.0);
}
)";

constexpr const char* kOverlayFragment = R"(
in vec2 v_uv;
in vec4 v_color;
in vec2 v_edge;
uniform sampler2D u_atlas;
uniform float u_on_edge;  // atlas value on a glyph's outline, 0..1
out vec4 o_color;
void main() {
    float alpha;
    if (v_edge.x < -1e5) {
        float d = texture(u_atlas, v_uv).r;
        float w = max(fwidth(d) * 0.7, 1e-3);
        // Small text: thin strokes (an i's dot, an underscore) are narrower
        // than the smoothing ramp and would fade away; the edge moves outward
        // by a fraction of the ramp so they keep their ink.
        float edge = u_on_edge - 0.35 * w;
        alpha = smoothstep(edge - w, edge + w, d);
    } else {
        alpha = clamp(v_edge.y + 0.5 - abs(v_edge.x), 0.0, 1.0);
    }
    o_color = vec4(v_color.rgb, v_color.a * alpha);
}
)";

// --- 2. GL helpers ----------------------------------------------------------------

GLuint compile(const GladGLContext& gl, GLenum type, const std::vector<const char*>& sources, const char* name) {
    const GLuint shader = gl.CreateShader(type);
    gl.ShaderSource(shader, static_cast<GLsizei>(sources.size()), sources.data(), nullptr);
    gl.CompileShader(shader);
    GLint ok = 0;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
        gl.DeleteShader(shader);
        throw RenderError(ErrorKind::gl, std::string("shader '") + name + "' does not compile: " + log);
    }
    return shader;
}

GLuint link(const GladGLContext& gl, const char* vertex, const char* fragment, bool lit, const char* name) {
    std::vector<const char*> vs{kVersion}, fs{kVersion};
    if (lit) {
        vs.push_back(kLighting);
        fs.push_back(kLighting);
    }
    vs.push_back(vertex);
    fs.push_back(fragment);
    const GLuint v = compile(gl, GL_VERTEX_SHADER, vs, name);
    const GLuint f = compile(gl, GL_FRAGMENT_SHADER, fs, name);
    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, v);
    gl.AttachShader(program, f);
    gl.LinkProgram(program);
    gl.DeleteShader(v);
    gl.DeleteShader(f);
    GLint ok = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
        gl.DeleteProgram(program);
        throw RenderError(ErrorKind::gl, std::string("program '") + name + "' does not link: " + log);
    }
    return program;
}

void float_attribute(const GladGLContext& gl, GLuint location, int size, int stride_floats, int offset_floats,
                     GLuint divisor) {
    gl.EnableVertexAttribArray(location);
    gl.VertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, stride_floats * static_cast<GLsizei>(sizeof(float)),
                           reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset_floats) * sizeof(float)));
    gl.VertexAttribDivisor(location, divisor);
}

template <typename T>
void upload(const GladGLContext& gl, GLenum target, GLuint buffer, const std::vector<T>& data) {
    gl.BindBuffer(target, buffer);
    // Orphan then fill: the driver need not wait for the previous frame's use.
    gl.BufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), nullptr, GL_STREAM_DRAW);
    if (!data.empty())
        gl.BufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data(), GL_STREAM_DRAW);
}

// A unit mesh ready to instance: its vertices, its indices, and a buffer of
// per-instance data (model matrix columns and colour, 20 floats).
struct InstancedMesh {
    GLuint vao = 0, vertices = 0, indices = 0, instances = 0;
    GLsizei index_count = 0;
    std::size_t triangles() const { return static_cast<std::size_t>(index_count) / 3; }
};

constexpr int kInstanceFloats = 20;

InstancedMesh make_instanced(const GladGLContext& gl, const detail::UnitMesh& mesh) {
    InstancedMesh m;
    gl.GenVertexArrays(1, &m.vao);
    gl.GenBuffers(1, &m.vertices);
    gl.GenBuffers(1, &m.indices);
    gl.GenBuffers(1, &m.instances);
    gl.BindVertexArray(m.vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vertices);
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

// --- 3. Frame preparation ---------------------------------------------------------

// A ghost: lighter and semi-transparent, so it reads as "the other solution"
// over the solid one and the scene behind shows through.
Color ghost_color(const Color& c) {
    constexpr float kLighten = 0.35f;  // share of white mixed in
    constexpr float kAlpha = 0.4f;     // opacity of a ghost
    return Color{c.r + (1 - c.r) * kLighten, c.g + (1 - c.g) * kLighten, c.b + (1 - c.b) * kLighten, kAlpha * c.a};
}

Color shown_color(const Look& look) {
    if (look.ghost) return ghost_color(look.color);
    Color c = look.color;
    c.a = 1.0f;  // solids are opaque; transparency is what ghosts are for
    return c;
}

void push_instance(std::vector<float>& out, const Eigen::Matrix4f& model, const Color& color) {
    out.insert(out.end(), model.data(), model.data() + 16);
    out.insert(out.end(), {color.r, color.g, color.b, color.a});
}

bool finite_positive(float value) { return std::isfinite(value) && value > 0.0f; }

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
};

void add_sphere(PassItems& pass, const Vec3& c, float r, const Color& color) {
    pass.spheres.insert(pass.spheres.end(), {c.x(), c.y(), c.z(), r, color.r, color.g, color.b, color.a});
}

void add_mesh(PassItems& pass, const Mesh& mesh, const Color& look_color, bool ghost) {
    const std::size_t n = mesh.positions.size();
    if (n == 0 || mesh.indices.empty()) return;
    if (!mesh.normals.empty() && mesh.normals.size() != n) {
        throw RenderError(ErrorKind::bad_input, "mesh has " + std::to_string(n) + " positions but " +
                                                    std::to_string(mesh.normals.size()) + " normals");
    }
    if (!mesh.colors.empty() && mesh.colors.size() != n) {
        throw RenderError(ErrorKind::bad_input, "mesh has " + std::to_string(n) + " positions but " +
                                                    std::to_string(mesh.colors.size()) + " colours");
    }
    if (mesh.indices.size() % 3 != 0) {
        throw RenderError(ErrorKind::bad_input,
                          "mesh index count " + std::to_string(mesh.indices.size()) + " is not a multiple of 3");
    }
    for (std::uint32_t index : mesh.indices) {
        if (index >= n) {
            throw RenderError(ErrorKind::bad_input, "mesh index " + std::to_string(index) + " out of range (" +
                                                        std::to_string(n) + " vertices)");
        }
    }
    // Normals from the triangles when none are given: area-weighted face normals.
    std::vector<Vec3> normals = mesh.normals;
    if (normals.empty()) {
        normals.assign(n, Vec3::Zero());
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            const auto a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
            const Vec3 face = (mesh.positions[b] - mesh.positions[a]).cross(mesh.positions[c] - mesh.positions[a]);
            normals[a] += face, normals[b] += face, normals[c] += face;
        }
        for (Vec3& v : normals) v = v.norm() > 0 ? Vec3(v.normalized()) : Vec3(Vec3::UnitY());
    }
    const auto base = static_cast<std::uint32_t>(pass.mesh_vertices.size() / 10);
    for (std::size_t i = 0; i < n; ++i) {
        Color c = mesh.colors.empty() ? look_color : mesh.colors[i];
        c = ghost ? ghost_color(c) : Color{c.r, c.g, c.b, 1.0f};
        const Vec3& p = mesh.positions[i];
        const Vec3& nn = normals[i];
        pass.mesh_vertices.insert(pass.mesh_vertices.end(),
                                  {p.x(), p.y(), p.z(), nn.x(), nn.y(), nn.z(), c.r, c.g, c.b, c.a});
    }
    for (std::uint32_t index : mesh.indices) pass.mesh_indices.push_back(base + index);
}

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

}  // namespace

// --- 5. Camera maths ----------------------------------------------------------------

Eigen::Matrix4f view_matrix(const Camera& camera) {
    const Vec3 f = (camera.target - camera.eye).normalized();
    Vec3 up = camera.up.normalized();
    if (std::abs(f.dot(up)) > 0.999f) up = std::abs(f.y()) < 0.9f ? Vec3::UnitY() : Vec3::UnitZ();
    const Vec3 s = f.cross(up).normalized();
    const Vec3 u = s.cross(f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.row(0) << s.x(), s.y(), s.z(), -s.dot(camera.eye);
    m.row(1) << u.x(), u.y(), u.z(), -u.dot(camera.eye);
    m.row(2) << -f.x(), -f.y(), -f.z(), f.dot(camera.eye);
    return m;
}

Eigen::Matrix4f projection_matrix(const Camera& camera, float aspect) {
    const float n = camera.near_plane, f = camera.far_plane;
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    if (camera.projection == Camera::Projection::orthographic) {
        const float top = 0.5f * camera.ortho_height, right = top * aspect;
        m(0, 0) = 1.0f / right;
        m(1, 1) = 1.0f / top;
        m(2, 2) = -2.0f / (f - n);
        m(2, 3) = -(f + n) / (f - n);
        m(3, 3) = 1.0f;
    } else {
        const float t = 1.0f / std::tan(0.5f * camera.fov_y_deg * std::numbers::pi_v<float> / 180.0f);
        m(0, 0) = t / aspect;
        m(1, 1) = t;
        m(2, 2) = -(f + n) / (f - n);
        m(2, 3) = -2.0f * f * n / (f - n);
        m(3, 2) = -1.0f;
    }
    return m;
}

std::optional<Vec2> project_to_pixel(const Camera& camera, int width, int height, const Vec3& point) {
    const Eigen::Vector4f clip = projection_matrix(camera, static_cast<float>(width) / static_cast<float>(height)) *
                                 view_matrix(camera) * point.homogeneous();
    if (clip.w() <= 0.0f) return std::nullopt;
    const float x = clip.x() / clip.w(), y = clip.y() / clip.w();
    return Vec2((x * 0.5f + 0.5f) * static_cast<float>(width), (0.5f - y * 0.5f) * static_cast<float>(height));
}

// --- The renderer ----------------------------------------------------------------------

struct Renderer::Impl {
    GlContext& context;
    const GladGLContext& gl;
    const Font& font;

    GLuint mesh_program = 0, sphere_program = 0, ground_program = 0, unlit_program = 0, overlay_program = 0;
    InstancedMesh cylinder, tube, cone, box, plane;
    GLuint quad_vao = 0, quad_vertices = 0, sphere_instances = 0;  // impostors: 4 corners, instanced
    GLuint ground_vao = 0, ground_vertices = 0;
    GLuint free_vao = 0, free_vertices = 0, free_indices = 0;  // meshes of the frame
    GLuint trail_vao = 0, trail_vertices = 0;
    GLuint overlay_vao = 0, overlay_vertices = 0;
    GLuint atlas = 0;

    // Render targets: multisampled colour + depth when MSAA is on, resolved
    // into a single-sample colour + depth target that read_back() reads.
    int width = 0, height = 0, samples = 0;
    GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0;
    GLuint resolve_fbo = 0, resolve_color = 0, resolve_depth = 0;
    int shadow_size = 0;
    GLuint shadow_fbo = 0, shadow_map = 0;

    PassItems solid, ghost;
    std::vector<float> trails;  // x y z r g b a per vertex, triangles
    detail::OverlayBatch overlay;
    FrameStats stats;
    bool has_frame = false;

    Impl(GlContext& c, const Font& f) : context(c), gl(c.gl()), font(f), overlay(f) {}

    void create_resources();
    void destroy_resources();
    void ensure_targets(int w, int h, int s);
    void ensure_shadow_map(int size);
    void prepare(const DrawList& list, const Vec3& eye, const Vec3& forward);
    void set_lighting_uniforms(GLuint program, const DrawList& list, const Eigen::Matrix4f& view_proj,
                               const Eigen::Matrix4f& light_view_proj, float shadow_texel, bool shadows,
                               const Vec3& eye, const Vec3& forward, bool ortho);
    void draw_pass(const PassItems& items, GLuint mesh_prog, GLuint sphere_prog, bool depth_only);
    void draw_instanced(const InstancedMesh& mesh, const std::vector<float>& instances);
    void draw(const DrawList& list, const RenderSettings& settings);
    void check_errors(const char* where);
};

void Renderer::Impl::create_resources() {
    mesh_program = link(gl, kMeshVertex, kMeshFragment, true, "mesh");
    sphere_program = link(gl, kSphereVertex, kSphereFragment, true, "sphere impostor");
    ground_program = link(gl, kGroundVertex, kGroundFragment, true, "ground");
    unlit_program = link(gl, kUnlitVertex, kUnlitFragment, false, "unlit");
    overlay_program = link(gl, kOverlayVertex, kOverlayFragment, false, "overlay");

    cylinder = make_instanced(gl, detail::unit_cylinder(true));
    tube = make_instanced(gl, detail::unit_cylinder(false));
    cone = make_instanced(gl, detail::unit_cone());
    box = make_instanced(gl, detail::unit_box());
    plane = make_instanced(gl, detail::unit_quad());

    // Sphere impostors: a triangle strip over four corners, one instance per sphere.
    const float corners[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    gl.GenVertexArrays(1, &quad_vao);
    gl.GenBuffers(1, &quad_vertices);
    gl.GenBuffers(1, &sphere_instances);
    gl.BindVertexArray(quad_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, quad_vertices);
    gl.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    float_attribute(gl, 0, 2, 2, 0, 0);
    gl.BindBuffer(GL_ARRAY_BUFFER, sphere_instances);
    float_attribute(gl, 1, 4, 8, 0, 1);
    float_attribute(gl, 2, 4, 8, 4, 1);

    // The ground: the unit quad's vertices, scaled in the shader.
    const float ground[] = {-1, 0, -1, 1, 0, -1, -1, 0, 1, 1, 0, 1};
    gl.GenVertexArrays(1, &ground_vao);
    gl.GenBuffers(1, &ground_vertices);
    gl.BindVertexArray(ground_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, ground_vertices);
    gl.BufferData(GL_ARRAY_BUFFER, sizeof ground, ground, GL_STATIC_DRAW);
    float_attribute(gl, 0, 3, 3, 0, 0);

    // Free meshes: position, normal, colour per vertex; the model matrix
    // attributes stay disabled and read a constant identity.
    gl.GenVertexArrays(1, &free_vao);
    gl.GenBuffers(1, &free_vertices);
    gl.GenBuffers(1, &free_indices);
    gl.BindVertexArray(free_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, free_vertices);
    float_attribute(gl, 0, 3, 10, 0, 0);
    float_attribute(gl, 1, 3, 10, 3, 0);
    float_attribute(gl, 6, 4, 10, 6, 0);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, free_indices);

    gl.GenVertexArrays(1, &trail_vao);
    gl.GenBuffers(1, &trail_vertices);
    gl.BindVertexArray(trail_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, trail_vertices);
    float_attribute(gl, 0, 3, 7, 0, 0);
    float_attribute(gl, 1, 4, 7, 3, 0);

    gl.GenVertexArrays(1, &overlay_vao);
    gl.GenBuffers(1, &overlay_vertices);
    gl.BindVertexArray(overlay_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, overlay_vertices);
    constexpr int kOverlayFloats = sizeof(detail::OverlayVertex) / sizeof(float);
    float_attribute(gl, 0, 2, kOverlayFloats, 0, 0);
    float_attribute(gl, 1, 2, kOverlayFloats, 2, 0);
    float_attribute(gl, 2, 4, kOverlayFloats, 4, 0);
    float_attribute(gl, 3, 2, kOverlayFloats, 8, 0);
    gl.BindVertexArray(0);

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
    check_errors("creating the renderer");
}

void Renderer::Impl::destroy_resources() {
    for (GLuint program : {mesh_program, sphere_program, ground_program, unlit_program, overlay_program}) {
        gl.DeleteProgram(program);
    }
    for (InstancedMesh* m : {&cylinder, &tube, &cone, &box, &plane}) destroy(gl, *m);
    const GLuint vaos[] = {quad_vao, ground_vao, free_vao, trail_vao, overlay_vao};
    gl.DeleteVertexArrays(5, vaos);
    const GLuint buffers[] = {quad_vertices, sphere_instances, ground_vertices, free_vertices,
                              free_indices,  trail_vertices,   overlay_vertices};
    gl.DeleteBuffers(7, buffers);
    gl.DeleteTextures(1, &atlas);
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

// Flattens the draw list into the per-pass instance arrays. Items with a
// non-finite position or a size <= 0 are skipped: a NaN must not reach GL,
// and the watchdog, not the renderer, reports it.
void Renderer::Impl::prepare(const DrawList& list, const Vec3& eye, const Vec3& forward) {
    solid.clear();
    ghost.clear();
    trails.clear();
    auto pass = [&](const Look& look) -> PassItems& { return look.ghost ? ghost : solid; };

    for (const Sphere& s : list.spheres) {
        if (!s.center.allFinite() || !finite_positive(s.radius)) continue;
        add_sphere(pass(s.look), s.center, s.radius, shown_color(s.look));
    }
    for (const Capsule& c : list.capsules) {
        if (!c.a.allFinite() || !c.b.allFinite() || !finite_positive(c.radius)) continue;
        PassItems& p = pass(c.look);
        const Color color = shown_color(c.look);
        if ((c.b - c.a).norm() > 0) push_instance(p.tubes, detail::segment_transform(c.a, c.b, c.radius), color);
        add_sphere(p, c.a, c.radius, color);
        add_sphere(p, c.b, c.radius, color);
    }
    for (const Cylinder& c : list.cylinders) {
        if (!c.a.allFinite() || !c.b.allFinite() || !finite_positive(c.radius) || !((c.b - c.a).norm() > 0)) continue;
        push_instance(pass(c.look).cylinders, detail::segment_transform(c.a, c.b, c.radius), shown_color(c.look));
    }
    for (const Cone& c : list.cones) {
        if (!c.base.allFinite() || !c.apex.allFinite() || !finite_positive(c.radius) ||
            !((c.apex - c.base).norm() > 0)) {
            continue;
        }
        push_instance(pass(c.look).cones, detail::segment_transform(c.base, c.apex, c.radius), shown_color(c.look));
    }
    for (const Arrow& a : list.arrows) {
        const float length = a.vector.norm();
        if (!a.origin.allFinite() || !std::isfinite(length) || length <= 0) continue;
        const float shaft = a.shaft_radius > 0 ? a.shaft_radius : 0.03f * length;
        const float head = a.head_radius > 0 ? a.head_radius : 0.08f * length;
        const float head_length = std::min(0.3f * length, 3.0f * head);
        const Vec3 tip = a.origin + a.vector, neck = tip - a.vector / length * head_length;
        PassItems& p = pass(a.look);
        const Color color = shown_color(a.look);
        push_instance(p.cylinders, detail::segment_transform(a.origin, neck, shaft), color);
        push_instance(p.cones, detail::segment_transform(neck, tip, head), color);
    }
    for (const Box& b : list.boxes) {
        if (!b.center.allFinite() || !b.half_extents.allFinite() || (b.half_extents.array() <= 0).any()) continue;
        push_instance(pass(b.look).boxes, detail::box_transform(b), shown_color(b.look));
    }
    for (const Plane& pl : list.planes) {
        if (!pl.center.allFinite() || !pl.normal.allFinite() || !(pl.size.array() > 0).all()) continue;
        push_instance(pass(pl.look).planes, detail::plane_transform(pl), shown_color(pl.look));
    }
    for (const Mesh& m : list.meshes) add_mesh(pass(m.look), m, m.look.color, m.look.ghost);

    // Trails: a band of the given width turned toward the camera, fading in
    // from its oldest point.
    const bool ortho = list.camera.projection == Camera::Projection::orthographic;
    for (const Ribbon& r : list.ribbons) {
        const std::size_t n = r.points.size();
        if (n < 2 || !finite_positive(r.width)) continue;
        const Color c = shown_color(r.look);
        std::vector<std::array<float, 7>> left(n), right(n);
        bool finite = true;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3& p = r.points[i];
            finite = finite && p.allFinite();
            const Vec3 tangent = r.points[std::min(i + 1, n - 1)] - r.points[i == 0 ? 0 : i - 1];
            const Vec3 to_eye = ortho ? Vec3(-forward) : Vec3(eye - p);
            Vec3 side = tangent.cross(to_eye);
            side = side.norm() > 0 ? Vec3(side.normalized() * 0.5f * r.width) : Vec3::Zero();
            const float alpha = c.a * static_cast<float>(i) / static_cast<float>(n - 1);
            const Vec3 a = p + side, b = p - side;
            left[i] = {a.x(), a.y(), a.z(), c.r, c.g, c.b, alpha};
            right[i] = {b.x(), b.y(), b.z(), c.r, c.g, c.b, alpha};
        }
        if (!finite) continue;
        for (std::size_t i = 1; i < n; ++i) {
            for (const auto* v : {&left[i - 1], &right[i - 1], &right[i], &left[i - 1], &right[i], &left[i]}) {
                trails.insert(trails.end(), v->begin(), v->end());
            }
        }
    }

    overlay.clear();
    for (const Plot& p : list.plots) overlay.plot(p);
    for (const Text& t : list.texts) overlay.text_block(t);
}

void Renderer::Impl::set_lighting_uniforms(GLuint program, const DrawList& list, const Eigen::Matrix4f& view_proj,
                                           const Eigen::Matrix4f& light_view_proj, float shadow_texel, bool shadows,
                                           const Vec3& eye, const Vec3& forward, bool ortho) {
    gl.UseProgram(program);
    auto loc = [&](const char* name) { return gl.GetUniformLocation(program, name); };
    const Light& light = list.light;
    const Vec3 dir = light.direction.norm() > 0 ? Vec3(light.direction.normalized()) : Vec3(-Vec3::UnitY());
    gl.UniformMatrix4fv(loc("u_view_proj"), 1, GL_FALSE, view_proj.data());
    gl.UniformMatrix4fv(loc("u_light_view_proj"), 1, GL_FALSE, light_view_proj.data());
    gl.Uniform3f(loc("u_light_dir"), dir.x(), dir.y(), dir.z());
    gl.Uniform3f(loc("u_eye"), eye.x(), eye.y(), eye.z());
    gl.Uniform3f(loc("u_forward"), forward.x(), forward.y(), forward.z());
    gl.Uniform1i(loc("u_ortho"), ortho ? 1 : 0);
    gl.Uniform1f(loc("u_intensity"), light.intensity);
    gl.Uniform1f(loc("u_ambient"), light.ambient);
    gl.Uniform1f(loc("u_specular"), light.specular);
    gl.Uniform1f(loc("u_shininess"), light.shininess);
    gl.Uniform1i(loc("u_shadows"), shadows ? 1 : 0);
    gl.Uniform1f(loc("u_shadow_texel"), shadow_texel);
    gl.Uniform1i(loc("u_shadow_map"), 0);
}

void Renderer::Impl::draw_instanced(const InstancedMesh& mesh, const std::vector<float>& instances) {
    if (instances.empty()) return;
    const auto count = static_cast<GLsizei>(instances.size() / kInstanceFloats);
    gl.BindVertexArray(mesh.vao);
    upload(gl, GL_ARRAY_BUFFER, mesh.instances, instances);
    gl.DrawElementsInstanced(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr, count);
    stats.triangles += mesh.triangles() * static_cast<std::size_t>(count);
    ++stats.draw_calls;
}

void Renderer::Impl::draw_pass(const PassItems& items, GLuint mesh_prog, GLuint sphere_prog, bool depth_only) {
    gl.UseProgram(mesh_prog);
    gl.Uniform1i(gl.GetUniformLocation(mesh_prog, "u_depth_only"), depth_only ? 1 : 0);
    if (!items.mesh_indices.empty()) {
        gl.BindVertexArray(free_vao);
        upload(gl, GL_ARRAY_BUFFER, free_vertices, items.mesh_vertices);
        upload(gl, GL_ELEMENT_ARRAY_BUFFER, free_indices, items.mesh_indices);
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
    if (!items.spheres.empty()) {
        gl.UseProgram(sphere_prog);
        gl.Uniform1i(gl.GetUniformLocation(sphere_prog, "u_depth_only"), depth_only ? 1 : 0);
        const auto count = static_cast<GLsizei>(items.spheres.size() / 8);
        gl.BindVertexArray(quad_vao);
        upload(gl, GL_ARRAY_BUFFER, sphere_instances, items.spheres);
        gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count);
        stats.triangles += 2 * static_cast<std::size_t>(count);
        ++stats.draw_calls;
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

void Renderer::Impl::draw(const DrawList& list, const RenderSettings& settings) {
    constexpr int kMaxSize = 8192;  // px per side
    if (settings.width < 1 || settings.height < 1 || settings.width > kMaxSize || settings.height > kMaxSize) {
        throw RenderError(ErrorKind::bad_input, "image size " + std::to_string(settings.width) + "x" +
                                                    std::to_string(settings.height) + " must be within 1x1 .. " +
                                                    std::to_string(kMaxSize) + "x" + std::to_string(kMaxSize) + " px");
    }
    const int s = settings.msaa_samples;
    if (s != 0 && s != 1 && s != 2 && s != 4 && s != 8) {
        throw RenderError(ErrorKind::bad_input, "MSAA samples must be 0, 1, 2, 4 or 8 (got " + std::to_string(s) + ")");
    }
    if (settings.shadow_map_size < 16 || settings.shadow_map_size > kMaxSize) {
        throw RenderError(ErrorKind::bad_input, "shadow map size must be within 16 .. " + std::to_string(kMaxSize) +
                                                    " texels (got " + std::to_string(settings.shadow_map_size) + ")");
    }
    const Camera& camera = list.camera;
    if (!camera.eye.allFinite() || !camera.target.allFinite() || !((camera.target - camera.eye).norm() > 0) ||
        !(camera.near_plane > 0) || !(camera.far_plane > camera.near_plane) ||
        (camera.projection == Camera::Projection::perspective && !(camera.fov_y_deg > 0 && camera.fov_y_deg < 180)) ||
        (camera.projection == Camera::Projection::orthographic && !(camera.ortho_height > 0))) {
        throw RenderError(ErrorKind::bad_input,
                          "camera needs finite eye != target, 0 < near < far, 0 < fov < 180 degrees, ortho height > 0");
    }
    context.make_current();
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
    ensure_targets(settings.width, settings.height, s > 1 ? s : 0);
    stats = {};

    const float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
    const Eigen::Matrix4f view_proj = projection_matrix(camera, aspect) * view_matrix(camera);
    const Vec3 eye = camera.eye, forward = (camera.target - camera.eye).normalized();
    const bool ortho = camera.projection == Camera::Projection::orthographic;
    prepare(list, eye, forward);

    // Shadow pass: the light's orthographic view, fitted around the casters.
    Bounds bounds;
    for (const std::vector<float>* v : {&solid.spheres}) {
        for (std::size_t i = 0; i < v->size(); i += 8) bounds.add(Vec3((*v)[i], (*v)[i + 1], (*v)[i + 2]), (*v)[i + 3]);
    }
    for (const std::vector<float>* v : {&solid.cylinders, &solid.tubes, &solid.cones, &solid.boxes, &solid.planes}) {
        for (std::size_t i = 0; i < v->size(); i += kInstanceFloats) {
            const Eigen::Map<const Eigen::Matrix4f> m(v->data() + i);
            // The unit meshes lie within [-1, 1]^3: a sphere of radius sqrt(3) around the origin.
            const float reach = std::sqrt(3.0f) * m.block<3, 3>(0, 0).colwise().norm().maxCoeff();
            bounds.add(m.block<3, 1>(0, 3), reach);
        }
    }
    for (std::size_t i = 0; i < solid.mesh_vertices.size(); i += 10) {
        bounds.add(Vec3(solid.mesh_vertices[i], solid.mesh_vertices[i + 1], solid.mesh_vertices[i + 2]), 0);
    }
    const bool shadows = list.light.shadows && !bounds.empty();
    Eigen::Matrix4f light_view_proj = Eigen::Matrix4f::Identity();
    float shadow_texel = 0;
    const Vec3 light_dir =
        list.light.direction.norm() > 0 ? Vec3(list.light.direction.normalized()) : Vec3(-Vec3::UnitY());

    gl.Disable(GL_CULL_FACE);  // thin cloth and open tubes are seen from both sides
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    if (shadows) {
        ensure_shadow_map(settings.shadow_map_size);
        const Vec3 centre = 0.5f * (bounds.lo + bounds.hi);
        const float radius = std::max(0.5f * (bounds.hi - bounds.lo).norm(), 1e-3f);
        Camera light_camera;
        light_camera.projection = Camera::Projection::orthographic;
        light_camera.eye = centre - light_dir * (2.0f * radius);
        light_camera.target = centre;
        light_camera.up = std::abs(light_dir.y()) < 0.99f ? Vec3::UnitY() : Vec3::UnitZ();
        light_camera.ortho_height = 2.0f * radius;
        light_camera.near_plane = 0.5f * radius;
        light_camera.far_plane = 3.5f * radius;
        light_view_proj = projection_matrix(light_camera, 1.0f) * view_matrix(light_camera);
        shadow_texel = 2.0f * radius / static_cast<float>(settings.shadow_map_size);

        gl.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
        gl.Viewport(0, 0, settings.shadow_map_size, settings.shadow_map_size);
        gl.DepthMask(GL_TRUE);
        gl.Clear(GL_DEPTH_BUFFER_BIT);
        gl.ActiveTexture(GL_TEXTURE0);
        gl.BindTexture(GL_TEXTURE_2D, 0);  // never sampled while it is being written
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        gl.PolygonOffset(1.5f, 2.0f);
        const Vec3 light_forward = light_dir;
        for (GLuint program : {mesh_program, sphere_program}) {
            set_lighting_uniforms(program, list, light_view_proj, light_view_proj, shadow_texel, false,
                                  light_camera.eye, light_forward, true);
        }
        gl.UseProgram(sphere_program);
        gl.Uniform1f(gl.GetUniformLocation(sphere_program, "u_pixel_scale"), shadow_texel);
        gl.Uniform1i(gl.GetUniformLocation(sphere_program, "u_multisample"), 0);
        draw_pass(solid, mesh_program, sphere_program, true);
        gl.Disable(GL_POLYGON_OFFSET_FILL);
    }

    // Main passes into the multisampled target (or straight into the resolve target).
    const bool multisample = samples > 1;
    gl.BindFramebuffer(GL_FRAMEBUFFER, multisample ? msaa_fbo : resolve_fbo);
    gl.Viewport(0, 0, settings.width, settings.height);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    gl.ClearColor(list.background.r, list.background.g, list.background.b, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);  // alpha stays 1: read-back RGBA is opaque
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, shadows ? shadow_map : 0);

    const float pixel_scale = ortho ? camera.ortho_height / static_cast<float>(settings.height)
                                    : 2.0f * std::tan(0.5f * camera.fov_y_deg * std::numbers::pi_v<float> / 180.0f) /
                                          static_cast<float>(settings.height);
    for (GLuint program : {mesh_program, sphere_program, ground_program}) {
        set_lighting_uniforms(program, list, view_proj, light_view_proj, shadow_texel, shadows, eye, forward, ortho);
    }
    gl.UseProgram(sphere_program);
    gl.Uniform1f(gl.GetUniformLocation(sphere_program, "u_pixel_scale"), pixel_scale);
    gl.Uniform1i(gl.GetUniformLocation(sphere_program, "u_multisample"), multisample ? 1 : 0);

    if (list.ground.enabled && std::isfinite(list.ground.height) && list.ground.extent > 0) {
        const Ground& g = list.ground;
        gl.UseProgram(ground_program);
        auto loc = [&](const char* name) { return gl.GetUniformLocation(ground_program, name); };
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

    // Solids: opaque; with MSAA the impostors' edge coverage goes to the samples.
    if (multisample) gl.Enable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    draw_pass(solid, mesh_program, sphere_program, false);
    gl.Disable(GL_SAMPLE_ALPHA_TO_COVERAGE);

    // Ghosts after every solid, blended; they keep writing depth so each shows
    // only its front surface.
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    draw_pass(ghost, mesh_program, sphere_program, false);

    // Trails: blended, tested against depth but not writing it.
    if (!trails.empty()) {
        gl.DepthMask(GL_FALSE);
        gl.UseProgram(unlit_program);
        gl.UniformMatrix4fv(gl.GetUniformLocation(unlit_program, "u_view_proj"), 1, GL_FALSE, view_proj.data());
        gl.BindVertexArray(trail_vao);
        upload(gl, GL_ARRAY_BUFFER, trail_vertices, trails);
        gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(trails.size() / 7));
        stats.triangles += trails.size() / 21;
        ++stats.draw_calls;
        gl.DepthMask(GL_TRUE);
    }

    // Overlays: pixels, on top of everything.
    if (!overlay.vertices().empty()) {
        gl.Disable(GL_DEPTH_TEST);
        gl.UseProgram(overlay_program);
        gl.Uniform2f(gl.GetUniformLocation(overlay_program, "u_viewport"), static_cast<float>(settings.width),
                     static_cast<float>(settings.height));
        gl.Uniform1i(gl.GetUniformLocation(overlay_program, "u_atlas"), 1);
        gl.Uniform1f(gl.GetUniformLocation(overlay_program, "u_on_edge"), Font::kOnEdge / 255.0f);
        gl.ActiveTexture(GL_TEXTURE1);
        gl.BindTexture(GL_TEXTURE_2D, atlas);
        gl.BindVertexArray(overlay_vao);
        upload(gl, GL_ARRAY_BUFFER, overlay_vertices, overlay.vertices());
        gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(overlay.vertices().size()));
        stats.triangles += overlay.vertices().size() / 3;
        ++stats.draw_calls;
        gl.ActiveTexture(GL_TEXTURE0);
        gl.Enable(GL_DEPTH_TEST);
    }
    gl.Disable(GL_BLEND);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

    if (multisample) {
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
        gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
        gl.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    gl.BindVertexArray(0);
    check_errors("drawing a frame");
    has_frame = true;
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

Image Renderer::read_back(int channels) {
    if (!impl_->has_frame) throw RenderError(ErrorKind::bad_input, "read_back: nothing has been drawn yet");
    return read_pixels(impl_->resolve_fbo, channels, "reading the frame back");
}

Image Renderer::read_window(int channels) {
    if (impl_->context.window() == nullptr)
        throw RenderError(ErrorKind::bad_input, "read_window: this context has no window");
    if (!impl_->has_frame) throw RenderError(ErrorKind::bad_input, "read_window: nothing has been drawn yet");
    return read_pixels(0, channels, "reading the window back");
}

Image Renderer::read_pixels(unsigned framebuffer, int channels, const char* what) {
    if (channels != 3 && channels != 4) {
        throw RenderError(ErrorKind::bad_input,
                          std::string(what) + ": channels must be 3 or 4 (got " + std::to_string(channels) + ")");
    }
    Impl& r = *impl_;
    r.context.make_current();
    const auto& gl = r.gl;
    Image image;
    image.width = r.width;
    image.height = r.height;
    image.channels = channels;
    const std::size_t row = static_cast<std::size_t>(r.width) * channels;
    std::vector<std::uint8_t> bottom_up(row * r.height);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    gl.ReadBuffer(framebuffer == 0 ? GL_BACK : GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);  // rows are tightly packed, whatever the width
    gl.ReadPixels(0, 0, r.width, r.height, channels == 4 ? GL_RGBA : GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
    r.check_errors(what);
    // GL's first row is the bottom one; images start at the top.
    image.pixels.resize(bottom_up.size());
    for (int y = 0; y < r.height; ++y) {
        std::memcpy(image.pixels.data() + static_cast<std::size_t>(y) * row,
                    bottom_up.data() + static_cast<std::size_t>(r.height - 1 - y) * row, row);
    }
    return image;
}

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
    r.gl.BlitFramebuffer(0, 0, r.width, r.height, 0, 0, r.width, r.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    r.gl.BindFramebuffer(GL_FRAMEBUFFER, 0);  // what draws on top (a UI) draws into the window
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

}  // namespace render
