// The draw list flattened for the passes: every shape as an instance (model
// matrix and colour) of a unit mesh or a sphere impostor, in the solid or the
// ghost pass by its look; meshes merged into one vertex and index array per
// pass; ribbons built into camera-facing bands; text and plots laid out as
// overlay triangles. Its own file: this is CPU work on plain data, done before
// any GL call of the frame.
#include "render/renderer_impl.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace render {
namespace detail {
namespace {

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

void add_sphere(PassItems& pass, const Vec3& c, float r, const Color& color) {
    pass.spheres.insert(pass.spheres.end(), {c.x(), c.y(), c.z(), r, color.r, color.g, color.b, color.a});
}

// Throws RenderError(bad_input) for a mesh whose arrays do not agree.
void check_mesh(const Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
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
}

// The mesh's normals, or when none are given, area-weighted face normals from
// its triangles.
std::vector<Vec3> vertex_normals(const Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
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
    return normals;
}

void add_mesh(PassItems& pass, const Mesh& mesh, const Color& look_color, bool ghost) {
    const std::size_t n = mesh.positions.size();
    if (n == 0 || mesh.indices.empty()) return;
    check_mesh(mesh);
    const std::vector<Vec3> normals = vertex_normals(mesh);
    const auto base = static_cast<std::uint32_t>(pass.mesh_vertices.size() / kMeshVertexFloats);
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

}  // namespace

// Items with a non-finite position or a size <= 0 are skipped: a NaN must not
// reach GL, and the watchdog, not the renderer, reports it.
void flatten_shapes(const DrawList& list, PassItems& solid, PassItems& ghost) {
    solid.clear();
    ghost.clear();
    auto pass = [&](const Look& look) -> PassItems& { return look.ghost ? ghost : solid; };

    for (const Sphere& s : list.spheres) {
        if (!s.center.allFinite() || !finite_positive(s.radius)) continue;
        add_sphere(pass(s.look), s.center, s.radius, shown_color(s.look));
    }
    for (const Capsule& c : list.capsules) {
        if (!c.a.allFinite() || !c.b.allFinite() || !finite_positive(c.radius)) continue;
        PassItems& p = pass(c.look);
        const Color color = shown_color(c.look);
        if ((c.b - c.a).norm() > 0) push_instance(p.tubes, segment_transform(c.a, c.b, c.radius), color);
        add_sphere(p, c.a, c.radius, color);
        add_sphere(p, c.b, c.radius, color);
    }
    for (const Cylinder& c : list.cylinders) {
        if (!c.a.allFinite() || !c.b.allFinite() || !finite_positive(c.radius) || !((c.b - c.a).norm() > 0)) continue;
        push_instance(pass(c.look).cylinders, segment_transform(c.a, c.b, c.radius), shown_color(c.look));
    }
    for (const Cone& c : list.cones) {
        if (!c.base.allFinite() || !c.apex.allFinite() || !finite_positive(c.radius) ||
            !((c.apex - c.base).norm() > 0)) {
            continue;
        }
        push_instance(pass(c.look).cones, segment_transform(c.base, c.apex, c.radius), shown_color(c.look));
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
        push_instance(p.cylinders, segment_transform(a.origin, neck, shaft), color);
        push_instance(p.cones, segment_transform(neck, tip, head), color);
    }
    for (const Box& b : list.boxes) {
        if (!b.center.allFinite() || !b.half_extents.allFinite() || (b.half_extents.array() <= 0).any()) continue;
        push_instance(pass(b.look).boxes, box_transform(b), shown_color(b.look));
    }
    for (const Plane& pl : list.planes) {
        if (!pl.center.allFinite() || !pl.normal.allFinite() || !(pl.size.array() > 0).all()) continue;
        push_instance(pass(pl.look).planes, plane_transform(pl), shown_color(pl.look));
    }
    for (const Mesh& m : list.meshes) add_mesh(pass(m.look), m, m.look.color, m.look.ghost);
}

// Trails: a band of the given width turned toward the camera, fading in
// from its oldest point.
void build_trails(const std::vector<Ribbon>& ribbons, bool ortho, const Vec3& eye, const Vec3& forward,
                  std::vector<float>& trails) {
    trails.clear();
    for (const Ribbon& r : ribbons) {
        const std::size_t n = r.points.size();
        if (n < 2 || !finite_positive(r.width)) continue;
        const Color c = shown_color(r.look);
        std::vector<std::array<float, kTrailVertexFloats>> left(n), right(n);
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
}

}  // namespace detail

// Flattens the draw list into the per-pass instance arrays and the overlay batch.
void Renderer::Impl::prepare(const DrawList& list, const Vec3& eye, const Vec3& forward) {
    detail::flatten_shapes(list, solid, ghost);
    const bool ortho = list.camera.projection == Camera::Projection::orthographic;
    detail::build_trails(list.ribbons, ortho, eye, forward, trails);
    overlay.clear();
    for (const Plot& p : list.plots) overlay.plot(p);
    for (const Text& t : list.texts) overlay.text_block(t);
}

}  // namespace render
