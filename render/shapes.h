// Unit meshes the renderer instances (internal to render/): each is placed in
// the world by one model matrix per instance. Kept lean on purpose: llvmpipe's
// frame time follows the triangle count more than the resolution, and spheres
// are not meshes at all (they are ray-cast impostors, see renderer.cpp).
#pragma once

#include "render/draw_list.h"

#include <cstdint>
#include <vector>

namespace render::detail {

struct UnitMesh {
    std::vector<float> vertices;         // x y z nx ny nz per vertex
    std::vector<std::uint32_t> indices;  // three per triangle
};

constexpr int kRoundSegments = 20;  // around a cylinder or cone: smooth at 1280x720, 40 side triangles

UnitMesh unit_cylinder(bool with_caps);  // radius 1, from y = 0 to y = 1
UnitMesh unit_cone();                    // base radius 1 at y = 0, apex at y = 1, with its base disc
UnitMesh unit_box();                     // [-1, 1]^3, flat faces
UnitMesh unit_quad();                    // [-1, 1]^2 in the xz-plane, normal +y

// Column-major 4x4 model matrices placing the unit meshes.
Eigen::Matrix4f segment_transform(const Vec3& a, const Vec3& b, float radius);  // unit cylinder/cone from a to b
Eigen::Matrix4f box_transform(const Box& box);
Eigen::Matrix4f plane_transform(const Plane& plane);

// A rotation taking +y to the unit vector `direction`.
Eigen::Matrix3f rotation_from_y(const Vec3& direction);

}  // namespace render::detail
