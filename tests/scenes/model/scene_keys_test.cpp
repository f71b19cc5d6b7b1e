// scenes/model/scene_keys.cpp: the loader's vocabulary against what else
// lists it. The fuzzer's dictionary (tools/fuzz/scene.dict) names every key
// of every table once as key_<name>="<name>": a key the loader learns and the
// dictionary lacks is one the fuzzer has to guess byte by byte.
#include "scenes/model/scene_keys.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

namespace scenes {
namespace {

std::set<std::string> dictionary_keys() {
    const std::filesystem::path file = std::filesystem::path(PLAUSIBLE_SOURCE_DIR) / "tools" / "fuzz" / "scene.dict";
    std::ifstream in(file);
    EXPECT_TRUE(in) << file << " cannot be read";
    const std::regex entry(R"re(^key_([A-Za-z0-9_]+)="([A-Za-z0-9_]+)"$)re");
    std::set<std::string> out;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        std::smatch m;
        if (!std::regex_match(line, m, entry)) continue;
        EXPECT_EQ(m[1], m[2]) << file << ":" << number << ": the entry's name and value differ";
        out.insert(m[2]);
    }
    return out;
}

TEST(SceneKeys, TheFuzzersDictionaryHoldsEveryKey) {
    std::set<std::string> loader;
    for (const keys::SectionKeys& section : keys::sections()) {
        for (keys::Table table : section.tables) loader.insert(table.begin(), table.end());
    }
    const std::set<std::string> dictionary = dictionary_keys();
    for (const std::string& key : loader) {
        EXPECT_TRUE(dictionary.contains(key)) << "tools/fuzz/scene.dict lacks key_" << key << "=\"" << key << "\"";
    }
    for (const std::string& key : dictionary) {
        EXPECT_TRUE(loader.contains(key)) << "tools/fuzz/scene.dict has key_" << key << ", which no loader table has";
    }
    EXPECT_GT(loader.size(), 100u) << "the tables were not read";
}

}  // namespace
}  // namespace scenes
