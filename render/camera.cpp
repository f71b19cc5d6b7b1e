// Camera maths: the view and projection matrices the renderer draws with,
// and where a world point lands in the image (for labels and picking, which
// must agree with the pixels). Its own file: plain Eigen, no GL.
#include "render/renderer.h"

#include <cmath>
#include <numbers>

namespace render {

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

}  // namespace render
