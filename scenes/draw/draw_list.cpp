// The glue that turns a SceneRun into a render::DrawList (docs/design.md rule 1:
// sim knows nothing of rendering, render nothing of physics; this file knows
// both). Like MuJoCo's mjv_addGeoms, each add_* appends one kind of thing to
// the list; draw_list() calls them in a fixed order, and that order is the
// order of the list's items, which the renderer keeps (it can matter for
// pixels). Its own file: what a frame shows, apart from how a run steps.
#include "scenes/draw/scene_run.h"

#include "sim/overloaded.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace scenes {

render::Color render_color(const Color& c) { return {c.r, c.g, c.b, c.a}; }

render::Camera render_camera(const CameraDef& c) {
    render::Camera camera;
    camera.projection = c.projection == CameraDef::Projection::orthographic ? render::Camera::Projection::orthographic
                                                                            : render::Camera::Projection::perspective;
    camera.eye = c.eye;
    camera.target = c.target;
    camera.up = c.up;
    camera.fov_y_deg = c.fov_y_deg;
    camera.ortho_height = c.ortho_height;
    return camera;
}

namespace {

render::Vec3 to_render(const sim::Vec3& v) { return v.cast<float>(); }

std::string format(const char* pattern, double value) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

// A link's colour by its strain: the body's colour at rest, towards red when
// stretched and blue when compressed, saturating at 10%.
render::Color strain_color(render::Color base, double strain) {
    const float t = static_cast<float>(std::clamp(std::abs(strain) / 0.1, 0.0, 1.0));
    const render::Color to = strain > 0 ? render::Color{0.9f, 0.08f, 0.05f, 1} : render::Color{0.1f, 0.3f, 0.95f, 1};
    return render::Color{base.r + t * (to.r - base.r), base.g + t * (to.g - base.g), base.b + t * (to.b - base.b),
                         base.a};
}

}  // namespace

std::string format_dt(double dt) {
    const double hz = 1.0 / dt;
    if (std::abs(hz - std::round(hz)) < 1e-9 * hz && hz >= 2) return "1/" + format("%.0f", hz) + " s";
    return format("%.4g", dt) + " s";
}

render::DrawList SceneRun::draw_list(int width, int height) const {
    render::DrawList list;
    list.camera = render_camera(scene_.camera);
    list.ground.enabled = scene_.view.ground;
    list.ground.height = static_cast<float>(scene_.view.ground_height);
    add_colliders(list);
    add_water(list);
    add_bodies(list);
    add_springs(list);
    add_particles(list);
    add_ghosts(list);
    add_overlays(list, width, height);
    return list;
}

double SceneRun::link_strain(std::uint32_t a, std::uint32_t b) const {
    const double rest = (scene_.model.particles[a].position - scene_.model.particles[b].position).norm();
    if (rest <= 0.0) return 0.0;
    return ((world_.state().x.get(a) - world_.state().x.get(b)).norm() - rest) / rest;
}

// Colliders, in their colours (invisible ones, such as a plane that is the ground, skipped).
void SceneRun::add_colliders(render::DrawList& list) const {
    for (std::size_t k = 0; k < scene_.model.collisions.colliders.size(); ++k) {
        const render::Look look{render_color(scene_.collider_colors[k])};
        if (look.color.a == 0.0f) continue;
        std::visit(
            sim::Overloaded{
                [&](const sim::PlaneCollider& p) {
                    list.planes.push_back(render::Plane{to_render(p.normal * p.offset), to_render(p.normal),
                                                        render::Vec2(8.0f, 8.0f), look});
                },
                [&](const sim::SphereCollider& c) {
                    list.spheres.push_back(render::Sphere{to_render(c.center), static_cast<float>(c.radius), look});
                },
                [&](const sim::BoxCollider& b) {
                    list.boxes.push_back(render::Box{to_render(b.center), to_render(b.half_extents),
                                                     Eigen::Quaternionf(b.rotation.cast<float>()), look});
                },
                [&](const sim::CapsuleCollider& c) {
                    list.capsules.push_back(
                        render::Capsule{to_render(c.a), to_render(c.b), static_cast<float>(c.radius), look});
                },
            },
            scene_.model.collisions.colliders[k]);
    }
}

void SceneRun::add_water(render::DrawList& list) const {
    if (!scene_.view.water) return;
    list.planes.push_back(
        render::Plane{render::Vec3(0.0f, static_cast<float>(scene_.view.water_height), 0.0f), render::Vec3::UnitY(),
                      render::Vec2(16.0f, 16.0f),
                      render::Look{render::Color{0.05f, 0.3f, 0.7f, 1.0f}, true}});  // translucent: a ghost
}

// Rigid bodies, then ropes, cloth and soft bodies.
void SceneRun::add_bodies(render::DrawList& list) const {
    add_rigid_bodies(list);
    for (const BodyLook& body : scene_.bodies) {
        if (body.kind == BodyLook::Kind::rope) {
            add_rope(list, body);
        } else {
            list.meshes.push_back(body_mesh(body));
        }
    }
}

// Rigid bodies, part by part where each is now (a body is a part, or a compound of several).
void SceneRun::add_rigid_bodies(render::DrawList& list) const {
    const sim::RigidWorld* rigid = world_.rigid();
    if (rigid == nullptr) return;
    for (const sim::PlacedPart& part : rigid->placed_parts()) {
        const render::Look look{render_color(scene_.body_colors[part.body.index])};
        const Eigen::Quaterniond& q = part.orientation;
        switch (part.shape) {
            case sim::RigidShape::box:
                list.boxes.push_back(
                    render::Box{to_render(part.center), to_render(0.5 * part.size), q.cast<float>(), look});
                break;
            case sim::RigidShape::sphere:
                list.spheres.push_back(render::Sphere{to_render(part.center), static_cast<float>(part.size.x()), look});
                break;
            case sim::RigidShape::capsule:
            case sim::RigidShape::cylinder: {
                const sim::Vec3 half = q * sim::Vec3(0, 0, 0.5 * part.size.y());
                const render::Vec3 a = to_render(part.center - half), b = to_render(part.center + half);
                const auto radius = static_cast<float>(part.size.x());
                if (part.shape == sim::RigidShape::capsule) {
                    list.capsules.push_back(render::Capsule{a, b, radius, look});
                } else {
                    list.cylinders.push_back(render::Cylinder{a, b, radius, look});
                }
                break;
            }
        }
    }
}

// A rope as rods through its nodes.
void SceneRun::add_rope(render::DrawList& list, const BodyLook& body) const {
    const sim::ParticleState& s = world_.state();
    for (const auto& [a, b] : body.range.links) {
        render::Color color = render_color(body.color);
        if (body.strain_colors) color = strain_color(render_color(body.color), link_strain(a, b));
        list.cylinders.push_back(render::Cylinder{to_render(s.x.get(a)), to_render(s.x.get(b)),
                                                  static_cast<float>(scene_.looks[a].radius), render::Look{color}});
    }
}

// Cloth and soft bodies as meshes over their surface.
render::Mesh SceneRun::body_mesh(const BodyLook& body) const {
    const sim::ParticleState& s = world_.state();
    const sim::BodyRange& r = body.range;
    render::Mesh mesh;
    mesh.look.color = render_color(body.color);
    mesh.positions.reserve(r.count);
    for (std::uint32_t k = 0; k < r.count; ++k) mesh.positions.push_back(to_render(s.x.get(r.first + k)));
    mesh.indices.reserve(3 * r.surface.size());
    for (const auto& tri : r.surface) {
        for (std::uint32_t v : tri) mesh.indices.push_back(v - r.first);
    }
    if (body.strain_colors) {
        // Per vertex: the largest |strain| of its links, signed.
        std::vector<double> strain(r.count, 0.0);
        for (const auto& [a, b] : r.links) {
            const double e = link_strain(a, b);
            for (std::uint32_t v : {a, b}) {
                double& cur = strain[v - r.first];
                if (std::abs(e) > std::abs(cur)) cur = e;
            }
        }
        mesh.colors.reserve(r.count);
        for (double e : strain) mesh.colors.push_back(strain_color(render_color(body.color), e));
    }
    return mesh;
}

// Springs as cylinders, thinner than the particles they join.
void SceneRun::add_springs(render::DrawList& list) const {
    const sim::ParticleState& s = world_.state();
    for (std::size_t index : scene_.drawn_springs) {
        if (const auto* springs = std::get_if<sim::Springs>(&scene_.model.forces[index])) {
            for (const sim::Spring& sp : springs->list) {
                const double r = 0.25 * std::min(scene_.looks[sp.i].radius, scene_.looks[sp.j].radius);
                list.cylinders.push_back(render::Cylinder{to_render(s.x.get(sp.i)), to_render(s.x.get(sp.j)),
                                                          static_cast<float>(std::min(r, 0.03)),
                                                          render::Look{render::Color{0.35f, 0.35f, 0.4f, 1}}});
            }
        }
    }
}

// Particles as spheres (emitter particles still parked left out), with their
// velocity and force arrows and their trails.
void SceneRun::add_particles(render::DrawList& list) const {
    const sim::ParticleState& s = world_.state();
    std::vector<bool> unborn(s.size(), false);  // emitter particles still parked
    for (const sim::Emitter& e : scene_.model.emitters) {
        for (std::uint32_t k = 0; k < e.count; ++k) unborn[e.first + k] = !sim::born(e, k, time());
    }
    const sim::Vec3Array forces = scene_.view.force_arrows > 0 ? world_.net_forces() : sim::Vec3Array();
    for (std::size_t i = 0; i < s.size(); ++i) {
        const ParticleLook& look = scene_.looks[i];
        if (!look.visible || unborn[i]) continue;
        list.spheres.push_back(render::Sphere{to_render(s.x.get(i)), static_cast<float>(look.radius),
                                              render::Look{render_color(look.color)}});
        if (scene_.view.velocity_arrows > 0)
            add_arrow(list, i, s.v.get(i) * scene_.view.velocity_arrows, render::Color{0.15f, 0.6f, 0.25f, 1});
        if (scene_.view.force_arrows > 0)
            add_arrow(list, i, forces.get(i) * scene_.view.force_arrows, render::Color{0.85f, 0.2f, 0.15f, 1});
        add_trail(list, i);
    }
}

// An arrow from a moving particle, scaled to metres; none shorter than its radius.
void SceneRun::add_arrow(render::DrawList& list, std::size_t i, const sim::Vec3& along, render::Color color) const {
    const sim::ParticleState& s = world_.state();
    const ParticleLook& look = scene_.looks[i];
    if (s.inv_mass[i] == 0.0 || along.norm() <= look.radius) return;
    list.arrows.push_back(render::Arrow{to_render(s.x.get(i)), to_render(along), 0.2f * static_cast<float>(look.radius),
                                        0.45f * static_cast<float>(look.radius), render::Look{color}});
}

// A particle's trail: its recorded positions, oldest first.
void SceneRun::add_trail(render::DrawList& list, std::size_t i) const {
    const auto& trail = trails_[i];
    if (trail.size() < 2) return;
    const ParticleLook& look = scene_.looks[i];
    render::Ribbon ribbon;
    ribbon.points.assign(trail.begin(), trail.end());
    ribbon.width = 0.5f * static_cast<float>(look.radius);
    ribbon.look.color = render_color(look.color);
    ribbon.look.color.a = 0.8f;
    list.ribbons.push_back(std::move(ribbon));
}

// Analytic solutions drawn over the simulated ones, translucent.
void SceneRun::add_ghosts(render::DrawList& list) const {
    for (const Ghost& g : scene_.ghosts) {
        if (g.body >= 0) {
            // A body's centre of mass: the whole analytic path, and where on it the body should be now.
            const render::Color color{0.15f, 0.4f, 0.85f, 1};  // the ghost's blue, apart from any body colour
            render::Ribbon path;
            const double end = scene_.frames * scene_.step.dt;
            for (int k = 0; k <= 96; ++k) path.points.push_back(to_render(g.exact(end * k / 96.0).x));
            path.width = 0.025f;
            path.look = render::Look{color, true};
            list.ribbons.push_back(std::move(path));
            list.spheres.push_back(render::Sphere{to_render(g.exact(time()).x), 0.07f, render::Look{color, true}});
            // The body's own centre of mass, a yellow dot on it: the one point that follows the ghost.
            const sim::BodyState body = world_.rigid()->state({static_cast<std::uint32_t>(g.body), 0});
            list.spheres.push_back(
                render::Sphere{to_render(body.position), 0.04f, render::Look{render::Color{0.95f, 0.8f, 0.1f, 1}}});
            continue;
        }
        const ParticleLook& look = scene_.looks[g.particle];
        list.spheres.push_back(render::Sphere{to_render(g.exact(time()).x), static_cast<float>(look.radius),
                                              render::Look{render_color(look.color), true}});
    }
}

// Overlays scale with the image: text about 1/20 of its height.
void SceneRun::add_overlays(render::DrawList& list, int width, int height) const {
    const float text = std::max(13.0f, static_cast<float>(height) / 22.0f);  // px; smaller text loses thin strokes
    if (scene_.view.hud) add_hud(list, text);
    if (scene_.view.energy_plot && energy_.size() >= 2) add_energy_plot(list, width, height, text);
}

// Top left: the scene, its integrator and step; time and energy; what exploded.
void SceneRun::add_hud(render::DrawList& list, float text) const {
    const std::string integrator(sim::integrator_info(step_.integrator).name);
    std::string title = scene_.name + " · " + integrator + " · Δt = " + format_dt(step_.dt);
    if (step_.substeps > 1) title += " / " + std::to_string(step_.substeps);
    list.texts.push_back(
        render::Text{title, render::Vec2(0.5f * text, 0.4f * text), text, render::Color{0.1f, 0.1f, 0.12f, 1}, true});
    const std::string state = "t = " + format("%.2f", time()) + " s   E = " + format("%.5g", world_.energy()) + " J";
    list.texts.push_back(render::Text{state, render::Vec2(0.5f * text, 1.9f * text), 0.85f * text,
                                      render::Color{0.2f, 0.2f, 0.25f, 1}, true});
    float line = 3.2f;
    for (const auto& c : world_.contained()) {
        list.texts.push_back(render::Text{
            c.name + ": exploded at frame " + std::to_string(c.verdict.frame) + " (frozen)",
            render::Vec2(0.5f * text, line * text), 0.8f * text, render::Color{0.8f, 0.05f, 0.05f, 1}, true});
        line += 1.2f;
    }
    if (diverged_ >= 0) {
        // A replayed recording whose state parted from the recorded one.
        list.texts.push_back(render::Text{"DIVERGED from the recording at frame " + std::to_string(diverged_),
                                          render::Vec2(0.5f * text, line * text), 0.8f * text,
                                          render::Color{0.8f, 0.05f, 0.05f, 1}, true});
        line += 1.2f;
    }
    if (verdict().exploded()) {
        list.texts.push_back(render::Text{verdict().message(scene_.name), render::Vec2(0.5f * text, line * text),
                                          0.8f * text, render::Color{0.8f, 0.05f, 0.05f, 1}, true});
    }
}

// Bottom right: the energy over the run so far.
void SceneRun::add_energy_plot(render::DrawList& list, int width, int height, float text) const {
    const float h = static_cast<float>(height), w = static_cast<float>(width);
    render::Plot plot;
    plot.size = render::Vec2(std::max(160.0f, 0.36f * w), std::max(100.0f, 0.3f * h));
    plot.position = render::Vec2(w - plot.size.x() - 0.3f * text, h - plot.size.y() - 0.3f * text);
    plot.text_size = std::max(9.0f, 0.7f * text);
    plot.title = "Energy (J)";
    plot.x_label = "t (s)";
    plot.x_range = render::Vec2(0.0f, static_cast<float>(scene_.frames * scene_.step.dt));
    plot.series.push_back(render::Plot::Series{"", energy_, render::Color{0.15f, 0.35f, 0.85f, 1}, 2.0f});
    list.plots.push_back(std::move(plot));
}

}  // namespace scenes
