// Draw lists shared by the renderer tests and bench_render: a lecture scene
// with one of everything, and a field of spheres for the speed figures.
#pragma once

#include "render/draw_list.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace render::testing {

inline Color hsv(float h, float s, float v) {
    const float c = v * s, hp = std::fmod(h, 1.0f) * 6.0f, x = c * (1 - std::abs(std::fmod(hp, 2.0f) - 1));
    float r = 0, g = 0, b = 0;
    if (hp < 1)
        r = c, g = x;
    else if (hp < 2)
        r = x, g = c;
    else if (hp < 3)
        g = c, b = x;
    else if (hp < 4)
        g = x, b = c;
    else if (hp < 5)
        r = x, b = c;
    else
        r = c, b = x;
    return Color{r + v - c, g + v - c, b + v - c, 1};
}

// A cloth of w x h vertices hanging in folds, coloured from blue (slack) to
// orange (stretched) the way strain colouring will look.
inline Mesh cloth_mesh(int w, int h, Vec3 origin, float size) {
    Mesh m;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            const float u = static_cast<float>(i) / static_cast<float>(w - 1);
            const float v = static_cast<float>(j) / static_cast<float>(h - 1);
            const float fold = 0.12f * size * std::sin(u * 4.0f * std::numbers::pi_v<float>) * v;
            m.positions.push_back(origin + Vec3(u * size, -v * size * 0.8f, fold + 0.15f * size * v * v));
            const float strain = 0.5f + 0.5f * std::sin(u * 4.0f * std::numbers::pi_v<float>);
            m.colors.push_back(Color{0.20f + 0.75f * strain, 0.45f + 0.1f * strain, 0.85f - 0.65f * strain, 1});
        }
    }
    for (int j = 0; j + 1 < h; ++j) {
        for (int i = 0; i + 1 < w; ++i) {
            const auto a = static_cast<std::uint32_t>(j * w + i), b = a + 1, c = a + static_cast<std::uint32_t>(w),
                       d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    }
    return m;
}

// One of everything the renderer draws, arranged the way a lecture slide would.
inline DrawList lecture_scene() {
    DrawList list;
    list.camera.eye = Vec3(0.6f, 2.6f, 7.5f);
    list.camera.target = Vec3(0.3f, 1.0f, 0.0f);
    list.camera.fov_y_deg = 42.0f;

    // A rope: spheres joined by springs drawn as cylinders.
    Vec3 previous(-3.0f, 2.6f, 0.0f);
    for (int i = 0; i < 8; ++i) {
        const float s = static_cast<float>(i) / 7.0f;
        const Vec3 p(-3.0f + 1.6f * s, 2.6f - 1.4f * std::sin(s * std::numbers::pi_v<float> * 0.5f), 0.0f);
        if (i > 0) list.cylinders.push_back(Cylinder{previous, p, 0.025f, Look{Color{0.3f, 0.3f, 0.35f, 1}}});
        list.spheres.push_back(Sphere{p, 0.08f, Look{Color{0.95f, 0.55f, 0.1f, 1}}});
        previous = p;
    }
    // A projectile and its analytic ghost, with a velocity arrow and a trail.
    list.spheres.push_back(Sphere{Vec3(-0.6f, 1.5f, 0.8f), 0.22f, Look{Color{0.85f, 0.15f, 0.15f, 1}}});
    list.spheres.push_back(Sphere{Vec3(-0.2f, 1.7f, 0.8f), 0.22f, Look{Color{0.85f, 0.15f, 0.15f, 1}, true}});
    list.arrows.push_back(
        Arrow{Vec3(-0.6f, 1.5f, 0.8f), Vec3(0.9f, 0.5f, 0.0f), 0, 0, Look{Color{0.1f, 0.6f, 0.2f, 1}}});
    Ribbon trail;
    trail.width = 0.05f;
    trail.look.color = Color{0.85f, 0.15f, 0.15f, 0.9f};
    for (int i = 0; i <= 20; ++i) {
        const float t = static_cast<float>(i) / 20.0f;
        trail.points.push_back(Vec3(-2.2f + 1.6f * t, 0.3f + 2.0f * t - 0.8f * t * t, 0.8f));
    }
    list.ribbons.push_back(trail);
    // A stack of boxes and two capsules (a ragdoll's limbs, later).
    list.boxes.push_back(Box{Vec3(2.2f, 0.3f, -0.5f), Vec3(0.5f, 0.3f, 0.5f), Eigen::Quaternionf::Identity(),
                             Look{Color{0.25f, 0.45f, 0.8f, 1}}});
    list.boxes.push_back(Box{Vec3(2.25f, 0.85f, -0.45f), Vec3(0.35f, 0.25f, 0.35f),
                             Eigen::Quaternionf(Eigen::AngleAxisf(0.4f, Vec3::UnitY())),
                             Look{Color{0.3f, 0.65f, 0.45f, 1}}});
    list.capsules.push_back(
        Capsule{Vec3(0.6f, 0.15f, 1.6f), Vec3(1.6f, 0.15f, 1.9f), 0.15f, Look{Color{0.75f, 0.6f, 0.45f, 1}}});
    list.capsules.push_back(
        Capsule{Vec3(1.3f, 0.5f, -1.2f), Vec3(1.5f, 1.6f, -1.3f), 0.12f, Look{Color{0.6f, 0.4f, 0.7f, 1}}});
    // A cloth.
    list.meshes.push_back(cloth_mesh(24, 18, Vec3(-1.6f, 2.9f, -1.4f), 2.2f));

    list.texts.push_back(Text{"Symplectic Euler · Δt = 1/60 s", Vec2(14, 12), 22.0f, Color{0.1f, 0.1f, 0.12f, 1}});
    list.texts.push_back(Text{"t = 1.25 s   E = 12.41 J", Vec2(14, 40), 16.0f, Color{0.2f, 0.2f, 0.25f, 1}, true});
    Plot energy;
    energy.title = "Energy";
    energy.x_label = "t (s)";
    energy.y_label = "E (J)";
    energy.position = Vec2(0, 0);  // placed by the caller for the image size
    energy.size = Vec2(300, 170);
    Plot::Series forward{"forward Euler", {}, Color{0.85f, 0.2f, 0.15f, 1}, 2.0f};
    Plot::Series symplectic{"symplectic Euler", {}, Color{0.15f, 0.35f, 0.85f, 1}, 2.0f};
    for (int i = 0; i <= 120; ++i) {
        const float t = static_cast<float>(i) / 40.0f;
        forward.points.push_back(Vec2(t, 12.0f * std::exp(0.12f * t)));
        symplectic.points.push_back(Vec2(t, 12.0f + 0.4f * std::sin(6.0f * t)));
    }
    energy.series = {forward, symplectic};
    list.plots.push_back(energy);
    return list;
}

// Places the lecture scene's plot in the bottom-right corner of a w x h image.
inline void place_plot(DrawList& list, int w, int h) {
    for (Plot& p : list.plots)
        p.position = Vec2(static_cast<float>(w) - p.size.x() - 10, static_cast<float>(h) - p.size.y() - 10);
}

// n spheres on a jittered grid above the ground (the bench_render workload).
inline DrawList sphere_field(int n) {
    DrawList list;
    list.camera.eye = Vec3(0.0f, 6.0f, 14.0f);
    list.camera.target = Vec3(0.0f, 1.0f, 0.0f);
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<float>(n))));
    for (int k = 0; k < n; ++k) {
        const int i = k % side, j = k / side;
        const float x = (static_cast<float>(i) - 0.5f * static_cast<float>(side - 1)) * 0.6f;
        const float z = (static_cast<float>(j) - 0.5f * static_cast<float>(side - 1)) * 0.6f;
        const float y = 0.3f + 0.8f * (0.5f + 0.5f * std::sin(0.7f * static_cast<float>(k)));
        list.spheres.push_back(Sphere{Vec3(x, y, z), 0.22f, Look{hsv(static_cast<float>(k) * 0.618f, 0.6f, 0.9f)}});
    }
    return list;
}

}  // namespace render::testing
