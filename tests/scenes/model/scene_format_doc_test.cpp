// docs/scene-format.md, the scene format's reference, against the loader: every
// key the loader accepts (scene_keys(), from the tables its section readers
// check) is documented, and every documented key is accepted. How the page
// marks its sections and keys is written at its end.
#include "scenes/model/scene_keys.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace scenes {
namespace {

struct DocumentedKey {
    std::string section;  // dotted, "" for the top level
    std::string key;
    int line = 0;
    std::string path() const { return section.empty() ? key : section + "." + key; }
};

// The cells of a Markdown table row "| a | b |", trimmed (an escaped \| stays in
// its cell); none when the line is not a row.
std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    if (!line.starts_with("|")) return out;
    auto trimmed = [](const std::string& c) {
        const auto first = c.find_first_not_of(' ');
        return first == std::string::npos ? std::string() : c.substr(first, c.find_last_not_of(' ') - first + 1);
    };
    std::string cell;
    for (std::size_t i = 1; i < line.size(); ++i) {
        if (line[i] == '|' && line[i - 1] != '\\') {
            out.push_back(trimmed(cell));
            cell.clear();
        } else {
            cell += line[i];
        }
    }
    return out;
}

// What the page documents: the sections its headings name, and the rows of
// its tables headed "key", each under the section of the heading above it.
struct Page {
    std::vector<DocumentedKey> sections;  // key empty
    std::vector<DocumentedKey> keys;
};

Page read_page() {
    const std::filesystem::path file = std::filesystem::path(PLAUSIBLE_SOURCE_DIR) / "docs" / "scene-format.md";
    std::ifstream in(file);
    EXPECT_TRUE(in) << file << " cannot be read";
    const std::regex section_name(R"(`\[\[?([A-Za-z0-9_.]+)\]\]?`)");
    const std::regex key_cell(R"(^`([A-Za-z0-9_]+)`$)");
    Page page;
    std::string line, section;
    bool in_key_table = false, in_code = false;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.starts_with("```")) in_code = !in_code;
        if (in_code) continue;
        if (line.starts_with("#")) {
            std::smatch m;
            section = std::regex_search(line, m, section_name) ? m[1].str() : "";
            if (!section.empty()) page.sections.push_back({section, "", number});
            continue;
        }
        const auto row = cells(line);
        if (row.empty()) {
            in_key_table = false;
            continue;
        }
        if (row[0] == "key") {
            in_key_table = true;
            continue;
        }
        if (!in_key_table || row[0].starts_with("---")) continue;
        std::smatch m;
        EXPECT_TRUE(std::regex_match(row[0], m, key_cell))
            << "docs/scene-format.md:" << number << ": a key table's first cell must be one key in backticks (got "
            << row[0] << ")";
        page.keys.push_back({section, m[1].str(), number});
    }
    return page;
}

bool is_section(const std::string& path) {
    const auto& all = keys::sections();
    return std::any_of(all.begin(), all.end(), [&](const keys::SectionKeys& s) { return s.path == path; });
}

std::string section_text(const std::string& section) { return section.empty() ? "the top level" : "[" + section + "]"; }

TEST(SceneFormatDoc, DocumentsEveryKeyTheLoaderAccepts) {
    const Page page = read_page();
    ASSERT_FALSE(page.keys.empty()) << "docs/scene-format.md documents no key";
    std::set<std::string> documented;
    for (const DocumentedKey& k : page.keys) documented.insert(k.path());
    for (const std::string& key : scene_keys()) {
        const auto dot = key.rfind('.');
        const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
        EXPECT_TRUE(documented.count(key))
            << "docs/scene-format.md lacks the key '" << key.substr(dot == std::string::npos ? 0 : dot + 1) << "' of "
            << section_text(section) << ": add a row to that section's key table";
    }
}

TEST(SceneFormatDoc, DocumentsEverySectionTheLoaderReads) {
    const Page page = read_page();
    for (const keys::SectionKeys& s : keys::sections()) {
        if (s.path.empty()) continue;
        EXPECT_TRUE(std::any_of(page.sections.begin(), page.sections.end(),
                                [&](const DocumentedKey& d) { return d.section == s.path; }))
            << "docs/scene-format.md has no heading for the section [" << s.path << "]";
    }
    for (const DocumentedKey& d : page.sections) {
        EXPECT_TRUE(is_section(d.section)) << "docs/scene-format.md:" << d.line << " documents the section ["
                                           << d.section << "], which the loader does not read";
    }
}

// A documented key is refused when the loader lists neither it nor a section
// of that name (a row may stand for a sub-table: [[bodies]] parts).
TEST(SceneFormatDoc, DocumentsNoKeyTheLoaderRefuses) {
    const auto accepted = scene_keys();
    for (const DocumentedKey& k : read_page().keys) {
        EXPECT_TRUE(std::find(accepted.begin(), accepted.end(), k.path()) != accepted.end() || is_section(k.path()))
            << "docs/scene-format.md:" << k.line << " documents the key '" << k.key << "' of "
            << section_text(k.section) << ", which the loader refuses (not in scenes/model/scene_keys.h)";
    }
}

TEST(SceneFormatDoc, KeysAreDottedPathsWithoutSections) {
    const auto keys = scene_keys();
    for (const char* key : {"description", "step.dt", "particles.mass", "forces.springs.stiffness",
                            "forces.quadratic_drag.c", "colliders.half_extents", "bodies.parts.shape", "ghosts.anchor"})
        EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
    // A key that is a section is listed by its own keys.
    for (const char* section : {"step", "forces", "forces.springs", "bodies.parts"})
        EXPECT_EQ(std::find(keys.begin(), keys.end(), section), keys.end()) << section;
}

}  // namespace
}  // namespace scenes
