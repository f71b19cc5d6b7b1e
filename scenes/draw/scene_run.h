// One run of a scene: a World built from the SceneDef (docs/design.md rule 2), the
// frame counter, what pictures need from the past (trails, the energy curve)
// (scene_run.cpp), and the glue that turns it all into a render::DrawList
// (draw_list.cpp; docs/design.md rule 1: sim knows nothing of rendering, render
// nothing of physics; this room knows both). run, render, check, video and
// view all step scenes through it.
#pragma once

#include "render/draw_list.h"
#include "scenes/model/scene.h"

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace scenes {

class SceneRun {
public:
    // The description must outlive the run. The step settings start as the
    // scene's; the viewer may change them between frames.
    explicit SceneRun(const SceneDef& scene);

    // One frame step (World::step). False once the watchdog has stopped the run.
    bool advance();
    // The same, keeping the state hash after each substep in `substep_hashes`
    // (the last is the frame's, state_hash()): where `check` looks for the
    // first substep that differs.
    bool advance(std::vector<std::uint64_t>& substep_hashes);

    const sim::StepSettings& step() const { return step_; }
    void set_step(const sim::StepSettings& step);  // validates (InputError)

    // Everything a frame needs to be shown again and stepped on from (the
    // viewer's step back): the world's snapshot, the frame counter and the
    // trails; the energy curve is cut back to the frame. The step settings
    // stay as they are now (an integrator chosen since is kept).
    struct Snapshot {
        sim::World::Snapshot world;
        int frame = 0;
        // The trails end to end, oldest point first: particle i's are
        // trail_points[trail_ends[i - 1] .. trail_ends[i]). Two arrays, not
        // a deque per particle: the viewer takes a snapshot every step, and
        // a deque's copy allocates 576 bytes even empty (1.1 MB a frame of
        // fresh pages for the showcase's 1900 particles with no trail).
        std::vector<render::Vec3> trail_points;
        std::vector<std::uint32_t> trail_ends;
        std::size_t bytes() const;  // about what it holds, for a history's budget
    };
    Snapshot snapshot() const;
    void restore(const Snapshot& snapshot);
    // Mouse drags and other direct edits.
    sim::World& world_for_edit() { return world_; }

    // A scene from a recording (SceneDef::recorded): the first frame whose
    // state hash differs from the recorded one, checked as each frame up to
    // the recording's last is reached; -1: none (or not a recording).
    int diverged_frame() const { return diverged_; }
    // A recording's frame, quickly: the nearest stored state at or before it,
    // then steps (trails start again from there). False when the scene is
    // not a recording or the frame is beyond it.
    bool seek(int frame);

    int frame() const { return frame_; }
    double time() const { return world_.state().t; }  // s
    const sim::World& world() const { return world_; }
    const SceneDef& scene() const { return scene_; }
    const sim::Verdict& verdict() const { return world_.verdict(); }
    std::uint64_t state_hash() const;
    std::string state_hash_hex() const;
    // One hash per object (scene_objects' order) of its state now: FNV-1a over
    // its particles' x and v, or its rigid bodies' position, orientation,
    // velocity and angular velocity; the low 32 bits (for naming what
    // changed, not for judging: the state hash judges).
    std::vector<std::uint32_t> object_hashes(const std::vector<SceneObject>& objects) const;

    // The picture now, for an image of width x height px (overlays are laid
    // out in pixels).
    render::DrawList draw_list(int width, int height) const;

private:
    void record();
    void compare_with_recording();  // the frame now against the recorded hash (diverged_)

    // The picture, one kind of thing at a time (draw_list.cpp); draw_list()
    // calls them in this order, which is the order of the list's items.
    void add_colliders(render::DrawList& list) const;
    void add_water(render::DrawList& list) const;
    void add_bodies(render::DrawList& list) const;  // rigid, then ropes, cloth and soft bodies
    void add_springs(render::DrawList& list) const;
    void add_particles(render::DrawList& list) const;  // with their arrows and trails
    void add_ghosts(render::DrawList& list) const;
    void add_overlays(render::DrawList& list, int width, int height) const;  // HUD text, energy plot

    void add_rigid_bodies(render::DrawList& list) const;
    void add_rope(render::DrawList& list, const BodyLook& body) const;
    render::Mesh body_mesh(const BodyLook& body) const;
    void add_arrow(render::DrawList& list, std::size_t particle, const sim::Vec3& along, render::Color color) const;
    void add_trail(render::DrawList& list, std::size_t particle) const;
    void add_hud(render::DrawList& list, float text) const;  // text: px, the title's height
    void add_energy_plot(render::DrawList& list, int width, int height, float text) const;
    double link_strain(std::uint32_t a, std::uint32_t b) const;  // (length - built length) / built length

    const SceneDef& scene_;
    sim::StepSettings step_;
    sim::World world_;
    int frame_ = 0;
    int diverged_ = -1;                             // diverged_frame()
    std::vector<std::deque<render::Vec3>> trails_;  // per particle, oldest first (empty for pinned ones)
    std::vector<render::Vec2> energy_;              // (t s, E J) per frame
};

// The model's look data (plain colours and camera) in render's types.
render::Color render_color(const Color& c);
render::Camera render_camera(const CameraDef& c);

// "1/60 s" when dt is the reciprocal of a whole number, else "0.004 s".
std::string format_dt(double dt);

}  // namespace scenes
