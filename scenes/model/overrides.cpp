// --set overrides on the parsed file (see overrides.h) and parse_override.
#include "scenes/model/overrides.h"

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <sstream>

namespace scenes {
namespace loader {
namespace {

// Marks a node made by --set and everything in it (an array's elements: their
// own places are in "v = VALUE", not in the file).
void mark(Reader& reader, const toml::node* node, const std::string& text) {
    reader.mark_override(node, text);
    if (const toml::array* a = node->as_array()) {
        for (const toml::node& e : *a) mark(reader, &e, text);
    } else if (const toml::table* t = node->as_table()) {
        for (auto&& [k, v] : *t) mark(reader, &v, text);
    }
}

// Applies "a.b[2].c = value" to the parsed file; the new node is marked so
// that errors about it say "--set KEY=VALUE".
void apply_override(toml::table& root, const Override& o, Reader& reader) {
    const std::string text = o.key + "=" + o.value;
    auto fail = [&](const std::string& why) -> void { throw SceneError("--set " + text + ": " + why); };
    // One value, on one line: "2\nstep.dt = 0.5" would set a second key unseen.
    if (o.value.find_first_of("\r\n") != std::string::npos) fail("the value spans more than one line");
    toml::table value_doc;
    try {
        value_doc = toml::parse("v = " + o.value);
    } catch (const toml::parse_error& e) {
        fail("the value is not a TOML value (" + std::string(e.description()) + "); strings need quotes: \"rk4\"");
    }
    if (value_doc.size() != 1) fail("the value is more than one TOML value");
    toml::table* table = &root;
    std::string so_far;
    std::stringstream path(o.key);
    std::string segment;
    std::vector<std::string> segments;
    while (std::getline(path, segment, '.')) segments.push_back(segment);
    if (segments.size() > static_cast<std::size_t>(kMaxKeyParts))
        fail("a key of more than " + std::to_string(kMaxKeyParts) + " parts");
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
            mark(reader, table->get(name), text);
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
                mark(reader, array->get(*index), text);
                return;
            }
            next = array->get(*index);
            // Appended piece by piece: GCC 12 at -O3 warns (-Wrestrict, a false
            // positive) on "[" + std::to_string(i) here.
            so_far.append("[").append(std::to_string(*index)).append("]");
        } else if (next == nullptr) {
            table->insert(name, toml::table{});
            next = table->get(name);
            reader.mark_override(next, text);  // a table made by --set: its errors name --set too
        }
        if (!next->is_table()) fail(quote(so_far) + " is not a table");
        table = next->as_table();
    }
}

// A run shortened with --set frames=N (--frames N) shows the checkpoints it
// reaches, and at least its last frame; the file's own checkpoints stay checked.
void trim_checkpoints(toml::table& root, const std::vector<Override>& overrides) {
    const bool shortened =
        std::any_of(overrides.begin(), overrides.end(), [](const Override& o) { return o.key == "frames"; });
    // Integers only (as_integer, not value<long long>: toml++ turns a float
    // such as frames = 1e308 into an integer by a cast, undefined out of
    // range; the fuzzer found it). A float is refused by the reader later.
    const auto* frames = root["frames"].as_integer();
    if (toml::array* checkpoints = root["checkpoints"].as_array(); shortened && frames && checkpoints) {
        for (std::size_t i = checkpoints->size(); i-- > 0;) {
            const auto* f = (*checkpoints)[i].as_integer();
            if (f && f->get() > frames->get())
                checkpoints->erase(checkpoints->begin() + static_cast<std::ptrdiff_t>(i));
        }
        if (checkpoints->empty()) checkpoints->push_back(frames->get());
    }
}

}  // namespace

void apply_overrides(toml::table& root, const std::vector<Override>& overrides, Reader& reader) {
    for (const Override& o : overrides) apply_override(root, o, reader);
    trim_checkpoints(root, overrides);
}

}  // namespace loader

Override parse_override(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
        throw SceneError("--set " + loader::quote(text) + ": expected KEY=VALUE, e.g. step.dt=0.01");
    }
    return Override{text.substr(0, eq), text.substr(eq + 1)};
}

}  // namespace scenes
