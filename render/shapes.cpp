#include "render/shapes.h"

#include <cmath>
#include <numbers>

namespace render::detail {
namespace {

void add_vertex(UnitMesh& mesh, const Vec3& p, const Vec3& n) {
    mesh.vertices.insert(mesh.vertices.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
}

std::uint32_t vertex_count(const UnitMesh& mesh) { return static_cast<std::uint32_t>(mesh.vertices.size() / 6); }

// A disc of radius 1 at height y facing +y (up) or -y.
void add_disc(UnitMesh& mesh, float y, bool up) {
    const std::uint32_t centre = vertex_count(mesh);
    const Vec3 normal(0, up ? 1.0f : -1.0f, 0);
    add_vertex(mesh, Vec3(0, y, 0), normal);
    for (int i = 0; i < kRoundSegments; ++i) {
        const float angle = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / kRoundSegments;
        add_vertex(mesh, Vec3(std::cos(angle), y, std::sin(angle)), normal);
    }
    for (std::uint32_t i = 0; i < kRoundSegments; ++i) {
        const std::uint32_t a = centre + 1 + i, b = centre + 1 + (i + 1) % kRoundSegments;
        // Counter-clockwise seen from the side the normal points to.
        if (up) {
            mesh.indices.insert(mesh.indices.end(), {centre, b, a});
        } else {
            mesh.indices.insert(mesh.indices.end(), {centre, a, b});
        }
    }
}

}  // namespace

UnitMesh unit_cylinder(bool with_caps) {
    UnitMesh mesh;
    for (int i = 0; i < kRoundSegments; ++i) {
        const float angle = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / kRoundSegments;
        const Vec3 n(std::cos(angle), 0, std::sin(angle));
        add_vertex(mesh, Vec3(n.x(), 0, n.z()), n);
        add_vertex(mesh, Vec3(n.x(), 1, n.z()), n);
    }
    for (std::uint32_t i = 0; i < kRoundSegments; ++i) {
        const std::uint32_t j = (i + 1) % kRoundSegments;
        const std::uint32_t b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * j, t1 = 2 * j + 1;
        mesh.indices.insert(mesh.indices.end(), {b0, t0, t1, b0, t1, b1});
    }
    if (with_caps) {
        add_disc(mesh, 0.0f, false);
        add_disc(mesh, 1.0f, true);
    }
    return mesh;
}

UnitMesh unit_cone() {
    UnitMesh mesh;
    // The side normal of a cone of height 1 and radius 1 leans 45 degrees up.
    const float k = 1.0f / std::sqrt(2.0f);
    for (int i = 0; i < kRoundSegments; ++i) {
        const float a0 = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / kRoundSegments;
        const float a1 = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i + 1) / kRoundSegments;
        const float am = 0.5f * (a0 + a1);
        const std::uint32_t base = vertex_count(mesh);
        add_vertex(mesh, Vec3(std::cos(a0), 0, std::sin(a0)), Vec3(std::cos(a0) * k, k, std::sin(a0) * k));
        add_vertex(mesh, Vec3(std::cos(a1), 0, std::sin(a1)), Vec3(std::cos(a1) * k, k, std::sin(a1) * k));
        add_vertex(mesh, Vec3(0, 1, 0), Vec3(std::cos(am) * k, k, std::sin(am) * k));
        mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1});
    }
    add_disc(mesh, 0.0f, false);
    return mesh;
}

UnitMesh unit_box() {
    UnitMesh mesh;
    for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {-1.0f, 1.0f}) {
            Vec3 n = Vec3::Zero();
            n[axis] = sign;
            // Two axes spanning the face, ordered so (u x v) = n: counter-clockwise outside.
            Vec3 u = Vec3::Zero(), v = Vec3::Zero();
            u[(axis + 1) % 3] = 1.0f;
            v[(axis + 2) % 3] = 1.0f;
            if (sign < 0) std::swap(u, v);
            const std::uint32_t base = vertex_count(mesh);
            add_vertex(mesh, n - u - v, n);
            add_vertex(mesh, n + u - v, n);
            add_vertex(mesh, n + u + v, n);
            add_vertex(mesh, n - u + v, n);
            mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    }
    return mesh;
}

UnitMesh unit_quad() {
    UnitMesh mesh;
    const Vec3 n = Vec3::UnitY();
    add_vertex(mesh, Vec3(-1, 0, -1), n);
    add_vertex(mesh, Vec3(1, 0, -1), n);
    add_vertex(mesh, Vec3(1, 0, 1), n);
    add_vertex(mesh, Vec3(-1, 0, 1), n);
    mesh.indices = {0, 2, 1, 0, 3, 2};
    return mesh;
}

Eigen::Matrix3f rotation_from_y(const Vec3& direction) {
    return Eigen::Quaternionf::FromTwoVectors(Vec3::UnitY(), direction).toRotationMatrix();
}

Eigen::Matrix4f segment_transform(const Vec3& a, const Vec3& b, float radius) {
    const Vec3 axis = b - a;
    const float length = axis.norm();
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    const Eigen::Matrix3f r = length > 0 ? rotation_from_y(axis / length) : Eigen::Matrix3f::Identity();
    m.block<3, 3>(0, 0) = r * Eigen::Vector3f(radius, length, radius).asDiagonal();
    m.block<3, 1>(0, 3) = a;
    return m;
}

Eigen::Matrix4f box_transform(const Box& box) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<3, 3>(0, 0) = box.rotation.normalized().toRotationMatrix() * box.half_extents.asDiagonal();
    m.block<3, 1>(0, 3) = box.center;
    return m;
}

Eigen::Matrix4f plane_transform(const Plane& plane) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    const Vec3 n = plane.normal.norm() > 0 ? Vec3(plane.normal.normalized()) : Vec3(Vec3::UnitY());
    m.block<3, 3>(0, 0) =
        rotation_from_y(n) * Eigen::Vector3f(0.5f * plane.size.x(), 1, 0.5f * plane.size.y()).asDiagonal();
    m.block<3, 1>(0, 3) = plane.center;
    return m;
}

}  // namespace render::detail
