// Scene files: TOML read with toml++, validated strictly, turned into a
// SceneDef. Every error names file:line:column, the key, what was expected and
// what was found, e.g.
//   scenes/rope.toml:12:5: forces.springs[0].stiffness must be >= 0 and finite, in N/m (got -3)
//
// The format, every table and key with its unit, default and range: docs/scene-format.md.
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
    SceneBuilder b{reader, scene, {}, {}, {}, {}};
    read_timing(b, top);
    read_step(b, top);
    read_particles(b, top);
    read_ropes(b, top);
    read_cloths(b, top);
    read_soft_bodies(b, top);
    read_emitters(b, top);
    read_rigid_bodies(b, top);
    read_ragdolls(b, top);
    read_chains(b, top);
    read_joints(b, top);
    read_rigid_settings(b, top);
    refuse_rigid_step_too_small(b, top);
    warn_jointed_mass_ratios(b);
    require_bodies(b, top);
    read_forces(b, top);
    read_constraints(b, top);
    read_collisions(b, top);
    read_watchdog(b, top);
    read_camera(b, top);
    read_view(b, top);
    read_ghosts(b, top);
    refuse_work_too_large(b, top);
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

// toml++ limits how deep values nest, not how many parts a dotted key or a
// table header has, and recurses once a part: 35,000 parts overflowed the
// stack. Refused before it parses: outside strings and comments, no run of
// text between = , [ ] { } or a line's end holds more than kMaxKeyParts - 1 dots.
void refuse_deep_keys(std::string_view text, const std::string& display) {
    int line = 1, dots = 0;
    char quote = 0;       // the open string's delimiter, or 0
    bool triple = false;  // a multi-line string
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (quote != 0) {
            if (c == '\\' && quote == '"') {
                ++i;  // an escaped character, whatever it is
                if (i < text.size() && text[i] == '\n') ++line;
            } else if (c == quote && (!triple || text.substr(i, 3) == std::string(3, quote))) {
                i += triple ? 2 : 0;
                quote = 0;
            } else if (c == '\n' && !triple) {
                quote = 0;  // an unterminated string: toml++ says so
            }
            continue;
        }
        if (c == '"' || c == '\'') {
            quote = c;
            triple = text.substr(i, 3) == std::string(3, c);
            i += triple ? 2 : 0;
        } else if (c == '#') {
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (c == '.') {
            if (++dots >= kMaxKeyParts) {
                throw SceneError(display + ":" + std::to_string(line) + ": a dotted key or table header of more than " +
                                 std::to_string(kMaxKeyParts) + " parts");
            }
        } else if (std::string_view("=,[]{}\n").find(c) != std::string_view::npos) {
            dots = 0;
        }
    }
}

SceneDef parse_with(std::string_view text, const std::string& display, const std::string& name,
                    const std::vector<Override>& overrides) {
    Reader reader(display);
    toml::table root;
    refuse_deep_keys(text, display);
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
    SceneDef scene =
        loader::parse_with(text, display_name, std::filesystem::path(display_name).stem().string(), overrides);
    scene.text = text;
    return scene;
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
    scene.text = std::move(text);
    scene.overrides = overrides;
    return scene;
}

}  // namespace scenes
