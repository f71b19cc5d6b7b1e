// The scene being built from a file, shared by the section readers: the
// SceneDef so far, the names seen so far (particles, rigid bodies), and the
// readers themselves, one per section family, each in its own file
// (read_particles.cpp, read_rope.cpp, read_cloth.cpp, read_soft_body.cpp,
// read_emitters.cpp, read_rigid_bodies.cpp, read_ragdolls.cpp,
// read_chains.cpp, read_joints.cpp, read_forces.cpp, read_collisions.cpp,
// read_run_settings.cpp, read_camera_view.cpp, read_ghosts.cpp).
// scene_file.cpp calls them in the order below: a reader may use what an
// earlier one built (springs name particles, chains place a body, joints
// name bodies, ghosts read forces).
#pragma once

#include "scenes/model/scene.h"
#include "scenes/model/scene_keys.h"
#include "scenes/model/toml_section.h"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace scenes::loader {

// Limits that keep a malformed file from asking for absurd work or memory.
constexpr int kMaxFrames = 10'000'000;
constexpr std::size_t kMaxParticles = 1'000'000;
constexpr std::size_t kMaxSprings = 4'000'000;
constexpr int kMaxCheckpoints = 16;
constexpr int kMaxSubsteps = 10'000;
constexpr double kMaxSleepTime = 1e6;  // s, [rigid] sleep_time: 11.6 days at rest (shipped scenes: 0.5)
// deg/s, each component of a body's angular_velocity: the norm stays under
// sim::kMaxBodySpin (1,745 rad/s a component, 3,023 at most).
constexpr double kMaxSpinDegrees = 1e5;

// How a pinned particle looks, whatever its body's colour.
constexpr Color kPinnedColor{0.45f, 0.45f, 0.48f, 1};

// A palette for particles without a colour: distinct, readable on the light sky.
Color palette(std::size_t i);

struct SceneBuilder {
    const Reader& r;
    SceneDef& scene;
    std::map<std::string, std::size_t, std::less<>> particle_index;  // particle names
    std::map<std::string, int, std::less<>> body_index;              // rigid body names (model.rigid.bodies)
    std::vector<const toml::node*> joint_nodes;                      // where each of model.rigid.joints was written
    std::vector<Section> contained_ropes;  // the [[ropes]] with contain_explosion, for read_watchdog's check

    // Registers a particle's name (none when empty); names are unique.
    void add_name(const Section& s, const std::string& name, std::size_t index);
    // `count` particles more, within the scene's limit (the key "count").
    std::size_t new_particles(const Section& s, long long fallback) const;
    // A particle named by its name or its index, at `where` ("forces.springs[0].a").
    std::size_t particle_at(const toml::node& n, const std::string& where) const;
    // The same for a required key.
    std::size_t particle_ref(const Section& s, std::string_view key) const;
    // An array of particle names or indices; empty when absent.
    std::vector<std::uint32_t> particle_list(const Section& s, std::string_view key) const;

    // The first force of type T in model.forces, or none.
    template <typename T>
    const T* find_force() const {
        for (const sim::ForceDef& f : scene.model.forces) {
            if (const T* t = std::get_if<T>(&f)) return t;
        }
        return nullptr;
    }
};

// --- The readers, in the order scene_file.cpp calls them --------------------------------

// Timing and stepping (read_run_settings.cpp): frames and checkpoints, [step].
void read_timing(SceneBuilder& b, const Section& top);
void read_step(SceneBuilder& b, const Section& top);

// Particles: [[particles]] and [[groups]] (read_particles.cpp).
void read_particles(SceneBuilder& b, const Section& top);

// Bodies of particles from the physics core's builders, each in its own file.
void read_ropes(SceneBuilder& b, const Section& top);        // read_rope.cpp
void read_cloths(SceneBuilder& b, const Section& top);       // read_cloth.cpp
void read_soft_bodies(SceneBuilder& b, const Section& top);  // read_soft_body.cpp
void read_emitters(SceneBuilder& b, const Section& top);     // read_emitters.cpp

// Rigid bodies (ODE): [[bodies]] and [rigid] (read_rigid_bodies.cpp), [[ragdolls]]
// (read_ragdolls.cpp), [[chains]] (read_chains.cpp), [[joints]] and the
// mass-ratio warning (read_joints.cpp). [[bodies]] come first in the model,
// so a [[bodies]] entry's index is its place in the file.
void read_rigid_bodies(SceneBuilder& b, const Section& top);
void read_ragdolls(SceneBuilder& b, const Section& top);
void read_chains(SceneBuilder& b, const Section& top);
void read_joints(SceneBuilder& b, const Section& top);
void read_rigid_settings(SceneBuilder& b, const Section& top);
// step.dt / substeps at least sim::kMinRigidStep when there are rigid bodies.
void refuse_rigid_step_too_small(SceneBuilder& b, const Section& top);
void warn_jointed_mass_ratios(SceneBuilder& b);

// [forces] and its sub-tables (read_forces.cpp).
void read_forces(SceneBuilder& b, const Section& top);

// [constraints], [collisions], [[colliders]] (read_collisions.cpp).
void read_constraints(SceneBuilder& b, const Section& top);
void read_collisions(SceneBuilder& b, const Section& top);

// [watchdog] (read_run_settings.cpp), and a contained rope inside its world box;
// [camera] and [view] (read_camera_view.cpp).
void read_watchdog(SceneBuilder& b, const Section& top);
void read_camera(SceneBuilder& b, const Section& top);
void read_view(SceneBuilder& b, const Section& top);

// [[ghosts]]: closed forms from the scene's own parameters (read_ghosts.cpp).
void read_ghosts(SceneBuilder& b, const Section& top);

// Last, once the scene is whole: work that grows faster than the file (Newton
// gravity's pairs, times the integrator's passes and the substeps; trails,
// particles times frames), refused with its estimate (work_limits.cpp).
void refuse_work_too_large(SceneBuilder& b, const Section& top);

// --- Shared by the rope, cloth and soft-body readers (particle_body.cpp) ----------------

// link, stiffness, damping, compliance, tethers.
sim::LinkSettings link_keys(const Section& s, double default_stiffness);
// Names, looks and a BodyLook for the particles a builder just added.
void add_body(SceneBuilder& b, const Section& s, BodyLook::Kind kind, const sim::BodyRange& range,
              const std::string& name, Color color, bool nodes_visible, double node_radius);
// A body's links counted before it is built (a 100³ soft body has 12.7
// million: 8 s and 750 MB to build before the count refused it); refused past
// the scene's 4,000,000 with add_body's message. add_body counts again after
// the build (tethers included).
void refuse_links_ahead(const SceneBuilder& b, const Section& s, std::size_t body_links, std::size_t nodes);
// Runs a builder; its InputError (naming its field) becomes a SceneError that says where in the file.
sim::BodyRange build_body(const Section& s, const std::function<sim::BodyRange()>& build);

}  // namespace scenes::loader
