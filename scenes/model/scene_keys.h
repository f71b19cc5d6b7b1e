// Every key a scene file may hold, one table per section, written once: the
// section readers check a table against it (Section::only) and scene_keys()
// lists them all for the test that keeps docs/scene-format.md complete.
// Its own file because it is the loader's whole vocabulary in one place; the
// order of each table is the order the "expected one of:" message lists.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace scenes {

namespace keys {

using Table = std::span<const std::string_view>;

// The tables are wrapped by hand, a line per group of keys.
// clang-format off

// The top level: a few keys and the sections below.
inline constexpr std::string_view top[] = {
    "description", "frames", "checkpoints", "step", "particles", "groups", "ropes", "cloths", "soft_bodies",
    "emitters", "bodies", "ragdolls", "chains", "joints", "rigid", "forces", "constraints", "collisions", "colliders",
    "watchdog", "camera", "view", "ghosts"};
inline constexpr std::string_view step[] = {"integrator", "dt", "substeps"};

// Particles and the builders that make them.
inline constexpr std::string_view particle[] = {"name", "position", "velocity", "mass", "pinned", "radius", "color"};
inline constexpr std::string_view group[] = {"name", "count",  "start",  "spacing", "velocity",
                                             "mass", "pinned", "radius", "color"};
inline constexpr std::string_view rope[] = {
    "name",  "start", "end",       "segments", "mass",       "radius",  "pin_start",     "pin_end",
    "color", "link",  "stiffness", "damping",  "compliance", "tethers", "strain_colors", "contain_explosion"};
inline constexpr std::string_view cloth[] = {"name", "corner",    "u",       "v",          "nx",      "ny",
                                             "mass", "radius",    "shear",   "bend",       "pins",    "color",
                                             "link", "stiffness", "damping", "compliance", "tethers", "strain_colors"};
inline constexpr std::string_view soft_body[] = {
    "name",    "corner",        "size",         "nx",    "ny",        "nz",      "mass",
    "radius",  "velocity",      "color",        "link",  "stiffness", "damping", "compliance",
    "tethers", "strain_colors", "yield_strain", "creep", "max_strain"};
inline constexpr std::string_view emitter[] = {"name",         "count", "position", "direction", "cone",   "speed",
                                               "speed_jitter", "rate",  "seed",     "mass",      "radius", "color"};

// Rigid bodies (ODE).
inline constexpr std::string_view rigid[] = {"quickstep",
                                             "iterations",
                                             "friction",
                                             "restitution",
                                             "bounce_velocity",
                                             "joint_erp",
                                             "joint_cfm",
                                             "contact_erp",
                                             "contact_cfm",
                                             "ground",
                                             "ground_height",
                                             "seed",
                                             "sleep",
                                             "sleep_speed",
                                             "sleep_time",
                                             "gravity",
                                             "self_collision",
                                             "articulated",
                                             "position_iterations",
                                             "position_slop",
                                             "speculative_stops"};
inline constexpr std::string_view body[] = {"name",    "shape",    "size",     "parts",    "mass",
                                            "density", "position", "rotation", "velocity", "angular_velocity",
                                            "com",     "color"};
inline constexpr std::string_view body_part[] = {"shape", "size", "offset", "rotation", "density"};
inline constexpr std::string_view ragdoll[] = {"name",     "height",           "mass",           "position", "rotation",
                                               "velocity", "angular_velocity", "joint_friction", "color"};
inline constexpr std::string_view chain[] = {"name",   "anchor", "direction", "links", "link_length", "radius",
                                             "mass",   "fixed",  "color",     "end",   "end_offset"};
inline constexpr std::string_view joint[] = {"type",
                                             "a",
                                             "b",
                                             "anchor",
                                             "axis",
                                             "axis2",
                                             "lo",
                                             "hi",
                                             "lo2",
                                             "hi2",
                                             "lo3",
                                             "hi3",
                                             "stop_stiffness",
                                             "stop_damping",
                                             "motor_velocity",
                                             "motor_max_force"};

// Forces.
inline constexpr std::string_view forces[] = {"gravity", "drag",     "quadratic_drag", "newton_gravity", "springs",
                                              "wind",    "buoyancy", "shock_waves",    "control"};
inline constexpr std::string_view gravity[] = {"g"};
inline constexpr std::string_view drag[] = {"c"};  // [forces.drag] and [forces.quadratic_drag]
inline constexpr std::string_view newton_gravity[] = {"G", "softening"};
inline constexpr std::string_view spring[] = {"a", "b", "rest_length", "stiffness", "damping"};
inline constexpr std::string_view wind[] = {"velocity",      "air_density", "drag_coefficient",
                                            "gust_strength", "gust_period", "seed",
                                            "bodies",        "particles",   "radius"};
inline constexpr std::string_view buoyancy[] = {"surface_height", "fluid_density", "radius", "drag", "particles"};
inline constexpr std::string_view shock_wave[] = {"center",   "start_time",         "speed",     "thickness",
                                                  "strength", "reference_distance", "max_radius"};
inline constexpr std::string_view control[] = {"start", "end", "particles", "force"};

// Constraints, collisions and colliders (a collider's keys depend on its shape).
inline constexpr std::string_view constraints[] = {"iterations"};
inline constexpr std::string_view collisions[] = {"restitution", "friction", "rest_speed", "particles"};
inline constexpr std::string_view plane_collider[] = {"shape", "normal", "offset", "color", "visible"};
inline constexpr std::string_view sphere_collider[] = {"shape", "center", "radius", "color", "visible"};
inline constexpr std::string_view box_collider[] = {"shape", "center", "half_extents", "rotation", "color", "visible"};
inline constexpr std::string_view capsule_collider[] = {"shape", "a", "b", "radius", "color", "visible"};

// How the run is watched and how it looks.
inline constexpr std::string_view watchdog[] = {"enabled", "max_speed", "world_half_extent", "energy_growth",
                                                "energy_floor"};
inline constexpr std::string_view camera[] = {"projection", "eye", "target", "up", "fov", "height"};
inline constexpr std::string_view view[] = {"ground",       "ground_height", "trail_frames", "velocity_arrows",
                                            "force_arrows", "energy_plot",   "hud"};
inline constexpr std::string_view ghost[] = {"particle", "body", "solution", "anchor", "center"};

// clang-format on

// A section of the file and the tables its keys may come from (colliders: one per shape).
struct SectionKeys {
    std::string_view path;  // dotted, without indices: "", "forces.springs", "bodies.parts"
    std::vector<Table> tables;
};
// Every section the loader reads, in the order of the file format.
const std::vector<SectionKeys>& sections();

}  // namespace keys

// Every key the loader accepts as a dotted path without indices, in section
// order: "description", "step.dt", "forces.springs.stiffness",
// "bodies.parts.shape". A key that is itself a section ("forces",
// "bodies.parts") is not listed: its keys are.
std::vector<std::string> scene_keys();

}  // namespace scenes
