// A scene as its file describes it (immutable once loaded): the particle
// model, how it steps, how long it runs, what the watchdog allows, what the
// camera sees and which overlays a picture shows. Every consumer (run,
// render, check, video, view, report, tests) builds its worlds from one.
//
// Scene files are TOML (scenes/<name>.toml); scenes/model/scene_file.cpp
// reads them (one reader per section, listed in scene_builder.h), and
// docs/scene-format.md documents every key.
//
// The model room links sim and toml++ only: how a scene looks is plain data
// here (Color, CameraDef), and scenes/draw turns it into render's types.
#pragma once

#include "sim/analytic.h"
#include "sim/error.h"
#include "sim/mass_spring.h"
#include "sim/watchdog.h"
#include "sim/world.h"

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace scenes {

// A scene file or a --set override that cannot be used. The message starts
// with "file:line:column: " (or "--set KEY: ") and names the key, what was
// expected and what was found. The command exits 2 on it.
class SceneError : public sim::InputError {
public:
    using sim::InputError::InputError;
};

// A colour as a scene file gives it: linear RGB in [0, 1]; a = 0 is not drawn.
struct Color {
    float r = 0.8f, g = 0.8f, b = 0.8f, a = 1.0f;
};

// What the scene's camera sees ([camera]): floats, as the renderer takes them.
struct CameraDef {
    enum class Projection { perspective, orthographic };
    Projection projection = Projection::perspective;
    Eigen::Vector3f eye{4.0f, 3.0f, 6.0f};             // m
    Eigen::Vector3f target = Eigen::Vector3f::Zero();  // m, point at the centre of the image
    Eigen::Vector3f up = Eigen::Vector3f::UnitY();
    float fov_y_deg = 40.0f;    // degrees, vertical field of view (perspective)
    float ortho_height = 4.0f;  // m, visible height (orthographic)
};

// How a particle is drawn (drawing only, never physics).
struct ParticleLook {
    double radius = 0.1;  // m
    Color color;
    bool visible = true;  // cloth and soft-body nodes are drawn as their mesh instead
};

// A body a builder made (rope, cloth, soft body), for drawing: where its
// particles are and how it looks.
struct BodyLook {
    enum class Kind { rope, cloth, soft_body };
    Kind kind = Kind::rope;
    std::string name;
    sim::BodyRange range;
    Color color;
    bool strain_colors = false;  // links coloured by strain: red stretched, blue compressed
};

// A closed-form trajectory for one particle: the semi-transparent "ghost"
// beside the simulated particle, and what run summaries measure the error
// against. Derived from the scene's own parameters by the loader.
struct Ghost {
    std::size_t particle = 0;
    int body = -1;         // >= 0: follows this rigid body's centre of mass (model.rigid.bodies index)
    std::string solution;  // ballistic, oscillator, kepler, pendulum
    std::function<sim::analytic::PointState(double t)> exact;
};

// What a picture of the scene shows besides the bodies.
struct View {
    bool ground = true;
    double ground_height = 0.0;    // m
    int trail_frames = 0;          // frames of trail behind each moving particle; 0: none
    double velocity_arrows = 0.0;  // s: an arrow of v * this per moving particle; 0: none
    double force_arrows = 0.0;     // m/N: an arrow of the net force * this per moving particle; 0: none
    bool energy_plot = false;      // total energy over time, bottom right
    bool hud = true;               // scene, integrator, dt, t and E, top left
    bool water = false;            // a translucent water surface (scenes with buoyancy)
    double water_height = 0.0;     // m
};

// "KEY=VALUE" overrides applied to the file before validation, with the same
// checks (and their errors say "--set KEY").
struct Override {
    std::string key;    // dotted path: step.dt, forces.springs[0].stiffness, particles[1].mass
    std::string value;  // a TOML value: 0.01, "rk4", true, [0, 1, 0]
};

struct RecordedRun;  // scenes/model/recording.h

struct SceneDef {
    std::string name;                 // scene name (file stem)
    std::filesystem::path file;       // where it was read from
    std::string text;                 // the file as read (a recording keeps it, to build the scene again)
    std::vector<Override> overrides;  // what was set over the file (load_scene's), applied in order
    std::string description;          // one sentence

    sim::ParticleModel model;
    std::vector<std::string> particle_names;  // one per particle ("" for unnamed)
    std::vector<ParticleLook> looks;          // one per particle
    std::vector<BodyLook> bodies;             // ropes, cloths, soft bodies
    std::vector<std::size_t> drawn_springs;   // model.forces indices of [[forces.springs]], drawn as rods
    std::vector<Color> collider_colors;       // one per model.collisions.colliders entry
    std::vector<std::string> body_names;      // one per model.rigid.bodies entry
    std::vector<std::string> body_groups;     // one per model.rigid.bodies entry: its ragdoll or chain, "" for none
    std::vector<Color> body_colors;
    sim::StepSettings step;
    int frames = 600;              // frame steps the scene runs
    std::vector<int> checkpoints;  // frames the golden filmstrip shows, ascending, <= frames
    sim::WatchdogLimits watchdog;
    CameraDef camera;
    View view;
    std::vector<Ghost> ghosts;
    // What is legal but likely a mistake (a jointed mass ratio over 10:1),
    // each "file:line:column: message"; the command prints them to stderr.
    std::vector<std::string> warnings;
    // Set when the scene came from a recording (scene_of): every run of it
    // checks each frame's state hash against the recorded one.
    std::shared_ptr<const RecordedRun> recorded;

    // The systems this scene builds, for `run --json` ("particles", "springs", ...).
    std::vector<std::string> systems() const;
};

// A named thing in a scene, for saying which one changed (`check`): a rope,
// cloth, soft body, emitter, named particle (or named group of particles),
// or rigid body (a ragdoll's bone or a chain's link grouped under its
// ragdoll or chain).
struct SceneObject {
    std::string name;       // as the scene names it: "rope", "emitter0", "ragdoll1.pelvis"
    std::string group;      // the ragdoll or chain of a rigid body; "" for none
    bool rigid = false;     // true: rigid bodies [first, first + count), else particles
    std::size_t first = 0;  // index of the first particle or model.rigid.bodies entry
    std::size_t count = 0;
};
// Every object of the scene, in a fixed order: the bodies (ropes, cloths,
// soft bodies), the emitters, the named particles outside them (a group
// "name[0]", "name[1]", ... as one object "name"), then the rigid bodies.
// Unnamed particles belong to no object.
std::vector<SceneObject> scene_objects(const SceneDef& scene);

Override parse_override(const std::string& text);  // "KEY=VALUE"; SceneError when malformed

// Reads and validates a scene file. Throws SceneError.
SceneDef load_scene(const std::filesystem::path& file, const std::vector<Override>& overrides = {});
// The same from text (tests); `display_name` stands for the file in messages.
SceneDef parse_scene(std::string_view text, const std::string& display_name,
                     const std::vector<Override>& overrides = {});

// A number in the scene file that a person may want to turn (the viewer's
// sliders): its --set key and its value in the file, or in `overrides` when
// one sets it. Changing one rebuilds the scene from the file with the key
// overridden.
struct Parameter {
    std::string key;  // e.g. forces.springs[0].stiffness
    double value = 0.0;
    bool integer = false;
};
std::vector<Parameter> scene_parameters(const SceneDef& scene, const std::vector<Override>& overrides = {});

// Where the shipped scenes/ and golden/ are: the source tree for a command
// run from its build tree, <prefix>/share/plausible for an installed one
// (docs/design.md, "Installed"). Throws SceneError naming the path when
// they are not there.
std::filesystem::path data_dir();
// Shipped scenes: the ordered catalogue (scenes/catalog.txt) and where their
// files live ($PLAUSIBLE_SCENES_DIR, else data_dir()/scenes).
std::filesystem::path scenes_dir();
std::vector<std::string> catalog();
// A catalogue name or the path of a .toml file. Throws SceneError naming the
// known scenes when it is neither.
std::filesystem::path resolve_scene(const std::string& name_or_path);

}  // namespace scenes
