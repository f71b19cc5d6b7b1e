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
// Contents: 1. locations and messages  2. typed reads  3. sections  4. ghosts
//           5. overrides  6. entry points
#include "scenes/model/scene.h"

#include "sim/ragdoll.h"

#include <toml++/toml.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

namespace scenes {
namespace {

// Limits that keep a malformed file from asking for absurd work or memory.
constexpr int kMaxFrames = 10'000'000;
constexpr std::size_t kMaxParticles = 1'000'000;
constexpr std::size_t kMaxSprings = 4'000'000;
constexpr int kMaxCheckpoints = 16;
constexpr int kMaxSubsteps = 10'000;

// --- 1. Locations and messages ---------------------------------------------------

std::string quote(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 0x20) ? '?' : c;
    if (s.size() > 60) out += "...";
    return out + "'";
}

// What a node is, for "(got ...)".
std::string describe(const toml::node& node) {
    if (auto v = node.value<double>(); v && (node.is_integer() || node.is_floating_point())) {
        return sim::format_value(*v);
    }
    if (auto s = node.value<std::string>()) return "the string " + quote(*s);
    if (auto b = node.value<bool>()) return *b ? "true" : "false";
    if (node.is_array()) return "an array of " + std::to_string(node.as_array()->size());
    if (node.is_table()) return "a table";
    return "a date or time";
}

// Edit distance, for "did you mean" on unknown keys.
std::size_t distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = up;
        }
    }
    return row[b.size()];
}

class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}

    // Nodes made by --set have no place in the file: they are named by the override.
    void mark_override(const toml::node* node, std::string text) { overrides_[node] = std::move(text); }

    std::string where(const toml::node* node) const {
        if (node != nullptr) {
            if (auto it = overrides_.find(node); it != overrides_.end()) return "--set " + it->second;
            const auto& begin = node->source().begin;
            if (begin.line > 0) return file_ + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column);
        }
        return file_ + ":1:1";  // about the whole file
    }
    [[noreturn]] void fail(const toml::node* node, const std::string& message) const {
        throw SceneError(where(node) + ": " + message);
    }
    const std::string& file() const { return file_; }

private:
    std::string file_;
    std::map<const toml::node*, std::string> overrides_;
};

// --- 2. Typed reads of one table ---------------------------------------------------

// A table of the file with its dotted path ("forces.springs[0]"), read key by key.
class Section {
public:
    Section(const Reader& reader, const toml::table& table, std::string path)
        : r_(reader), t_(table), path_(std::move(path)) {}

    const toml::table& table() const { return t_; }
    const std::string& path() const { return path_; }
    std::string key_path(std::string_view key) const {
        return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
    }
    const toml::node* node(std::string_view key) const { return t_.get(key); }
    [[noreturn]] void fail(std::string_view key, const std::string& message) const {
        const toml::node* n = node(key);
        r_.fail(n != nullptr ? n : static_cast<const toml::node*>(&t_), key_path(key) + " " + message);
    }

    // Every key must be one of `allowed`; the error suggests the nearest.
    void only(std::initializer_list<std::string_view> allowed) const {
        for (auto&& [key, value] : t_) {
            const std::string_view k = key.str();
            if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
            std::string list, best;
            std::size_t best_distance = 3;
            for (std::string_view a : allowed) {
                list += (list.empty() ? "" : ", ") + std::string(a);
                if (const std::size_t d = distance(k, a); d < best_distance) best_distance = d, best = a;
            }
            const std::string hint = best.empty() ? "" : " (did you mean '" + best + "'?)";
            r_.fail(&value, "unknown key " + quote(key_path(k)) + hint + "; expected one of: " + list);
        }
    }

    // A finite number within [lo, hi] (an integer literal is fine).
    double number(std::string_view key, double fallback, double lo, double hi, const char* unit) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        const auto value = n->value<double>();
        const std::string range = range_text(lo, hi, unit);
        if (!value || !(n->is_integer() || n->is_floating_point()))
            fail(key, "must be a number " + range + " (got " + describe(*n) + ")");
        if (!std::isfinite(*value) || *value < lo || *value > hi) {
            fail(key, "must be " + range + " (got " + sim::format_value(*value) + ")");
        }
        return *value;
    }
    // Strictly positive, at most hi.
    double positive(std::string_view key, double fallback, double hi, const char* unit) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        const auto value = n->value<double>();
        std::string expected = "must be > 0 and finite, in " + std::string(unit);
        if (hi < 1e300) expected = "must be > 0 and at most " + sim::format_value(hi) + ", in " + std::string(unit);
        if (!value || !(n->is_integer() || n->is_floating_point())) fail(key, expected + " (got " + describe(*n) + ")");
        if (!std::isfinite(*value) || !(*value > 0) || *value > hi)
            fail(key, expected + " (got " + sim::format_value(*value) + ")");
        return *value;
    }
    long long integer(std::string_view key, long long fallback, long long lo, long long hi) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        if (!n->is_integer()) {
            fail(key, "must be an integer within " + std::to_string(lo) + " .. " + std::to_string(hi) + " (got " +
                          describe(*n) + ")");
        }
        const long long v = *n->value<long long>();
        if (v < lo || v > hi) {
            fail(key, "must be within " + std::to_string(lo) + " .. " + std::to_string(hi) + " (got " +
                          std::to_string(v) + ")");
        }
        return v;
    }
    bool boolean(std::string_view key, bool fallback) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        if (!n->is_boolean()) fail(key, "must be true or false (got " + describe(*n) + ")");
        return *n->value<bool>();
    }
    std::string string(std::string_view key, const std::string& fallback, std::size_t max_length = 200) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        if (!n->is_string()) fail(key, "must be a string (got " + describe(*n) + ")");
        std::string s = *n->value<std::string>();
        if (s.size() > max_length)
            fail(key, "must be at most " + std::to_string(max_length) + " bytes long (got " + std::to_string(s.size()) +
                          ")");
        return s;
    }
    // One of a fixed set of words.
    std::string word(std::string_view key, const std::string& fallback,
                     std::initializer_list<std::string_view> words) const {
        const std::string s = string(key, fallback);
        std::string list;
        for (std::string_view w : words) {
            if (w == s) return s;
            list += (list.empty() ? "" : ", ") + std::string(w);
        }
        fail(key, "must be one of " + list + " (got " + quote(s) + ")");
    }
    // [x, y, z] of finite numbers, each within +-limit.
    sim::Vec3 vec3(std::string_view key, const sim::Vec3& fallback, const char* unit, double limit = 1e9) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        const toml::array* a = n->as_array();
        const std::string expected = "must be [x, y, z]: three finite numbers in " + std::string(unit);
        if (a == nullptr || a->size() != 3) fail(key, expected + " (got " + describe(*n) + ")");
        sim::Vec3 v;
        for (std::size_t i = 0; i < 3; ++i) {
            const toml::node& e = *a->get(i);
            const auto x = e.value<double>();
            if (!x || !(e.is_integer() || e.is_floating_point()) || !std::isfinite(*x) || std::abs(*x) > limit) {
                r_.fail(&e, key_path(key) + "[" + std::to_string(i) + "] " + expected + ", within +-" +
                                sim::format_value(limit) + " (got " + describe(e) + ")");
            }
            v[static_cast<int>(i)] = *x;
        }
        return v;
    }
    Color color(std::string_view key, const Color& fallback) const {
        const toml::node* n = node(key);
        if (n == nullptr) return fallback;
        const std::string expected = "must be \"#rrggbb\" or [r, g, b] with each in 0 .. 1";
        if (auto s = n->value<std::string>()) {
            unsigned rgb = 0;
            char end = 0;
            if (s->size() != 7 || (*s)[0] != '#' || std::sscanf(s->c_str() + 1, "%6x%c", &rgb, &end) != 1) {
                fail(key, expected + " (got " + quote(*s) + ")");
            }
            return Color{static_cast<float>((rgb >> 16) & 0xFF) / 255.0f,
                                 static_cast<float>((rgb >> 8) & 0xFF) / 255.0f,
                                 static_cast<float>(rgb & 0xFF) / 255.0f, 1};
        }
        const toml::array* a = n->as_array();
        if (a == nullptr || a->size() != 3) fail(key, expected + " (got " + describe(*n) + ")");
        float c[3];
        for (std::size_t i = 0; i < 3; ++i) {
            const auto x = a->get(i)->value<double>();
            if (!x || !(*x >= 0.0 && *x <= 1.0))
                fail(key, expected + " (got " + describe(*a->get(i)) + " at [" + std::to_string(i) + "])");
            c[i] = static_cast<float>(*x);
        }
        return Color{c[0], c[1], c[2], 1};
    }
    // A sub-table, or none.
    const toml::table* subtable(std::string_view key) const {
        const toml::node* n = node(key);
        if (n == nullptr) return nullptr;
        if (!n->is_table()) fail(key, "must be a table (got " + describe(*n) + ")");
        return n->as_table();
    }
    // An array of tables ([[key]]), or none.
    std::vector<const toml::table*> tables(std::string_view key, std::size_t max_count) const {
        std::vector<const toml::table*> out;
        const toml::node* n = node(key);
        if (n == nullptr) return out;
        const toml::array* a = n->as_array();
        if (a == nullptr)
            fail(key, "must be an array of tables ([[" + key_path(key) + "]]) (got " + describe(*n) + ")");
        if (a->size() > max_count)
            fail(key,
                 "may have at most " + std::to_string(max_count) + " entries (got " + std::to_string(a->size()) + ")");
        for (std::size_t i = 0; i < a->size(); ++i) {
            const toml::node& e = *a->get(i);
            if (!e.is_table())
                r_.fail(&e, key_path(key) + "[" + std::to_string(i) + "] must be a table (got " + describe(e) + ")");
            out.push_back(e.as_table());
        }
        return out;
    }

private:
    static std::string range_text(double lo, double hi, const char* unit) {
        std::string text;
        if (lo == -std::numeric_limits<double>::max() || lo <= -1e300) {
            text = "finite";
        } else {
            text = ">= " + sim::format_value(lo) + " and finite";
        }
        if (hi < 1e300) text = "within " + sim::format_value(lo) + " .. " + sim::format_value(hi);
        return text + ", in " + unit;
    }

    const Reader& r_;
    const toml::table& t_;
    std::string path_;
};

constexpr double kHuge = std::numeric_limits<double>::max();

// A ragdoll's bones in shades of its colour, so that limbs read apart from
// the trunk: forearms, shins and the head lighter, hands and feet darker.
Color bone_color(Color c, sim::RagdollBone bone) {
    using B = sim::RagdollBone;
    auto mix = [&](float target, float amount) {
        return Color{c.r + (target - c.r) * amount, c.g + (target - c.g) * amount,
                             c.b + (target - c.b) * amount, c.a};
    };
    switch (bone) {
        case B::head:
        case B::lower_arm_left:
        case B::lower_arm_right:
        case B::lower_leg_left:
        case B::lower_leg_right:
            return mix(1.0f, 0.3f);
        case B::hand_left:
        case B::hand_right:
        case B::foot_left:
        case B::foot_right:
            return mix(0.0f, 0.35f);
        default:
            return c;
    }
}

// A palette for particles without a colour: distinct, readable on the light sky.
Color palette(std::size_t i) {
    static const Color colors[] = {{0.90f, 0.33f, 0.12f, 1}, {0.16f, 0.42f, 0.80f, 1},
                                           {0.20f, 0.62f, 0.30f, 1}, {0.78f, 0.22f, 0.52f, 1},
                                           {0.95f, 0.70f, 0.15f, 1}, {0.35f, 0.30f, 0.70f, 1}};
    return colors[i % std::size(colors)];
}

// --- 3. Sections -------------------------------------------------------------------

struct Builder {
    const Reader& r;
    SceneDef& scene;
    std::map<std::string, std::size_t, std::less<>> by_name;

    void particle_keys(const Section& s, sim::ParticleDef& p, ParticleLook& look, std::size_t index) {
        p.velocity = s.vec3("velocity", sim::Vec3::Zero(), "m/s");
        p.mass = s.positive("mass", 1.0, kHuge, "kg");
        p.pinned = s.boolean("pinned", false);
        if (p.pinned) p.velocity.setZero();
        look.radius = s.positive("radius", 0.1, 100.0, "m");
        p.radius = look.radius;  // what you see is what collides
        look.color = s.color("color", p.pinned ? Color{0.45f, 0.45f, 0.48f, 1} : palette(index));
    }

    void add_name(const Section& s, const std::string& name, std::size_t index) {
        if (name.empty()) return;
        if (!by_name.emplace(name, index).second) s.fail("name", "must be unique: " + quote(name) + " is taken");
    }

    void particles(const Section& top) {
        for (const toml::table* t : top.tables("particles", kMaxParticles)) {
            const std::size_t i = scene.model.particles.size();
            const Section s(r, *t, "particles[" + std::to_string(i) + "]");
            s.only({"name", "position", "velocity", "mass", "pinned", "radius", "color"});
            sim::ParticleDef p;
            ParticleLook look;
            if (s.node("position") == nullptr) r.fail(t, s.key_path("position") + " is required: [x, y, z] in m");
            p.position = s.vec3("position", sim::Vec3::Zero(), "m");
            particle_keys(s, p, look, i);
            const std::string name = s.string("name", "", 64);
            add_name(s, name, i);
            scene.model.particles.push_back(p);
            scene.looks.push_back(look);
            scene.particle_names.push_back(name);
        }
        const auto groups = top.tables("groups", 10'000);
        for (std::size_t g = 0; g < groups.size(); ++g) {
            const Section s(r, *groups[g], "groups[" + std::to_string(g) + "]");
            s.only({"name", "count", "start", "spacing", "velocity", "mass", "pinned", "radius", "color"});
            const long long count = s.integer("count", 1, 1, static_cast<long long>(kMaxParticles));
            if (scene.model.particles.size() + static_cast<std::size_t>(count) > kMaxParticles) {
                s.fail("count", "makes more than " + std::to_string(kMaxParticles) + " particles in the scene");
            }
            const sim::Vec3 start = s.vec3("start", sim::Vec3::Zero(), "m");
            const sim::Vec3 spacing = s.vec3("spacing", sim::Vec3(0.5, 0, 0), "m");
            const std::string name = s.string("name", "", 64);
            sim::ParticleDef p;
            ParticleLook look;
            particle_keys(s, p, look, scene.model.particles.size());
            for (long long k = 0; k < count; ++k) {
                p.position = start + static_cast<double>(k) * spacing;
                const std::size_t i = scene.model.particles.size();
                const std::string member = name.empty() ? "" : name + "[" + std::to_string(k) + "]";
                add_name(s, member, i);
                scene.model.particles.push_back(p);
                scene.looks.push_back(look);
                scene.particle_names.push_back(member);
            }
        }
    }

    // --- Bodies from builders ---------------------------------------------------------

    sim::LinkSettings link_keys(const Section& s, double default_stiffness) {
        sim::LinkSettings l;
        l.kind = s.word("link", "springs", {"springs", "constraints"}) == "constraints"
                     ? sim::LinkSettings::Kind::constraints
                     : sim::LinkSettings::Kind::springs;
        l.stiffness = s.number("stiffness", default_stiffness, 0.0, kHuge, "N/m");
        l.damping = s.number("damping", 0.0, 0.0, kHuge, "N·s/m");
        l.compliance = s.number("compliance", 0.0, 0.0, kHuge, "m/N");
        l.tethers = s.boolean("tethers", true);
        return l;
    }

    // Names, looks and a BodyLook for the particles a builder just added.
    void add_body(const Section& s, BodyLook::Kind kind, const sim::BodyRange& range, const std::string& name,
                  Color color, bool nodes_visible, double node_radius) {
        for (std::uint32_t k = 0; k < range.count; ++k) {
            const std::size_t i = range.first + k;
            const std::string member = name.empty() ? "" : name + "[" + std::to_string(k) + "]";
            add_name(s, member, i);
            scene.particle_names.push_back(member);
            ParticleLook look;
            look.radius = std::max(node_radius, 0.005);
            look.color = scene.model.particles[i].pinned ? Color{0.45f, 0.45f, 0.48f, 1} : color;
            look.visible = nodes_visible || scene.model.particles[i].pinned;
            scene.looks.push_back(look);
        }
        BodyLook body;
        body.kind = kind;
        body.name = name;
        body.range = range;
        body.color = color;
        body.strain_colors = s.boolean("strain_colors", false);
        scene.bodies.push_back(std::move(body));
    }

    // Builders throw InputError naming their field; say where in the file.
    template <typename F>
    sim::BodyRange build_body(const Section& s, F&& f) {
        try {
            return f();
        } catch (const sim::InputError& e) {
            r.fail(&s.table(), s.path() + ": " + e.what());
        }
    }

    void bodies(const Section& top) {
        const auto ropes = top.tables("ropes", 10'000);
        for (std::size_t k = 0; k < ropes.size(); ++k) {
            const Section s(r, *ropes[k], "ropes[" + std::to_string(k) + "]");
            s.only({"name", "start", "end", "segments", "mass", "radius", "pin_start", "pin_end", "color", "link",
                    "stiffness", "damping", "compliance", "tethers", "strain_colors", "contain_explosion"});
            sim::RopeDef d;
            d.start = s.vec3("start", d.start, "m");
            d.end = s.vec3("end", d.end, "m");
            if ((d.end - d.start).norm() == 0.0) s.fail("end", "must differ from start");
            d.segments = static_cast<int>(s.integer("segments", d.segments, 1, 4096));
            d.mass = s.positive("mass", d.mass, kHuge, "kg");
            d.radius = s.positive("radius", d.radius, 100.0, "m");
            d.pin_start = s.boolean("pin_start", d.pin_start);
            d.pin_end = s.boolean("pin_end", d.pin_end);
            d.links = link_keys(s, 1000.0);
            const Color color = s.color("color", palette(scene.bodies.size()));
            const auto range = build_body(s, [&] { return sim::add_rope(scene.model, d); });
            const std::string name = s.string("name", "rope" + std::to_string(k), 64);
            add_body(s, BodyLook::Kind::rope, range, name, color, true, d.radius);
            if (s.boolean("contain_explosion", false))
                scene.watchdog.contain.push_back({name, range.first, range.count});
        }
        const auto cloths = top.tables("cloths", 1'000);
        for (std::size_t k = 0; k < cloths.size(); ++k) {
            const Section s(r, *cloths[k], "cloths[" + std::to_string(k) + "]");
            s.only({"name", "corner", "u", "v", "nx", "ny", "mass", "radius", "shear", "bend", "pins", "color", "link",
                    "stiffness", "damping", "compliance", "tethers", "strain_colors"});
            sim::ClothDef d;
            d.corner = s.vec3("corner", d.corner, "m");
            d.u = s.vec3("u", d.u, "m");
            d.v = s.vec3("v", d.v, "m");
            if (d.u.cross(d.v).norm() < 1e-12) s.fail("v", "must be non-zero and not parallel to u");
            d.nx = static_cast<int>(s.integer("nx", d.nx, 2, 1024));
            d.ny = static_cast<int>(s.integer("ny", d.ny, 2, 1024));
            d.mass = s.positive("mass", d.mass, kHuge, "kg");
            d.radius = s.number("radius", d.radius, 0.0, 100.0, "m");
            d.shear = s.number("shear", d.shear, 0.0, 1e6, "(a factor)");
            d.bend = s.number("bend", d.bend, 0.0, 1e6, "(a factor)");
            const std::string pins = s.word("pins", "corners", {"none", "corners", "edge", "all"});
            d.pins = pins == "none"   ? sim::ClothDef::Pins::none
                     : pins == "edge" ? sim::ClothDef::Pins::edge
                     : pins == "all"  ? sim::ClothDef::Pins::all
                                      : sim::ClothDef::Pins::corners;
            d.links = link_keys(s, 1000.0);
            const Color color = s.color("color", Color{0.75f, 0.2f, 0.2f, 1});
            const auto range = build_body(s, [&] { return sim::add_cloth(scene.model, d); });
            add_body(s, BodyLook::Kind::cloth, range, s.string("name", "cloth" + std::to_string(k), 64), color, false,
                     d.radius);
        }
        const auto softs = top.tables("soft_bodies", 1'000);
        for (std::size_t k = 0; k < softs.size(); ++k) {
            const Section s(r, *softs[k], "soft_bodies[" + std::to_string(k) + "]");
            s.only({"name", "corner", "size", "nx", "ny", "nz", "mass", "radius", "velocity", "color", "link",
                    "stiffness", "damping", "compliance", "tethers", "strain_colors", "yield_strain", "creep",
                    "max_strain"});
            sim::LatticeDef d;
            d.corner = s.vec3("corner", d.corner, "m");
            d.size = s.vec3("size", d.size, "m");
            for (int a = 0; a < 3; ++a) {
                if (!(d.size[a] > 0)) s.fail("size", "must have three sizes > 0, in m");
            }
            d.nx = static_cast<int>(s.integer("nx", d.nx, 2, 256));
            d.ny = static_cast<int>(s.integer("ny", d.ny, 2, 256));
            d.nz = static_cast<int>(s.integer("nz", d.nz, 2, 256));
            d.mass = s.positive("mass", d.mass, kHuge, "kg");
            d.radius = s.number("radius", d.radius, 0.0, 100.0, "m");
            d.velocity = s.vec3("velocity", d.velocity, "m/s");
            d.links = link_keys(s, 1000.0);
            d.plasticity.yield_strain = s.number("yield_strain", 0.0, 0.0, 0.99, "(a strain)");
            d.plasticity.creep = s.number("creep", d.plasticity.yield_strain > 0 ? 10.0 : 0.0, 0.0, 1e6, "1/s");
            d.plasticity.max_strain = s.number("max_strain", d.plasticity.max_strain, 0.0, 0.99, "(a strain)");
            const Color color = s.color("color", palette(scene.bodies.size()));
            const auto range = build_body(s, [&] { return sim::add_lattice(scene.model, d); });
            add_body(s, BodyLook::Kind::soft_body, range, s.string("name", "soft_body" + std::to_string(k), 64), color,
                     false, d.radius);
        }
        const auto emitters = top.tables("emitters", 100);
        for (std::size_t k = 0; k < emitters.size(); ++k) {
            const Section s(r, *emitters[k], "emitters[" + std::to_string(k) + "]");
            s.only({"name", "count", "position", "direction", "cone", "speed", "speed_jitter", "rate", "seed", "mass",
                    "radius", "color"});
            sim::Emitter e;
            const long long count = s.integer("count", 1000, 1, static_cast<long long>(kMaxParticles));
            if (scene.model.particles.size() + static_cast<std::size_t>(count) > kMaxParticles) {
                s.fail("count", "makes more than " + std::to_string(kMaxParticles) + " particles in the scene");
            }
            e.first = static_cast<std::uint32_t>(scene.model.particles.size());
            e.count = static_cast<std::uint32_t>(count);
            e.position = s.vec3("position", e.position, "m");
            const sim::Vec3 d = s.vec3("direction", e.direction, "(a direction)");
            if (d.norm() < 1e-9) s.fail("direction", "must be a non-zero direction");
            e.direction = d.normalized();
            e.cone = s.number("cone", e.cone, 0.0, 180.0, "degrees");
            e.speed = s.positive("speed", e.speed, 1e4, "m/s");
            e.speed_jitter = s.number("speed_jitter", e.speed_jitter, 0.0, 1.0, "(a fraction)");
            e.rate = s.positive("rate", e.rate, 1e7, "particles/s");
            e.seed = static_cast<std::uint64_t>(s.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
            sim::ParticleDef p;
            p.mass = s.positive("mass", 0.01, kHuge, "kg");
            p.radius = s.positive("radius", 0.02, 100.0, "m");
            p.pinned = true;  // parked until born
            p.position = sim::parked_position(e);
            ParticleLook look;
            look.radius = p.radius;
            look.color = s.color("color", Color{0.25f, 0.55f, 0.95f, 1});
            const std::string name = s.string("name", "emitter" + std::to_string(k), 64);
            for (std::uint32_t i = 0; i < e.count; ++i) {
                const std::string member = name + "[" + std::to_string(i) + "]";
                add_name(s, member, scene.model.particles.size());
                scene.particle_names.push_back(member);
                scene.model.particles.push_back(p);
                scene.looks.push_back(look);
            }
            scene.model.emitters.push_back(e);
        }
        rigid(top);
        if (scene.model.particles.empty() && scene.model.rigid.empty()) {
            r.fail(&top.table(),
                   "a scene needs at least one [[particles]], [[groups]], [[ropes]], [[cloths]], "
                   "[[soft_bodies]], [[emitters]], [[bodies]] or [[ragdolls]] entry");
        }
    }

    // Rigid bodies and joints.
    void rigid(const Section& top) {
        sim::RigidModel& m = scene.model.rigid;
        constexpr double kDeg = std::numbers::pi / 180.0;
        auto rotation = [&](const Section& s) {
            const sim::Vec3 deg = s.vec3("rotation", sim::Vec3::Zero(), "degrees", 360.0) * kDeg;
            return Eigen::Quaterniond(Eigen::AngleAxisd(deg.z(), sim::Vec3::UnitZ()) *
                                      Eigen::AngleAxisd(deg.y(), sim::Vec3::UnitY()) *
                                      Eigen::AngleAxisd(deg.x(), sim::Vec3::UnitX()));
        };
        const auto bodies = top.tables("bodies", 10'000);
        std::map<std::string, int, std::less<>> names;
        for (std::size_t k = 0; k < bodies.size(); ++k) {
            const Section s(r, *bodies[k], "bodies[" + std::to_string(k) + "]");
            s.only({"name", "shape", "size", "parts", "mass", "density", "position", "rotation", "velocity",
                    "angular_velocity", "com", "color"});
            sim::BodyDef b;
            auto shape_of = [](const Section& at) {
                const std::string shape = at.word("shape", "box", {"box", "sphere", "capsule", "cylinder"});
                return shape == "sphere"     ? sim::RigidShape::sphere
                       : shape == "capsule"  ? sim::RigidShape::capsule
                       : shape == "cylinder" ? sim::RigidShape::cylinder
                                             : sim::RigidShape::box;
            };
            auto size_of = [](const Section& at, sim::RigidShape shape, const sim::Vec3& fallback) {
                const sim::Vec3 size = at.vec3("size", fallback, "m");
                const int used = shape == sim::RigidShape::box ? 3 : shape == sim::RigidShape::sphere ? 1 : 2;
                for (int a = 0; a < used; ++a) {
                    if (!(size[a] > 0))
                        at.fail("size", "needs its first " + std::to_string(used) + " entries > 0, in m");
                }
                return size;
            };
            const auto parts = s.tables("parts", 64);
            if (!parts.empty() && (s.node("shape") != nullptr || s.node("size") != nullptr))
                s.fail("parts", "replace shape and size: give one or the other");
            for (std::size_t p = 0; p < parts.size(); ++p) {
                const Section ps(r, *parts[p], s.key_path("parts") + "[" + std::to_string(p) + "]");
                ps.only({"shape", "size", "offset", "rotation", "density"});
                sim::BodyPart part;
                part.shape = shape_of(ps);
                part.size = size_of(ps, part.shape, part.size);
                part.offset = ps.vec3("offset", part.offset, "m");
                part.orientation = rotation(ps);
                part.density = ps.positive("density", part.density, kHuge, "kg/m³");
                b.parts.push_back(part);
            }
            b.shape = shape_of(s);
            if (parts.empty()) b.size = size_of(s, b.shape, b.size);
            if (s.node("mass") != nullptr && s.node("density") != nullptr)
                s.fail("density", "and mass cannot both be given");
            b.mass = s.node("density") != nullptr ? 0.0 : s.positive("mass", 1.0, kHuge, "kg");
            b.density = s.positive("density", b.density, kHuge, "kg/m³");
            b.position = s.vec3("position", b.position, "m");
            b.orientation = rotation(s);
            b.velocity = s.vec3("velocity", b.velocity, "m/s");
            b.angular_velocity = s.vec3("angular_velocity", sim::Vec3::Zero(), "deg/s") * kDeg;
            b.com = s.vec3("com", b.com, "m");
            const std::string name = s.string("name", "body" + std::to_string(k), 64);
            if (!names.emplace(name, static_cast<int>(k)).second)
                s.fail("name", "must be unique: " + quote(name) + " is taken");
            m.bodies.push_back(b);
            scene.body_names.push_back(name);
            scene.body_colors.push_back(s.color("color", palette(k + 2)));
        }
        std::vector<const toml::node*> joint_nodes;  // where each joint of m.joints was written
        const auto ragdolls = top.tables("ragdolls", 1'000);
        for (std::size_t k = 0; k < ragdolls.size(); ++k) {
            const Section s(r, *ragdolls[k], "ragdolls[" + std::to_string(k) + "]");
            s.only({"name", "height", "mass", "position", "rotation", "velocity", "angular_velocity", "joint_friction",
                    "color"});
            sim::RagdollDef d;
            d.height = s.positive("height", d.height, 100.0, "m");
            d.mass = s.positive("mass", d.mass, kHuge, "kg");
            d.position = s.vec3("position", d.position, "m");
            d.orientation = rotation(s);
            d.velocity = s.vec3("velocity", d.velocity, "m/s");
            d.angular_velocity = s.vec3("angular_velocity", sim::Vec3::Zero(), "deg/s") * kDeg;
            d.joint_friction = s.number("joint_friction", d.joint_friction, 0.0, kHuge, "N·m");
            const std::string name = s.string("name", "ragdoll" + std::to_string(k), 64);
            const Color color = s.color("color", palette(k + 5));
            const sim::RagdollParts made = sim::ragdoll_parts(d, static_cast<int>(m.bodies.size()));
            for (std::size_t b = 0; b < made.bodies.size(); ++b) {
                const std::string bone = name + "." + std::string(sim::name(static_cast<sim::RagdollBone>(b)));
                if (!names.emplace(bone, static_cast<int>(m.bodies.size())).second)
                    s.fail("name", "must be unique: " + quote(bone) + " is taken");
                m.bodies.push_back(made.bodies[b]);
                scene.body_names.push_back(bone);
                scene.body_colors.push_back(bone_color(color, static_cast<sim::RagdollBone>(b)));
            }
            m.joints.insert(m.joints.end(), made.joints.begin(), made.joints.end());
            joint_nodes.insert(joint_nodes.end(), made.joints.size(), ragdolls[k]);
        }
        const auto joints = top.tables("joints", 10'000);
        for (std::size_t k = 0; k < joints.size(); ++k) {
            const Section s(r, *joints[k], "joints[" + std::to_string(k) + "]");
            s.only({"type", "a", "b", "anchor", "axis", "axis2", "lo", "hi", "lo2", "hi2", "lo3", "hi3",
                    "stop_stiffness", "stop_damping", "motor_velocity", "motor_max_force"});
            sim::RigidJoint j;
            const std::string type = s.word("type", "ball", {"ball", "hinge", "universal", "slider", "fixed"});
            j.joint.type = type == "hinge"       ? sim::JointType::hinge
                           : type == "universal" ? sim::JointType::universal
                           : type == "slider"    ? sim::JointType::slider
                           : type == "fixed"     ? sim::JointType::fixed
                                                 : sim::JointType::ball;
            auto body = [&](std::string_view key) {
                const std::string name = s.string(key, "");
                const auto it = names.find(name);
                if (it == names.end()) s.fail(key, "names no body (got " + quote(name) + ")");
                return it->second;
            };
            if (s.node("a") == nullptr) s.fail("a", "is required: a body name");
            j.a = body("a");
            j.b = s.node("b") != nullptr ? body("b") : -1;
            if (j.a == j.b) s.fail("b", "must be another body than a");
            j.joint.anchor = s.vec3("anchor", j.joint.anchor, "m");
            auto unit = [&](std::string_view key, const sim::Vec3& fallback) {
                const sim::Vec3 v = s.vec3(key, fallback, "(a direction)");
                if (v.norm() < 1e-9) s.fail(key, "must be a non-zero direction");
                return sim::Vec3(v.normalized());
            };
            j.joint.axis = unit("axis", j.joint.axis);
            j.joint.axis2 = unit("axis2", j.joint.axis2);
            const bool angular = j.joint.type != sim::JointType::slider;
            const double scale = angular ? kDeg : 1.0;
            auto limits = [&](const char* lo_key, const char* hi_key, double& lo, double& hi) {
                if (s.node(lo_key) == nullptr && s.node(hi_key) == nullptr) return;
                lo = s.number(lo_key, -1e300, -1e6, 1e6, angular ? "degrees" : "m") * scale;
                hi = s.number(hi_key, 1e300, -1e6, 1e6, angular ? "degrees" : "m") * scale;
                if (lo > hi) s.fail(hi_key, std::string("must be >= ") + lo_key);
            };
            limits("lo", "hi", j.joint.lo, j.joint.hi);
            limits("lo2", "hi2", j.joint.lo2, j.joint.hi2);
            limits("lo3", "hi3", j.joint.lo3, j.joint.hi3);
            j.joint.stop_stiffness = s.number("stop_stiffness", 0.0, 0.0, kHuge, angular ? "N·m/rad" : "N/m");
            j.joint.stop_damping = s.number("stop_damping", 0.0, 0.0, kHuge, angular ? "N·m·s/rad" : "N·s/m");
            j.joint.motor_velocity = s.number("motor_velocity", 0.0, -1e6, 1e6, angular ? "deg/s" : "m/s") * scale;
            j.joint.motor_max_force = s.number("motor_max_force", 0.0, 0.0, kHuge, angular ? "N·m" : "N");
            m.joints.push_back(j);
            joint_nodes.push_back(joints[k]);
        }
        if (const toml::table* t = top.subtable("rigid")) {
            const Section s(r, *t, "rigid");
            s.only({"quickstep", "iterations", "friction", "restitution", "bounce_velocity", "erp", "cfm", "ground",
                    "ground_height", "seed", "sleep", "sleep_speed", "sleep_time", "gravity", "self_collision",
                    "position_iterations", "speculative_stops"});
            sim::RigidSettings& rs = m.settings;
            rs.quickstep = s.boolean("quickstep", rs.quickstep);
            rs.iterations = static_cast<int>(s.integer("iterations", rs.iterations, 1, 10'000));
            rs.friction = s.number("friction", rs.friction, 0.0, 1e6, "(Coulomb μ)");
            rs.restitution = s.number("restitution", rs.restitution, 0.0, 1.0, "(0 .. 1)");
            rs.bounce_velocity = s.number("bounce_velocity", rs.bounce_velocity, 0.0, kHuge, "m/s");
            rs.erp = s.number("erp", rs.erp, 0.0, 1.0, "(0 .. 1)");
            rs.cfm = s.number("cfm", rs.cfm, 0.0, kHuge, "(ODE's CFM)");
            rs.gravity = s.vec3("gravity", rs.gravity, "m/s²");
            rs.ground = s.boolean("ground", rs.ground);
            rs.ground_height = s.number("ground_height", rs.ground_height, -1e5, 1e5, "m");
            rs.seed = static_cast<std::uint64_t>(s.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
            rs.sleep = s.boolean("sleep", rs.sleep);
            rs.sleep_speed = s.positive("sleep_speed", rs.sleep_speed, kHuge, "m/s");
            rs.sleep_time = s.positive("sleep_time", rs.sleep_time, kHuge, "s");
            rs.self_collision = s.boolean("self_collision", rs.self_collision);
            rs.speculative_stops = s.boolean("speculative_stops", rs.speculative_stops);
            rs.position_iterations = static_cast<int>(s.integer("position_iterations", rs.position_iterations, 0, 100));
        }
        // Jointed mass ratios above 10:1 converge slowly in the iterative solver: warn
        // (ODE's exact solver, quickstep = false, does not care).
        for (std::size_t k = 0; m.settings.quickstep && k < m.joints.size(); ++k) {
            const sim::RigidJoint& j = m.joints[k];
            if (j.b < 0) continue;
            const auto a = static_cast<std::size_t>(j.a), b = static_cast<std::size_t>(j.b);
            const double ma = sim::mass_of(m.bodies[a]), mb = sim::mass_of(m.bodies[b]);
            const double ratio = std::max(ma, mb) / std::min(ma, mb);
            if (ratio <= 10.0) continue;
            std::ostringstream w;
            w.precision(3);
            w << r.where(joint_nodes[k]) << ": " << scene.body_names[a] << " (" << ma << " kg) and "
              << scene.body_names[b] << " (" << mb << " kg) are jointed with a mass ratio of " << ratio
              << ":1, over 10:1: the iterative solver converges slowly (the joint stretches); "
                 "raise rigid.iterations, use the exact solver (rigid.quickstep = false) or even out the masses";
            scene.warnings.push_back(w.str());
        }
    }

    void constraints(const Section& top) {
        const toml::table* t = top.subtable("constraints");
        if (t == nullptr) return;
        const Section s(r, *t, "constraints");
        s.only({"iterations"});
        scene.model.constraints.iterations = static_cast<int>(s.integer("iterations", 1, 1, 1000));
    }

    void collisions(const Section& top) {
        sim::Collisions& c = scene.model.collisions;
        if (const toml::table* t = top.subtable("collisions")) {
            const Section s(r, *t, "collisions");
            s.only({"restitution", "friction", "rest_speed", "particles"});
            c.restitution = s.number("restitution", c.restitution, 0.0, 1.0, "(0 .. 1)");
            c.friction = s.number("friction", c.friction, 0.0, 100.0, "(Coulomb μ)");
            c.rest_speed = s.number("rest_speed", c.rest_speed, 0.0, kHuge, "m/s");
            c.particle_particle = s.boolean("particles", false);
        }
        const auto list = top.tables("colliders", 10'000);
        for (std::size_t k = 0; k < list.size(); ++k) {
            const Section s(r, *list[k], "colliders[" + std::to_string(k) + "]");
            const std::string shape = s.word("shape", "", {"plane", "sphere", "box", "capsule"});
            Color color = s.color("color", Color{0.6f, 0.62f, 0.66f, 1});
            color.a = s.boolean("visible", true) ? 1.0f : 0.0f;
            if (shape == "plane") {
                s.only({"shape", "normal", "offset", "color", "visible"});
                const sim::Vec3 n = s.vec3("normal", sim::Vec3::UnitY(), "(a direction)");
                if (n.norm() < 1e-9) s.fail("normal", "must be a non-zero direction");
                c.colliders.push_back(sim::PlaneCollider{n.normalized(), s.number("offset", 0.0, -1e6, 1e6, "m")});
            } else if (shape == "sphere") {
                s.only({"shape", "center", "radius", "color", "visible"});
                c.colliders.push_back(
                    sim::SphereCollider{s.vec3("center", sim::Vec3::Zero(), "m"), s.positive("radius", 1.0, 1e6, "m")});
            } else if (shape == "box") {
                s.only({"shape", "center", "half_extents", "rotation", "color", "visible"});
                sim::BoxCollider b;
                b.center = s.vec3("center", b.center, "m");
                b.half_extents = s.vec3("half_extents", b.half_extents, "m");
                for (int a = 0; a < 3; ++a) {
                    if (!(b.half_extents[a] > 0)) s.fail("half_extents", "must be three lengths > 0, in m");
                }
                const sim::Vec3 deg =
                    s.vec3("rotation", sim::Vec3::Zero(), "degrees", 360.0) * (std::numbers::pi / 180.0);
                b.rotation =
                    (Eigen::AngleAxisd(deg.z(), sim::Vec3::UnitZ()) * Eigen::AngleAxisd(deg.y(), sim::Vec3::UnitY()) *
                     Eigen::AngleAxisd(deg.x(), sim::Vec3::UnitX()))
                        .toRotationMatrix();
                c.colliders.push_back(b);
            } else {
                s.only({"shape", "a", "b", "radius", "color", "visible"});
                c.colliders.push_back(sim::CapsuleCollider{s.vec3("a", sim::Vec3::Zero(), "m"),
                                                           s.vec3("b", sim::Vec3::UnitY(), "m"),
                                                           s.positive("radius", 0.25, 1e6, "m")});
            }
            scene.collider_colors.push_back(color);
        }
    }

    // A particle named by its name or its index.
    // A particle named by its name or its index, at `where` ("forces.springs[0].a").
    std::size_t particle_at(const toml::node& n, const std::string& where) {
        if (auto name = n.value<std::string>(); name && n.is_string()) {
            if (auto it = by_name.find(*name); it != by_name.end()) return it->second;
            r.fail(&n, where + " names no particle (got " + quote(*name) + ")");
        }
        if (n.is_integer()) {
            const long long i = *n.value<long long>();
            if (i >= 0 && static_cast<std::size_t>(i) < scene.model.particles.size())
                return static_cast<std::size_t>(i);
            r.fail(&n, where + " must be a particle index within 0 .. " +
                           std::to_string(scene.model.particles.size() - 1) + " (got " + std::to_string(i) + ")");
        }
        r.fail(&n, where + " must be a particle name or index (got " + describe(n) + ")");
    }

    std::size_t particle_ref(const Section& s, std::string_view key) {
        const toml::node* n = s.node(key);
        if (n == nullptr) s.fail(key, "is required: a particle name or index");
        return particle_at(*n, s.key_path(key));
    }

    void forces(const Section& top) {
        const toml::table* t = top.subtable("forces");
        if (t == nullptr) return;
        const Section f(r, *t, "forces");
        f.only({"gravity", "drag", "quadratic_drag", "newton_gravity", "springs", "wind", "buoyancy", "shock_waves",
                "control"});
        if (const toml::table* g = f.subtable("gravity")) {
            const Section s(r, *g, "forces.gravity");
            s.only({"g"});
            scene.model.forces.push_back(sim::UniformGravity{s.vec3("g", sim::Vec3(0, -9.81, 0), "m/s²", 1e6)});
        }
        if (const toml::table* d = f.subtable("drag")) {
            const Section s(r, *d, "forces.drag");
            s.only({"c"});
            scene.model.forces.push_back(sim::LinearDrag{s.number("c", 0.1, 0.0, kHuge, "N·s/m")});
        }
        if (const toml::table* d = f.subtable("quadratic_drag")) {
            const Section s(r, *d, "forces.quadratic_drag");
            s.only({"c"});
            scene.model.forces.push_back(sim::QuadraticDrag{s.number("c", 0.01, 0.0, kHuge, "N·s²/m²")});
        }
        if (const toml::table* n = f.subtable("newton_gravity")) {
            const Section s(r, *n, "forces.newton_gravity");
            s.only({"G", "softening"});
            scene.model.forces.push_back(sim::NewtonGravity{s.positive("G", 6.674e-11, kHuge, "m³/(kg·s²)"),
                                                            s.number("softening", 0.0, 0.0, kHuge, "m")});
        }
        const auto springs = f.tables("springs", kMaxSprings);
        if (!springs.empty()) {
            sim::Springs list;
            for (std::size_t k = 0; k < springs.size(); ++k) {
                const Section s(r, *springs[k], "forces.springs[" + std::to_string(k) + "]");
                s.only({"a", "b", "rest_length", "stiffness", "damping"});
                sim::Spring spring;
                const std::size_t a = particle_ref(s, "a"), b = particle_ref(s, "b");
                if (a == b)
                    s.fail("b", "must be another particle than a (both are particle " + std::to_string(a) + ")");
                spring.i = static_cast<std::uint32_t>(a);
                spring.j = static_cast<std::uint32_t>(b);
                const double initial = (scene.model.particles[a].position - scene.model.particles[b].position).norm();
                spring.rest = s.number("rest_length", initial, 0.0, kHuge, "m");
                spring.k = s.number("stiffness", 100.0, 0.0, kHuge, "N/m");
                spring.c = s.number("damping", 0.0, 0.0, kHuge, "N·s/m");
                list.list.push_back(spring);
            }
            scene.drawn_springs.push_back(scene.model.forces.size());
            scene.model.forces.push_back(std::move(list));
        }
        more_forces(f);
    }

    // An array of particle names or indices; empty when absent.
    std::vector<std::uint32_t> particle_list(const Section& s, std::string_view key) {
        std::vector<std::uint32_t> out;
        const toml::node* n = s.node(key);
        if (n == nullptr) return out;
        const toml::array* a = n->as_array();
        if (a == nullptr) s.fail(key, "must be an array of particle names or indices (got " + describe(*n) + ")");
        for (std::size_t k = 0; k < a->size(); ++k) {
            out.push_back(
                static_cast<std::uint32_t>(particle_at(*a->get(k), s.key_path(key) + "[" + std::to_string(k) + "]")));
        }
        return out;
    }

    // Wind, buoyancy, shock waves and control forces (after gravity: buoyancy takes its g).
    void more_forces(const Section& f) {
        const sim::UniformGravity* gravity_force = find_force<sim::UniformGravity>();
        const double g = gravity_force != nullptr ? gravity_force->g.norm() : 0.0;  // m/s² (a copy: forces grow below)
        if (const toml::table* t = f.subtable("wind")) {
            const Section s(r, *t, "forces.wind");
            s.only({"velocity", "air_density", "drag_coefficient", "gust_strength", "gust_period", "seed", "bodies",
                    "particles", "radius"});
            sim::Wind w;
            w.velocity = s.vec3("velocity", w.velocity, "m/s");
            w.air_density = s.number("air_density", w.air_density, 0.0, 1e5, "kg/m³");
            w.drag_coefficient = s.number("drag_coefficient", w.drag_coefficient, 0.0, 100.0, "(C_d)");
            w.gust_strength = s.number("gust_strength", w.gust_strength, 0.0, 1e4, "m/s");
            w.gust_period = s.positive("gust_period", w.gust_period, 1e6, "s");
            w.seed = static_cast<std::uint64_t>(s.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
            w.radius = s.number("radius", w.radius, 0.0, 100.0, "m");
            w.particles = particle_list(s, "particles");
            if (const toml::node* n = s.node("bodies")) {
                const toml::array* a = n->as_array();
                if (a == nullptr) s.fail("bodies", "must be an array of cloth or soft-body names");
                for (std::size_t k = 0; k < a->size(); ++k) {
                    const auto name = a->get(k)->value<std::string>();
                    const auto body = std::find_if(scene.bodies.begin(), scene.bodies.end(), [&](const BodyLook& b) {
                        return name && b.name == *name && !b.range.surface.empty();
                    });
                    if (body == scene.bodies.end()) {
                        r.fail(a->get(k), "forces.wind.bodies[" + std::to_string(k) +
                                              "] names no cloth or soft body (got " + describe(*a->get(k)) + ")");
                    }
                    for (const auto& tri : body->range.surface) w.triangles.push_back(tri);
                }
            }
            scene.model.forces.push_back(std::move(w));
        }
        const auto floats = f.tables("buoyancy", 64);
        for (std::size_t k = 0; k < floats.size(); ++k) {
            const Section s(r, *floats[k], "forces.buoyancy[" + std::to_string(k) + "]");
            s.only({"surface_height", "fluid_density", "radius", "drag", "particles"});
            sim::Buoyancy b;
            b.surface_height = s.number("surface_height", b.surface_height, -1e5, 1e5, "m");
            b.fluid_density = s.positive("fluid_density", b.fluid_density, 1e6, "kg/m³");
            b.radius = s.positive("radius", b.radius, 100.0, "m");
            b.drag = s.number("drag", b.drag, 0.0, kHuge, "N·s/m");
            b.particles = particle_list(s, "particles");
            if (g == 0.0)
                s.fail("surface_height", "needs [forces.gravity]: buoyancy is the weight of the water displaced");
            b.gravity = g;
            scene.view.water = true;
            scene.view.water_height = b.surface_height;
            scene.model.forces.push_back(std::move(b));
        }
        const auto shocks = f.tables("shock_waves", 64);
        for (std::size_t k = 0; k < shocks.size(); ++k) {
            const Section s(r, *shocks[k], "forces.shock_waves[" + std::to_string(k) + "]");
            s.only({"center", "start_time", "speed", "thickness", "strength", "reference_distance", "max_radius"});
            sim::ShockWave w;
            w.center = s.vec3("center", w.center, "m");
            w.start_time = s.number("start_time", w.start_time, 0.0, 1e6, "s");
            w.speed = s.positive("speed", w.speed, 1e5, "m/s");
            w.thickness = s.positive("thickness", w.thickness, 1e4, "m");
            w.strength = s.number("strength", w.strength, 0.0, kHuge, "N");
            w.reference_distance = s.positive("reference_distance", w.reference_distance, 1e4, "m");
            w.max_radius = s.number("max_radius", w.max_radius, 0.0, 1e6, "m");
            scene.model.forces.push_back(w);
        }
        const auto keys = f.tables("control", 10'000);
        if (!keys.empty()) {
            sim::ControlForces c;
            for (std::size_t k = 0; k < keys.size(); ++k) {
                const Section s(r, *keys[k], "forces.control[" + std::to_string(k) + "]");
                s.only({"start", "end", "particles", "force"});
                sim::ControlKey key;
                key.start = s.number("start", 0.0, 0.0, 1e6, "s");
                key.end = s.number("end", key.start + 1.0, 0.0, 1e6, "s");
                if (!(key.end > key.start))
                    s.fail("end", "must be after start (got " + sim::format_value(key.end) + ")");
                key.particles = particle_list(s, "particles");
                if (key.particles.empty()) s.fail("particles", "is required: the particles the key pushes");
                key.force = s.vec3("force", sim::Vec3::Zero(), "N");
                c.keys.push_back(std::move(key));
            }
            scene.model.forces.push_back(std::move(c));
        }
    }

    void step(const Section& top) {
        const toml::table* t = top.subtable("step");
        if (t == nullptr) return;
        const Section s(r, *t, "step");
        s.only({"integrator", "dt", "substeps"});
        if (s.node("integrator") != nullptr) {
            const std::string name = s.string("integrator", "");
            const auto id = sim::integrator_from_name(name);
            if (!id) s.fail("integrator", "must be one of " + sim::integrator_names() + " (got " + quote(name) + ")");
            scene.step.integrator = *id;
        }
        scene.step.dt = s.positive("dt", scene.step.dt, 10.0, "s");
        scene.step.substeps = static_cast<int>(s.integer("substeps", 1, 1, kMaxSubsteps));
    }

    void watchdog(const Section& top) {
        const toml::table* t = top.subtable("watchdog");
        if (t == nullptr) return;
        const Section s(r, *t, "watchdog");
        s.only({"enabled", "max_speed", "world_half_extent", "energy_growth", "energy_floor"});
        sim::WatchdogLimits& w = scene.watchdog;
        w.enabled = s.boolean("enabled", w.enabled);
        w.max_speed = s.positive("max_speed", w.max_speed, kHuge, "m/s");
        w.world_half_extent = s.positive("world_half_extent", w.world_half_extent, kHuge, "m");
        w.energy_growth = s.number("energy_growth", w.energy_growth, 0.0, kHuge, "(a factor; 0 is off)");
        if (w.energy_growth != 0.0 && w.energy_growth < 1.0) {
            s.fail("energy_growth", "must be 0 (off) or >= 1 (got " + sim::format_value(w.energy_growth) + ")");
        }
        w.energy_floor = s.positive("energy_floor", w.energy_floor, kHuge, "J");
    }

    void camera(const Section& top) {
        CameraDef& c = scene.camera;
        c.eye = Eigen::Vector3f(0.0f, 1.5f, 6.0f);
        c.target = Eigen::Vector3f(0.0f, 1.0f, 0.0f);
        const toml::table* t = top.subtable("camera");
        if (t == nullptr) return;
        const Section s(r, *t, "camera");
        s.only({"projection", "eye", "target", "up", "fov", "height"});
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

    void view(const Section& top) {
        const toml::table* t = top.subtable("view");
        if (t == nullptr) return;
        const Section s(r, *t, "view");
        s.only({"ground", "ground_height", "trail_frames", "velocity_arrows", "force_arrows", "energy_plot", "hud"});
        View& v = scene.view;
        v.ground = s.boolean("ground", v.ground);
        v.ground_height = s.number("ground_height", v.ground_height, -1e5, 1e5, "m");
        v.trail_frames = static_cast<int>(s.integer("trail_frames", v.trail_frames, 0, 100'000));
        v.velocity_arrows = s.number("velocity_arrows", v.velocity_arrows, 0.0, 1e3, "s");
        v.force_arrows = s.number("force_arrows", v.force_arrows, 0.0, 1e9, "m/N");
        v.energy_plot = s.boolean("energy_plot", v.energy_plot);
        v.hud = s.boolean("hud", v.hud);
    }

    void timing(const Section& top) {
        scene.frames = static_cast<int>(top.integer("frames", 600, 1, kMaxFrames));
        const toml::node* n = top.node("checkpoints");
        if (n == nullptr) {
            for (int k = 0; k <= 3; ++k) scene.checkpoints.push_back(scene.frames * k / 3);
            return;
        }
        const toml::array* a = n->as_array();
        if (a == nullptr || a->empty() || a->size() > kMaxCheckpoints) {
            top.fail("checkpoints", "must be an array of 1 .. " + std::to_string(kMaxCheckpoints) +
                                        " frame numbers (got " + describe(*n) + ")");
        }
        for (std::size_t i = 0; i < a->size(); ++i) {
            const toml::node& e = *a->get(i);
            const auto f = e.value<long long>();
            if (!e.is_integer() || *f < 0 || *f > scene.frames ||
                (!scene.checkpoints.empty() && *f <= scene.checkpoints.back())) {
                r.fail(&e, "checkpoints[" + std::to_string(i) + "] must be an integer frame within 0 .. frames (" +
                               std::to_string(scene.frames) + "), ascending (got " + describe(e) + ")");
            }
            scene.checkpoints.push_back(static_cast<int>(*f));
        }
    }

    // --- 4. Ghosts: closed forms from the scene's own parameters ----------------------

    template <typename T>
    const T* find_force() const {
        for (const sim::ForceDef& f : scene.model.forces) {
            if (const T* t = std::get_if<T>(&f)) return t;
        }
        return nullptr;
    }
    bool has_drag() const {
        return find_force<sim::LinearDrag>() != nullptr || find_force<sim::QuadraticDrag>() != nullptr;
    }
    // The spring joining particles a and b, or none.
    const sim::Spring* spring_between(std::size_t a, std::size_t b) const {
        if (const sim::Springs* s = find_force<sim::Springs>()) {
            for (const sim::Spring& sp : s->list) {
                if ((sp.i == a && sp.j == b) || (sp.i == b && sp.j == a)) return &sp;
            }
        }
        return nullptr;
    }

    void ghosts(const Section& top) {
        const auto list = top.tables("ghosts", 64);
        for (std::size_t k = 0; k < list.size(); ++k) {
            const Section s(r, *list[k], "ghosts[" + std::to_string(k) + "]");
            s.only({"particle", "body", "solution", "anchor", "center"});
            Ghost g;
            if (s.node("body") != nullptr) {
                // A rigid body's centre of mass in free flight: a parabola, whatever the body spins.
                const std::string name = s.string("body", "");
                const auto it = std::find(scene.body_names.begin(), scene.body_names.end(), name);
                if (it == scene.body_names.end()) s.fail("body", "names no body (got " + quote(name) + ")");
                if (s.node("particle") != nullptr) s.fail("particle", "and body cannot both be given");
                g.body = static_cast<int>(it - scene.body_names.begin());
                g.solution = s.word("solution", "", {"ballistic"});
                const sim::BodyDef& b = scene.model.rigid.bodies[static_cast<std::size_t>(g.body)];
                const sim::Vec3 x0 = b.position, v0 = b.velocity, gv = scene.model.rigid.settings.gravity;
                g.exact = [=](double t) { return sim::analytic::ballistic(x0, v0, gv, t); };
                scene.ghosts.push_back(std::move(g));
                continue;
            }
            g.particle = particle_ref(s, "particle");
            g.solution = s.word("solution", "", {"ballistic", "oscillator", "kepler", "pendulum"});
            const sim::ParticleDef& p = scene.model.particles[g.particle];
            if (p.pinned) s.fail("particle", "is pinned: it has no trajectory to compare");
            const sim::Vec3 x0 = p.position, v0 = p.velocity;
            const sim::UniformGravity* gravity = find_force<sim::UniformGravity>();
            const sim::Springs* springs = find_force<sim::Springs>();
            const std::size_t coupled = springs != nullptr ? springs->list.size() : 0;
            auto pinned_ref = [&](std::string_view key) {
                const std::size_t a = particle_ref(s, key);
                if (!scene.model.particles[a].pinned) s.fail(key, "must name a pinned particle");
                return a;
            };
            if (g.solution == "ballistic") {
                if (gravity == nullptr || has_drag() || coupled > 0 || find_force<sim::NewtonGravity>() != nullptr) {
                    s.fail("solution", "'ballistic' needs uniform gravity and no drag, springs or Newtonian gravity");
                }
                const sim::Vec3 gv = gravity->g;
                g.exact = [=](double t) { return sim::analytic::ballistic(x0, v0, gv, t); };
            } else if (g.solution == "oscillator") {
                const std::size_t a = pinned_ref("anchor");
                const sim::Spring* sp = spring_between(g.particle, a);
                if (sp == nullptr || sp->rest != 0.0 || coupled != 1 || gravity != nullptr || has_drag()) {
                    s.fail(
                        "solution",
                        "'oscillator' needs exactly one zero-rest-length spring to the anchor, and no gravity or drag");
                }
                const sim::analytic::Oscillator o{p.mass, sp->k, sp->c};
                const sim::Vec3 anchor = scene.model.particles[a].position;
                g.exact = [=](double t) {
                    sim::analytic::PointState st = sim::analytic::oscillator(o, x0 - anchor, v0, t);
                    st.x += anchor;
                    return st;
                };
            } else if (g.solution == "kepler") {
                const std::size_t c = pinned_ref("center");
                const sim::NewtonGravity* ng = find_force<sim::NewtonGravity>();
                if (ng == nullptr || ng->softening != 0.0 || gravity != nullptr || has_drag() || coupled > 0 ||
                    scene.model.particles.size() != 2) {
                    s.fail("solution",
                           "'kepler' needs two particles, Newtonian gravity without softening, and no other force");
                }
                const double mu = ng->G * scene.model.particles[c].mass;
                const sim::Vec3 centre = scene.model.particles[c].position;
                if ((v0.squaredNorm() / 2 - mu / (x0 - centre).norm()) >= 0)
                    s.fail("particle", "is not on a bound orbit (energy >= 0)");
                g.exact = [=](double t) {
                    sim::analytic::PointState st = sim::analytic::kepler(mu, x0 - centre, v0, t);
                    st.x += centre;
                    return st;
                };
            } else {  // pendulum: small-angle closed form about a pinned anchor
                const std::size_t a = pinned_ref("anchor");
                const sim::Spring* sp = spring_between(g.particle, a);
                if (sp == nullptr || gravity == nullptr || coupled != 1 || has_drag() || !(sp->k > 0)) {
                    s.fail("solution", "'pendulum' needs gravity and one spring (the rod) to the anchor, and no drag");
                }
                const sim::Vec3 anchor = scene.model.particles[a].position;
                const double gn = gravity->g.norm();
                const sim::Vec3 down = gravity->g / gn;
                // The spring rod stretches by m g / k under the bob's weight: that is the length that swings.
                const double length = sp->rest + p.mass * gn / sp->k;
                const sim::Vec3 d = x0 - anchor;
                sim::Vec3 side = d - d.dot(down) * down;
                const double theta0 = std::atan2(side.norm(), d.dot(down));
                side = side.norm() > 0 ? sim::Vec3(side.normalized()) : sim::Vec3::UnitX();
                const double theta_dot0 = v0.dot(side) / length;
                if (std::abs(theta0) > 30.0 * std::numbers::pi / 180.0) {
                    s.fail("particle",
                           "starts more than 30 degrees from the vertical: the small-angle closed form does not hold");
                }
                g.exact = [=](double t) {
                    const auto ang = sim::analytic::small_angle_pendulum(length, gn, theta0, theta_dot0, t);
                    const sim::Vec3 radial = std::sin(ang.theta) * side + std::cos(ang.theta) * down;
                    const sim::Vec3 tangent = std::cos(ang.theta) * side - std::sin(ang.theta) * down;
                    return sim::analytic::PointState{anchor + length * radial, length * ang.omega * tangent};
                };
            }
            scene.ghosts.push_back(std::move(g));
        }
    }
};

// --- 5. Overrides ---------------------------------------------------------------------

// Applies "a.b[2].c = value" to the parsed file; the new node is marked so
// that errors about it say "--set KEY=VALUE".
void apply_override(toml::table& root, const Override& o, Reader& reader) {
    const std::string text = o.key + "=" + o.value;
    auto fail = [&](const std::string& why) -> void { throw SceneError("--set " + text + ": " + why); };
    toml::table value_doc;
    try {
        value_doc = toml::parse("v = " + o.value);
    } catch (const toml::parse_error& e) {
        fail("the value is not a TOML value (" + std::string(e.description()) + "); strings need quotes: \"rk4\"");
    }
    toml::table* table = &root;
    std::string so_far;
    std::stringstream path(o.key);
    std::string segment;
    std::vector<std::string> segments;
    while (std::getline(path, segment, '.')) segments.push_back(segment);
    for (std::size_t s = 0; s < segments.size(); ++s) {
        std::string name = segments[s];
        std::optional<std::size_t> index;
        if (const auto open = name.find('['); open != std::string::npos) {
            char* end = nullptr;
            const unsigned long i = std::strtoul(name.c_str() + open + 1, &end, 10);
            if (end == name.c_str() + open + 1 || *end != ']' || end[1] != '\0')
                fail("malformed index in " + quote(name));
            index = i;
            name = name.substr(0, open);
        }
        if (name.empty()) fail("empty key segment");
        const bool last = s + 1 == segments.size();
        so_far += (so_far.empty() ? "" : ".") + name;
        if (last && !index) {
            table->insert_or_assign(name, std::move(*value_doc.get("v")));
            reader.mark_override(table->get(name), text);
            return;
        }
        toml::node* next = table->get(name);
        if (index) {
            toml::array* array = next != nullptr ? next->as_array() : nullptr;
            if (array == nullptr || *index >= array->size()) {
                fail(quote(so_far) + " has " + std::to_string(array != nullptr ? array->size() : 0) + " entries");
            }
            if (last) {
                array->replace(array->begin() + static_cast<std::ptrdiff_t>(*index), std::move(*value_doc.get("v")));
                reader.mark_override(array->get(*index), text);
                return;
            }
            next = array->get(*index);
            so_far += "[" + std::to_string(*index) + "]";
        } else if (next == nullptr) {
            table->insert(name, toml::table{});
            next = table->get(name);
        }
        if (!next->is_table()) fail(quote(so_far) + " is not a table");
        table = next->as_table();
    }
}

// --- 6. Entry points ---------------------------------------------------------------------

SceneDef build(const toml::table& root, Reader& reader, const std::string& name) {
    SceneDef scene;
    scene.name = name;
    const Section top(reader, root, "");
    if (root.empty()) reader.fail(nullptr, "the file is empty: a scene needs at least description and [[particles]]");
    top.only({"description", "frames",    "checkpoints", "step",     "particles", "groups", "ropes",  "cloths",
              "soft_bodies", "emitters",  "bodies",      "ragdolls", "joints",    "rigid",  "forces", "constraints",
              "collisions",  "colliders", "watchdog",    "camera",   "view",      "ghosts"});
    if (top.node("description") == nullptr)
        reader.fail(&root, "description is required: one sentence saying what the scene shows");
    scene.description = top.string("description", "", 300);
    Builder b{reader, scene, {}};
    b.timing(top);
    b.step(top);
    b.particles(top);
    b.bodies(top);
    b.forces(top);
    b.constraints(top);
    b.collisions(top);
    b.watchdog(top);
    b.camera(top);
    b.view(top);
    b.ghosts(top);
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
    for (const Override& o : overrides) apply_override(root, o, reader);
    // A run shortened with --set frames=N (--frames N) shows the checkpoints it
    // reaches, and at least its last frame; the file's own checkpoints stay checked.
    const bool shortened =
        std::any_of(overrides.begin(), overrides.end(), [](const Override& o) { return o.key == "frames"; });
    const auto frames = root["frames"].value<long long>();
    if (toml::array* checkpoints = root["checkpoints"].as_array(); shortened && frames && checkpoints) {
        for (std::size_t i = checkpoints->size(); i-- > 0;) {
            const auto f = (*checkpoints)[i].value<long long>();
            if (f && *f > *frames) checkpoints->erase(checkpoints->begin() + static_cast<std::ptrdiff_t>(i));
        }
        if (checkpoints->empty()) checkpoints->push_back(*frames);
    }
    return build(root, reader, name);
}

}  // namespace

std::vector<std::string> SceneDef::systems() const {
    std::vector<std::string> out;
    if (!model.particles.empty()) out.push_back("particles");
    bool springs = false, plastic = false;
    for (const sim::ForceDef& f : model.forces) {
        if (const auto* s = std::get_if<sim::Springs>(&f)) {
            springs = true;
            plastic = plastic || s->plasticity.enabled();
        }
    }
    if (springs) out.push_back("springs");
    if (!model.constraints.empty()) out.push_back("constraints");
    // Particles collide with the colliders, each other and the rigid bodies
    // (bodies meet the colliders inside "rigid").
    if (!model.particles.empty() && (!model.collisions.empty() || !model.rigid.empty())) out.push_back("collisions");
    if (plastic) out.push_back("plasticity");
    if (!model.emitters.empty()) out.push_back("emitters");
    if (!model.rigid.empty()) out.push_back("rigid");
    if (watchdog.enabled) out.push_back("watchdog");
    return out;
}

Override parse_override(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
        throw SceneError("--set " + quote(text) + ": expected KEY=VALUE, e.g. step.dt=0.01");
    }
    return Override{text.substr(0, eq), text.substr(eq + 1)};
}

SceneDef parse_scene(std::string_view text, const std::string& display_name, const std::vector<Override>& overrides) {
    return parse_with(text, display_name, std::filesystem::path(display_name).stem().string(), overrides);
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
    SceneDef scene = parse_with(text, file.string(), file.stem().string(), overrides);
    scene.file = file;
    return scene;
}

std::filesystem::path scenes_dir() {
    const char* env = std::getenv("PLAUSIBLE_SCENES_DIR");
    return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                          : std::filesystem::path(PLAUSIBLE_SOURCE_DIR) / "scenes";
}

std::vector<std::string> catalog() {
    std::vector<std::string> names;
    std::ifstream in(scenes_dir() / "catalog.txt");
    if (!in) throw SceneError((scenes_dir() / "catalog.txt").string() + ": the scene catalogue cannot be read");
    std::string line;
    while (std::getline(in, line)) {
        line = line.substr(0, line.find('#'));
        line.erase(0, line.find_first_not_of(" \t"));
        line.erase(line.find_last_not_of(" \t\r") + 1);
        if (!line.empty()) names.push_back(line);
    }
    return names;
}

std::filesystem::path resolve_scene(const std::string& name_or_path) {
    const auto names = catalog();
    if (std::find(names.begin(), names.end(), name_or_path) != names.end()) {
        return scenes_dir() / (name_or_path + ".toml");
    }
    if (name_or_path.ends_with(".toml")) {
        if (!std::filesystem::exists(name_or_path)) throw SceneError(name_or_path + ": no such scene file");
        return name_or_path;
    }
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw SceneError("unknown scene " + quote(name_or_path) + " (scenes: " + list + "; or the path of a .toml file)");
}

namespace {

// Numeric leaves under `node`, depth first in file order, as --set keys.
void collect_parameters(const toml::node& node, const std::string& key, std::vector<Parameter>& out) {
    if (const toml::table* t = node.as_table()) {
        for (const auto& [k, v] : *t)
            collect_parameters(v, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), out);
    } else if (const toml::array* a = node.as_array()) {
        // Arrays of tables ([[forces.springs]]) are walked; arrays of numbers are vectors, not sliders.
        for (std::size_t i = 0; i < a->size(); ++i) {
            if ((*a)[i].is_table()) collect_parameters((*a)[i], key + "[" + std::to_string(i) + "]", out);
        }
    } else if (const auto* f = node.as_floating_point()) {
        out.push_back({key, f->get(), false});
    } else if (const auto* n = node.as_integer()) {
        out.push_back({key, static_cast<double>(n->get()), true});
    }
}

}  // namespace

std::vector<Parameter> scene_parameters(const SceneDef& scene, const std::vector<Override>& overrides) {
    toml::table root;
    try {
        root = toml::parse_file(scene.file.string());
    } catch (const toml::parse_error&) {
        return {};  // the scene loaded from this file once; a file edited since is simply not offered
    }
    std::vector<Parameter> all, out;
    collect_parameters(root, "", all);
    // Pictures, timing and the watchdog are not physics parameters; step settings have their own controls.
    for (const Parameter& p : all) {
        const std::string head = p.key.substr(0, p.key.find_first_of(".["));
        if (head == "camera" || head == "view" || head == "step" || head == "watchdog" || head == "frames" ||
            head == "checkpoints" || p.key.find("color") != std::string::npos ||
            p.key.find("seed") != std::string::npos) {
            continue;
        }
        out.push_back(p);
    }
    // The values this run uses: the last --set of a key wins, as in the loader.
    for (const Override& o : overrides) {
        for (Parameter& p : out) {
            if (p.key != o.key) continue;
            char* end = nullptr;
            const double v = std::strtod(o.value.c_str(), &end);
            if (end != o.value.c_str() && *end == '\0') p.value = v;
        }
    }
    return out;
}

}  // namespace scenes
