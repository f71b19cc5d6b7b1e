// Typed reads of a TOML scene file and their messages (see toml_section.h).
#include "scenes/model/toml_section.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace scenes::loader {
namespace {

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

// "within lo .. hi, in unit", ">= lo and finite, in unit" or "finite, in unit".
std::string range_text(double lo, double hi, const char* unit) {
    std::string text;
    if (lo == -std::numeric_limits<double>::max() || lo <= -1e300) {
        text = "finite";
    } else {
        text = ">= " + sim::format_value(lo) + " and finite";
    }
    if (hi < 1e300) text = "within " + sim::format_value(lo) + " .. " + sim::format_value(hi);
    return text + ", in " + unit;
}

}  // namespace

// --- Locations and messages ---------------------------------------------------------

std::string quote(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 0x20) ? '?' : c;
    if (s.size() > 60) out += "...";
    return out + "'";
}

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

std::string Reader::where(const toml::node* node) const {
    if (node != nullptr) {
        if (auto it = overrides_.find(node); it != overrides_.end()) return "--set " + it->second;
        const auto& begin = node->source().begin;
        if (begin.line > 0) return file_ + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column);
    }
    return file_ + ":1:1";  // about the whole file
}

void Reader::fail(const toml::node* node, const std::string& message) const {
    throw SceneError(where(node) + ": " + message);
}

void Section::fail(std::string_view key, const std::string& message) const {
    const toml::node* n = node(key);
    r_.fail(n != nullptr ? n : static_cast<const toml::node*>(&t_), key_path(key) + " " + message);
}

void Section::only(std::span<const std::string_view> allowed) const {
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

// --- Numbers, words and vectors ---------------------------------------------------------

double Section::number(std::string_view key, double fallback, double lo, double hi, const char* unit) const {
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

double Section::positive(std::string_view key, double fallback, double hi, const char* unit) const {
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

long long Section::integer(std::string_view key, long long fallback, long long lo, long long hi) const {
    const toml::node* n = node(key);
    if (n == nullptr) return fallback;
    if (!n->is_integer()) {
        fail(key, "must be an integer within " + std::to_string(lo) + " .. " + std::to_string(hi) + " (got " +
                      describe(*n) + ")");
    }
    const long long v = *n->value<long long>();
    if (v < lo || v > hi) {
        fail(key,
             "must be within " + std::to_string(lo) + " .. " + std::to_string(hi) + " (got " + std::to_string(v) + ")");
    }
    return v;
}

std::uint64_t Section::seed(std::string_view key) const {
    return static_cast<std::uint64_t>(integer(key, 1, 0, std::numeric_limits<long long>::max()));
}

bool Section::boolean(std::string_view key, bool fallback) const {
    const toml::node* n = node(key);
    if (n == nullptr) return fallback;
    if (!n->is_boolean()) fail(key, "must be true or false (got " + describe(*n) + ")");
    return *n->value<bool>();
}

std::string Section::string(std::string_view key, const std::string& fallback, std::size_t max_length) const {
    const toml::node* n = node(key);
    if (n == nullptr) return fallback;
    if (!n->is_string()) fail(key, "must be a string (got " + describe(*n) + ")");
    std::string s = *n->value<std::string>();
    if (s.size() > max_length)
        fail(key,
             "must be at most " + std::to_string(max_length) + " bytes long (got " + std::to_string(s.size()) + ")");
    return s;
}

std::string Section::word(std::string_view key, const std::string& fallback,
                          std::initializer_list<std::string_view> words) const {
    const std::string s = string(key, fallback);
    std::string list;
    for (std::string_view w : words) {
        if (w == s) return s;
        list += (list.empty() ? "" : ", ") + std::string(w);
    }
    fail(key, "must be one of " + list + " (got " + quote(s) + ")");
}

sim::Vec3 Section::vec3(std::string_view key, const sim::Vec3& fallback, const char* unit, double limit) const {
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

sim::Vec3 Section::lengths(std::string_view key, const sim::Vec3& fallback, const char* refusal) const {
    const sim::Vec3 v = vec3(key, fallback, "m");
    for (int a = 0; a < 3; ++a) {
        if (!(v[a] > 0)) fail(key, refusal);
    }
    return v;
}

sim::Vec3 Section::direction(std::string_view key, const sim::Vec3& fallback) const {
    const sim::Vec3 v = vec3(key, fallback, "(a direction)");
    if (v.norm() < 1e-9) fail(key, "must be a non-zero direction");
    return v.normalized();
}

Eigen::Quaterniond Section::rotation() const {
    const sim::Vec3 deg = vec3("rotation", sim::Vec3::Zero(), "degrees", 360.0) * (std::numbers::pi / 180.0);
    return Eigen::Quaterniond(Eigen::AngleAxisd(deg.z(), sim::Vec3::UnitZ()) *
                              Eigen::AngleAxisd(deg.y(), sim::Vec3::UnitY()) *
                              Eigen::AngleAxisd(deg.x(), sim::Vec3::UnitX()));
}

Color Section::color(std::string_view key, const Color& fallback) const {
    const toml::node* n = node(key);
    if (n == nullptr) return fallback;
    const std::string expected = "must be \"#rrggbb\" or [r, g, b] with each in 0 .. 1";
    if (auto s = n->value<std::string>()) {
        unsigned rgb = 0;
        char end = 0;
        if (s->size() != 7 || (*s)[0] != '#' || std::sscanf(s->c_str() + 1, "%6x%c", &rgb, &end) != 1) {
            fail(key, expected + " (got " + quote(*s) + ")");
        }
        return Color{static_cast<float>((rgb >> 16) & 0xFF) / 255.0f, static_cast<float>((rgb >> 8) & 0xFF) / 255.0f,
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

// --- Sub-tables ------------------------------------------------------------------------

const toml::table* Section::subtable(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return nullptr;
    if (!n->is_table()) fail(key, "must be a table (got " + describe(*n) + ")");
    return n->as_table();
}

std::vector<const toml::table*> Section::tables(std::string_view key, std::size_t max_count) const {
    std::vector<const toml::table*> out;
    const toml::node* n = node(key);
    if (n == nullptr) return out;
    const toml::array* a = n->as_array();
    if (a == nullptr) fail(key, "must be an array of tables ([[" + key_path(key) + "]]) (got " + describe(*n) + ")");
    if (a->size() > max_count)
        fail(key, "may have at most " + std::to_string(max_count) + " entries (got " + std::to_string(a->size()) + ")");
    for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::node& e = *a->get(i);
        if (!e.is_table())
            r_.fail(&e, key_path(key) + "[" + std::to_string(i) + "] must be a table (got " + describe(e) + ")");
        out.push_back(e.as_table());
    }
    return out;
}

std::vector<Section> Section::entries(std::string_view key, std::size_t max_count) const {
    std::vector<Section> out;
    const auto list = tables(key, max_count);
    for (std::size_t i = 0; i < list.size(); ++i)
        out.emplace_back(r_, *list[i], key_path(key) + "[" + std::to_string(i) + "]");
    return out;
}

}  // namespace scenes::loader
