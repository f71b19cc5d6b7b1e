// The renderer's GLSL 3.30 core shaders (lighting, lit meshes, sphere
// impostors, ground grid, unlit trails, overlays) and their compiling and
// linking into the programs the passes use. Its own file: the shader text is
// the largest part of the renderer and is read apart from the C++ around it.
#include "render/renderer_impl.h"

#include <string>
#include <vector>

namespace render::detail {
namespace {

// --- Sources -------------------------------------------------------------------------

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

vec3 shade_linear(vec3 base, vec3 world, vec3 n, float specular_scale) {
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
vec3 shade(vec3 base_srgb, vec3 world, vec3 n, float specular_scale) {
    return shade_linear(to_linear(base_srgb), world, n, specular_scale);
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
    v_color = vec4(to_linear(a_color.rgb), a_color.a);
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
    vec3 color = shade_linear(v_color.rgb, hit, (hit - c) / r, 1.0);
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

// --- Compiling and linking ---------------------------------------------------------------

// Throws RenderError(gl) with the driver's log when a shader does not compile
// or a program does not link; the object is deleted first.
void check_built(const GladGLContext& gl, GLuint object, bool program, const char* name) {
    GLint ok = 0;
    if (program) {
        gl.GetProgramiv(object, GL_LINK_STATUS, &ok);
    } else {
        gl.GetShaderiv(object, GL_COMPILE_STATUS, &ok);
    }
    if (ok) return;
    char log[4096] = {};
    if (program) {
        gl.GetProgramInfoLog(object, sizeof log, nullptr, log);
        gl.DeleteProgram(object);
    } else {
        gl.GetShaderInfoLog(object, sizeof log, nullptr, log);
        gl.DeleteShader(object);
    }
    throw RenderError(ErrorKind::gl, std::string(program ? "program '" : "shader '") + name +
                                         (program ? "' does not link: " : "' does not compile: ") + log);
}

GLuint compile(const GladGLContext& gl, GLenum type, const std::vector<const char*>& sources, const char* name) {
    const GLuint shader = gl.CreateShader(type);
    gl.ShaderSource(shader, static_cast<GLsizei>(sources.size()), sources.data(), nullptr);
    gl.CompileShader(shader);
    check_built(gl, shader, false, name);
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
    check_built(gl, program, true, name);
    return program;
}

}  // namespace

Programs link_programs(const GladGLContext& gl) {
    Programs p;
    p.mesh = link(gl, kMeshVertex, kMeshFragment, true, "mesh");
    p.sphere = link(gl, kSphereVertex, kSphereFragment, true, "sphere impostor");
    p.ground = link(gl, kGroundVertex, kGroundFragment, true, "ground");
    p.unlit = link(gl, kUnlitVertex, kUnlitFragment, false, "unlit");
    p.overlay = link(gl, kOverlayVertex, kOverlayFragment, false, "overlay");
    return p;
}

void delete_programs(const GladGLContext& gl, const Programs& p) {
    for (GLuint program : {p.mesh, p.sphere, p.ground, p.unlit, p.overlay}) gl.DeleteProgram(program);
}

}  // namespace render::detail
