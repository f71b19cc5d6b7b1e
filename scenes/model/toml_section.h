// Typed reads of a TOML scene file, each failure a SceneError that names
// file:line:column, the key, what was expected and what was found, e.g.
//   scenes/rope.toml:12:5: forces.springs[0].stiffness must be >= 0 and finite, in N/m (got -3)
// Its own file because every section reader uses it and none of it knows
// what a scene is: Reader says where a node is, Section reads one table.
#pragma once

#include "scenes/model/scene.h"

#include <toml++/toml.h>

#include <Eigen/Geometry>

#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace scenes::loader {

// The most parts a dotted key or table header may have, in a file or a --set
// key: toml++ recurses once a part, and a scene needs a handful.
constexpr int kMaxKeyParts = 64;

// "No upper bound" for number() and positive().
constexpr double kHuge = std::numeric_limits<double>::max();

// A string as messages show it: quoted, control characters as '?', at most 60 characters.
std::string quote(std::string_view s);
// What a node is, for "(got ...)".
std::string describe(const toml::node& node);

// Where a node is: file:line:column, or the --set that made it.
class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}

    // Nodes made by --set have no place in the file: they are named by the override.
    void mark_override(const toml::node* node, std::string text) { overrides_[node] = std::move(text); }

    std::string where(const toml::node* node) const;
    [[noreturn]] void fail(const toml::node* node, const std::string& message) const;
    const std::string& file() const { return file_; }

private:
    std::string file_;
    std::map<const toml::node*, std::string> overrides_;
};

// A table of the file with its dotted path ("forces.springs[0]"), read key by key.
class Section {
public:
    Section(const Reader& reader, const toml::table& table, std::string path)
        : r_(reader), t_(table), path_(std::move(path)) {}

    const Reader& reader() const { return r_; }
    const toml::table& table() const { return t_; }
    const std::string& path() const { return path_; }
    std::string key_path(std::string_view key) const {
        return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
    }
    const toml::node* node(std::string_view key) const { return t_.get(key); }
    [[noreturn]] void fail(std::string_view key, const std::string& message) const;

    // Every key must be one of `allowed` (a table of scene_keys.h); the error suggests the nearest.
    void only(std::span<const std::string_view> allowed) const;

    // A finite number within [lo, hi] (an integer literal is fine).
    double number(std::string_view key, double fallback, double lo, double hi, const char* unit) const;
    // Strictly positive, at most hi.
    double positive(std::string_view key, double fallback, double hi, const char* unit) const;
    long long integer(std::string_view key, long long fallback, long long lo, long long hi) const;
    // A seed: any integer from 0 up (the default is 1).
    std::uint64_t seed(std::string_view key) const;
    bool boolean(std::string_view key, bool fallback) const;
    std::string string(std::string_view key, const std::string& fallback, std::size_t max_length = 200) const;
    // One of a fixed set of words.
    std::string word(std::string_view key, const std::string& fallback,
                     std::initializer_list<std::string_view> words) const;
    // [x, y, z] of finite numbers, each within +-limit.
    sim::Vec3 vec3(std::string_view key, const sim::Vec3& fallback, const char* unit, double limit = 1e9) const;
    // [x, y, z] in m, each > 0 (extents, sizes); `refusal` is the message when one is not.
    sim::Vec3 lengths(std::string_view key, const sim::Vec3& fallback, const char* refusal) const;
    // A non-zero [x, y, z], normalized.
    sim::Vec3 direction(std::string_view key, const sim::Vec3& fallback) const;
    // `rotation` = [x, y, z] in degrees, turned about x, then y, then z (each within +-360).
    Eigen::Quaterniond rotation() const;
    Color color(std::string_view key, const Color& fallback) const;
    // A sub-table, or none.
    const toml::table* subtable(std::string_view key) const;
    // An array of tables ([[key]]), or none.
    std::vector<const toml::table*> tables(std::string_view key, std::size_t max_count) const;
    // The entries of [[key]], each as a Section named "path.key[i]".
    std::vector<Section> entries(std::string_view key, std::size_t max_count) const;

private:
    const Reader& r_;
    const toml::table& t_;
    std::string path_;
};

}  // namespace scenes::loader
