// The loader's reader of how a scene looks: [camera] (where the picture is
// taken from) and [view] (ground, trails, arrows, energy plot, HUD). Drawing
// only: nothing here changes the physics.
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

void read_camera(SceneBuilder& b, const Section& top) {
    CameraDef& c = b.scene.camera;
    c.eye = Eigen::Vector3f(0.0f, 1.5f, 6.0f);
    c.target = Eigen::Vector3f(0.0f, 1.0f, 0.0f);
    const toml::table* t = top.subtable("camera");
    if (t == nullptr) return;
    const Section s(b.r, *t, "camera");
    s.only(keys::camera);
    c.projection = s.word("projection", "perspective", {"perspective", "orthographic"}) == "orthographic"
                       ? CameraDef::Projection::orthographic
                       : CameraDef::Projection::perspective;
    c.eye = s.vec3("eye", c.eye.cast<double>(), "m", 1e5).cast<float>();
    c.target = s.vec3("target", c.target.cast<double>(), "m", 1e5).cast<float>();
    c.up = s.vec3("up", sim::Vec3::UnitY(), "(a direction)", 1e5).cast<float>();
    if ((c.eye - c.target).norm() < 1e-6f) s.fail("target", "must differ from camera.eye");
    if (c.up.norm() < 1e-6f || c.up.normalized().cross((c.target - c.eye).normalized()).norm() < 1e-3f) {
        s.fail("up", "must be a non-zero direction not parallel to the view direction");
    }
    c.fov_y_deg = static_cast<float>(s.number("fov", c.fov_y_deg, 1.0, 170.0, "degrees"));
    c.ortho_height = static_cast<float>(s.positive("height", c.ortho_height, 1e5, "m"));
}

void read_view(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("view");
    if (t == nullptr) return;
    const Section s(b.r, *t, "view");
    s.only(keys::view);
    View& v = b.scene.view;
    v.ground = s.boolean("ground", v.ground);
    v.ground_height = s.number("ground_height", v.ground_height, -1e5, 1e5, "m");
    v.trail_frames = static_cast<int>(s.integer("trail_frames", v.trail_frames, 0, 100'000));
    v.velocity_arrows = s.number("velocity_arrows", v.velocity_arrows, 0.0, 1e3, "s");
    v.force_arrows = s.number("force_arrows", v.force_arrows, 0.0, 1e9, "m/N");
    v.energy_plot = s.boolean("energy_plot", v.energy_plot);
    v.hud = s.boolean("hud", v.hud);
}

}  // namespace scenes::loader
