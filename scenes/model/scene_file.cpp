// Scene files: TOML read with toml++, validated strictly, turned into a
// SceneDef. Every error names file:line:column, the key, what was expected and
// what was found, e.g.
//   scenes/rope.toml:12:5: forces.springs[0].stiffness must be >= 0 and finite, in N/m (got -3)
//
// The format (all keys but `description` are optional; units SI, angles in degrees):
//   description = "One sentence."
//   frames = 600                      # frame steps the scene runs
//   checkpoints = [0, 60, 120]        # frames the golden filmstrip shows
//   [step]       integrator = "symplectic_euler", dt = 0.0166667 (s), substeps = 1
//   [[particles]] name, position = [x, y, z] (m), velocity (m/s), mass (kg), pinned,
//                 radius (m, drawing), color = "#rrggbb" or [r, g, b]
//   [[groups]]   name, count, start (m), spacing (m, between neighbours), and the
//                particle keys above (velocity, mass, pinned, radius, color)
//   [forces.gravity] g = [0, -9.81, 0]      [forces.drag] c (N·s/m)
//   [forces.quadratic_drag] c (N·s²/m²)     [forces.newton_gravity] G, softening
//   [[forces.springs]] a, b (particle names or indices), rest_length (m; default:
//                the initial distance), stiffness (N/m), damping (N·s/m)
//   [forces.wind] velocity (m/s), air_density (kg/m³), drag_coefficient, gust_strength (m/s),
//                gust_period (s), seed, bodies = [cloth or soft-body names], particles, radius (m)
//   [[forces.buoyancy]] surface_height (m), fluid_density (kg/m³), radius (m), drag (N·s/m),
//                particles (default all); g from [forces.gravity]
//   [[forces.shock_waves]] center (m), start_time (s), speed (m/s), thickness (m), strength (N),
//                reference_distance (m), max_radius (m)
//   [[forces.control]] start, end (s), particles = [names or indices], force (N, on each)
//   Bodies (their particles are named "<name>[k]"; links: link = "springs"|"constraints",
//                stiffness (N/m), damping (N·s/m), compliance (m/N), tethers, strain_colors;
//                ropes also contain_explosion: its explosion freezes it and the run goes on):
//   [[ropes]]    name, start, end (m), segments, mass (kg, whole rope), radius (m), pin_start,
//                pin_end, color, and the link keys
//   [[cloths]]   name, corner, u, v (m, the two sides), nx, ny (nodes), mass, radius, shear,
//                bend (stiffness factors), pins = "none"|"corners"|"edge"|"all", color, link keys
//   [[soft_bodies]] name, corner, size (m), nx, ny, nz, mass, radius, velocity (m/s), color,
//                link keys, yield_strain, creep (1/s), max_strain (plastic when yield_strain > 0)
//   [[emitters]] name, count, position (m), direction, cone (deg), speed (m/s), speed_jitter,
//                rate (particles/s; each lives count / rate s), seed, mass (kg), radius (m), color
//   Rigid bodies (ODE; a scene without them makes no ODE world):
//   [rigid]      gravity (m/s², default [0, -9.81, 0]), quickstep, iterations, friction, restitution, bounce_velocity
//   (m/s), erp, cfm,
//                ground, ground_height (m), seed, sleep, sleep_speed (m/s, RMS), sleep_time (s),
//                self_collision, position_iterations, speculative_stops; the [[colliders]] are static
//                geometry for bodies too
//   [[bodies]]   name, shape = "box"|"sphere"|"capsule"|"cylinder", size (m: box extents; radius,
//                length), mass (kg) or density (kg/m³), position (m), rotation ([x, y, z] deg),
//                velocity (m/s), angular_velocity (deg/s), com (m, in the shape's frame), color
//                or parts = [{shape, size, offset (m), rotation, density}, ...] (a compound body)
//   [[ragdolls]] name, height (m), mass (kg), position (m, pelvis), rotation, velocity (m/s),
//                angular_velocity (deg/s), joint_friction (N·m), color; bones are "<name>.<bone>"
//   [[joints]]   type = "ball"|"hinge"|"universal"|"slider"|"fixed", a, b (body names; b absent:
//                the world), anchor (m), axis, axis2, lo, hi (deg; m for sliders), lo2, hi2
//                (universal: axis2; ball: swing about axis2 × axis), lo3, hi3 (ball: twist),
//                stop_stiffness, stop_damping, motor_velocity (deg/s; m/s), motor_max_force
//   [constraints] iterations (Gauss-Seidel sweeps per substep)
//   [collisions] restitution, friction, rest_speed (m/s), particles (particle-particle, bool;
//                also a cloth's self-collision when its radius is under half its link length)
//   [[colliders]] shape = "plane" (normal, offset m) | "sphere" (center, radius) |
//                "box" (center, half_extents, rotation = [x, y, z] degrees) | "capsule" (a, b, radius);
//                color; visible (planes at the ground are not drawn twice)
//   [watchdog]   enabled, max_speed (m/s), world_half_extent (m), energy_growth, energy_floor (J)
//   [camera]     projection = "perspective"|"orthographic", eye, target, up, fov (deg), height (m)
//   [view]       ground, ground_height (m), trail_frames, velocity_arrows (s), force_arrows (m/N), energy_plot, hud
//   [[ghosts]]   particle, solution = "ballistic"|"oscillator"|"kepler"|"pendulum",
//                anchor (oscillator, pendulum: the pinned particle), center (kepler);
//                or body (a rigid body's centre of mass), solution = "ballistic"
//
// This file is the loader's outline: parse the text, apply the --set
// overrides, then read the sections in order, one reader per section family
// (scene_builder.h lists them and their files), and let the physics core check
// the result.
#include "scenes/model/overrides.h"
#include "scenes/model/scene.h"
#include "scenes/model/scene_builder.h"

#include <fstream>

namespace scenes {
namespace loader {
namespace {

// The top level's own keys: description is the one key every scene needs.
void read_top(const Section& top, SceneDef& scene) {
    const Reader& reader = top.reader();
    if (top.table().empty())
        reader.fail(nullptr, "the file is empty: a scene needs at least description and [[particles]]");
    top.only(keys::top);
    if (top.node("description") == nullptr)
        reader.fail(&top.table(), "description is required: one sentence saying what the scene shows");
    scene.description = top.string("description", "", 300);
}

// Particles (of any builder) or rigid bodies: a scene needs something to move.
void require_bodies(const SceneBuilder& b, const Section& top) {
    if (b.scene.model.particles.empty() && b.scene.model.rigid.empty()) {
        b.r.fail(&top.table(),
                 "a scene needs at least one [[particles]], [[groups]], [[ropes]], [[cloths]], "
                 "[[soft_bodies]], [[emitters]], [[bodies]] or [[ragdolls]] entry");
    }
}

// The readers in order: a reader may use what an earlier one built.
SceneDef build(const toml::table& root, Reader& reader, const std::string& name) {
    SceneDef scene;
    scene.name = name;
    const Section top(reader, root, "");
    read_top(top, scene);
    SceneBuilder b{reader, scene, {}, {}, {}};
    read_timing(b, top);
    read_step(b, top);
    read_particles(b, top);
    read_ropes(b, top);
    read_cloths(b, top);
    read_soft_bodies(b, top);
    read_emitters(b, top);
    read_rigid_bodies(b, top);
    read_ragdolls(b, top);
    read_joints(b, top);
    read_rigid_settings(b, top);
    warn_jointed_mass_ratios(b);
    require_bodies(b, top);
    read_forces(b, top);
    read_constraints(b, top);
    read_collisions(b, top);
    read_watchdog(b, top);
    read_camera(b, top);
    read_view(b, top);
    read_ghosts(b, top);
    // The physics core's own checks, as a backstop (they name the item, not the line).
    try {
        sim::validate(scene.model);
        sim::validate(scene.step);
        sim::validate(scene.watchdog);
    } catch (const sim::InputError& e) {
        throw SceneError(reader.file() + ": " + e.what());
    }
    return scene;
}

SceneDef parse_with(std::string_view text, const std::string& display, const std::string& name,
                    const std::vector<Override>& overrides) {
    Reader reader(display);
    toml::table root;
    try {
        root = toml::parse(text, display);
    } catch (const toml::parse_error& e) {
        const auto& at = e.source().begin;
        throw SceneError(display + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                         ": not valid TOML: " + std::string(e.description()));
    }
    apply_overrides(root, overrides, reader);
    return build(root, reader, name);
}

}  // namespace
}  // namespace loader

SceneDef parse_scene(std::string_view text, const std::string& display_name, const std::vector<Override>& overrides) {
    return loader::parse_with(text, display_name, std::filesystem::path(display_name).stem().string(), overrides);
}

SceneDef load_scene(const std::filesystem::path& file, const std::vector<Override>& overrides) {
    constexpr std::uintmax_t kMaxBytes = 16u << 20;  // a scene file is text a person writes
    std::error_code error;
    const auto size = std::filesystem::file_size(file, error);
    if (error) throw SceneError(file.string() + ": cannot read the scene file (" + error.message() + ")");
    if (size > kMaxBytes)
        throw SceneError(file.string() + ": " + std::to_string(size) +
                         " bytes is too large for a scene file (at most 16 MiB)");
    std::ifstream in(file, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) throw SceneError(file.string() + ": cannot read the scene file");
    SceneDef scene = loader::parse_with(text, file.string(), file.stem().string(), overrides);
    scene.file = file;
    return scene;
}

}  // namespace scenes
