// The viewer's camera and mouse (private to scenes/view): the scene's camera
// as a point orbiting its target, the ray under the cursor, and what that ray
// picks (a particle or a rigid body) for a mouse drag.
#pragma once

#include "render/draw_list.h"
#include "render/renderer.h"
#include "scenes/draw/scene_run.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace scenes::view {

using render::Vec3;

// --- 1. the orbit camera and mouse rays ------------------------------------------

// The scene's camera as a point orbiting its target: yaw about +y, pitch
// above the horizon, distance; orthographic scenes zoom by their height.
struct Orbit {
    render::Camera base;  // the scene's camera (C goes back to it)
    Vec3 target = Vec3::Zero();
    float yaw = 0.0f;                          // rad
    float pitch = 0.0f;                        // rad, within ±kMaxPitch
    static constexpr float kMaxPitch = 1.48f;  // rad (85°): never straight down, where "up" is undefined
    float distance = 1.0f;                     // m
    float ortho_height = 4.0f;

    explicit Orbit(const render::Camera& camera) : base(camera) { reset(); }

    void reset() {
        target = base.target;
        const Vec3 d = base.eye - base.target;
        distance = std::max(1e-3f, d.norm());
        pitch = std::clamp(std::asin(std::clamp(d.y() / distance, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
        yaw = std::atan2(d.x(), d.z());
        ortho_height = base.ortho_height;
    }
    render::Camera camera() const {
        render::Camera c = base;
        c.target = target;
        c.eye =
            target + distance * Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
        c.up = Vec3::UnitY();
        c.ortho_height = ortho_height;
        return c;
    }
    void rotate(float dx, float dy) {        // px of mouse motion
        constexpr float kRadPerPx = 0.008f;  // rad per px of mouse motion: 400 px turn ~180°
        yaw -= kRadPerPx * dx;
        pitch = std::clamp(pitch + kRadPerPx * dy, -kMaxPitch, kMaxPitch);
    }
    void pan(float dx, float dy, int height) {  // px
        const render::Camera c = camera();
        const Vec3 forward = (c.target - c.eye).normalized();
        const Vec3 right = forward.cross(Vec3::UnitY()).normalized();
        const Vec3 up = right.cross(forward);
        const float metres_per_px = c.projection == render::Camera::Projection::orthographic
                                        ? ortho_height / static_cast<float>(height)
                                        : 2.0f * distance *
                                              std::tan(0.5f * c.fov_y_deg * std::numbers::pi_v<float> / 180.0f) /
                                              static_cast<float>(height);
        target += metres_per_px * (-dx * right + dy * up);
    }
    void zoom(float steps) {                     // wheel clicks, + is closer
        const float f = std::pow(0.88f, steps);  // 12% closer per wheel click
        distance = std::clamp(distance * f, 0.05f, 500.0f);
        ortho_height = std::clamp(ortho_height * f, 0.05f, 500.0f);
    }
};

struct Ray {
    Eigen::Vector3d origin;
    Eigen::Vector3d direction;  // unit
};

// The ray through pixel (px, py) of a width x height image (y down).
inline Ray mouse_ray(const render::Camera& camera, int width, int height, double px, double py) {
    const Eigen::Matrix4f m =
        (render::projection_matrix(camera, static_cast<float>(width) / static_cast<float>(height)) *
         render::view_matrix(camera))
            .inverse();
    const float nx = static_cast<float>(2.0 * px / width - 1.0), ny = static_cast<float>(1.0 - 2.0 * py / height);
    auto unproject = [&](float z) {
        const Eigen::Vector4f p = m * Eigen::Vector4f(nx, ny, z, 1.0f);
        return Eigen::Vector3d((p.head<3>() / p.w()).cast<double>());
    };
    const Eigen::Vector3d a = unproject(-1.0f), b = unproject(1.0f);
    return {a, (b - a).normalized()};
}

// --- 2. picking ------------------------------------------------------------------

struct Pick {
    sim::Drag drag;
    double depth = 0.0;  // m along the ray
};

// The nearest particle or body part the ray passes within reach of (its
// 1.5 radii, at least 6 cm): particles that move, and rigid bodies.
inline std::optional<Pick> pick(const SceneRun& run, const Ray& ray) {
    std::optional<Pick> best;
    auto consider = [&](const Eigen::Vector3d& centre, double reach, sim::Drag::Kind kind, std::uint32_t index) {
        const double t = (centre - ray.origin).dot(ray.direction);
        if (t <= 0.0) return;
        const double miss = (ray.origin + t * ray.direction - centre).norm();
        if (miss > reach || (best && t >= best->depth)) return;
        Pick p;
        p.drag.kind = kind;
        p.drag.index = index;
        p.drag.target = ray.origin + t * ray.direction;
        p.depth = t;
        best = p;
    };
    const sim::World& world = run.world();
    const sim::ParticleState& s = world.state();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.inv_mass[i] == 0.0) continue;
        const double r = run.scene().looks[i].radius;
        consider(s.x.get(i), std::max(1.5 * r, 0.06), sim::Drag::Kind::particle, static_cast<std::uint32_t>(i));
    }
    if (const sim::RigidWorld* rigid = world.rigid()) {
        for (const sim::PlacedPart& part : rigid->placed_parts()) {
            // A part's bounding sphere: boxes by their half diagonal, round parts by radius and half length.
            const double reach =
                part.shape == sim::RigidShape::box ? 0.5 * part.size.norm() : part.size.x() + 0.5 * part.size.y();
            consider(part.center, reach, sim::Drag::Kind::body, part.body.index);
        }
    }
    if (best && best->drag.kind == sim::Drag::Kind::body) {
        // Grab the point of the body where the ray came closest, in the body's frame.
        const sim::BodyState b = world.rigid()->state({best->drag.index, 0});
        best->drag.anchor = b.orientation.conjugate() * (best->drag.target - b.position);
    } else if (best) {
        best->drag.target = s.x.get(best->drag.index);
    }
    return best;
}

}  // namespace scenes::view
