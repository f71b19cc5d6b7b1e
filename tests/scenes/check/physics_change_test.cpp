// `plausible check` says where physics changed, through the real command: a
// one-object perturbation in a multi-object scene (the showcase's rope made
// 1e-7 heavier; the showcase also has a cloth, an emitter, two ragdolls and
// colliders) names exactly that object and the first frame whose state
// differs, the frame and the object found independently from two
// `plausible run --csv` files (every particle's and body's x and v, 17
// significant digits: exact).
#include "scenes/model/scene.h"
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

namespace {

namespace fs = std::filesystem;

// run --csv's rows: (frame, kind, id) -> "x,y,z,vx,vy,vz".
using Rows = std::map<std::tuple<int, std::string, int>, std::string>;
Rows read_csv(const fs::path& file) {
    Rows rows;
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string frame, time, kind, id, rest;
        std::getline(s, frame, ',');
        std::getline(s, time, ',');
        std::getline(s, kind, ',');
        std::getline(s, id, ',');
        std::getline(s, rest);
        rows[{std::stoi(frame), kind, std::stoi(id)}] = rest;
    }
    return rows;
}

TEST(PhysicsChange, AOneObjectChangeNamesThatObjectAndItsFirstFrame) {
    const fs::path dir = fs::temp_directory_path() / ("plausible-physics-change-" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string exe = PLAUSIBLE_EXE;
    const std::string change = " --set ropes[0].mass=1.0000001";

    // Independently: the first frame whose rows differ, and which.
    ASSERT_EQ(test::shell(exe + " run showcase --frames 4 --csv " + (dir / "base.csv").string()).status, 0);
    ASSERT_EQ(test::shell(exe + " run showcase --frames 4 --csv " + (dir / "changed.csv").string() + change).status, 0);
    const Rows base = read_csv(dir / "base.csv"), changed = read_csv(dir / "changed.csv");
    ASSERT_EQ(base.size(), changed.size());
    int first = -1;
    std::set<std::pair<std::string, int>> differing;  // (kind, id) at the first differing frame
    for (const auto& [key, values] : base) {
        const int frame = std::get<0>(key);
        if (first >= 0 && frame > first) break;
        if (changed.at(key) != values) {
            first = frame;
            differing.insert({std::get<1>(key), std::get<2>(key)});
        }
    }
    ASSERT_GE(first, 0) << "the change shows within 4 frames";
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("showcase"));
    const scenes::BodyLook* rope = nullptr;
    for (const scenes::BodyLook& body : scene.bodies) {
        if (body.name == "rope") rope = &body;
    }
    ASSERT_NE(rope, nullptr);
    for (const auto& [kind, id] : differing) {
        EXPECT_EQ(kind, "particle") << "only the rope's particles differ at frame " << first;
        EXPECT_GE(id, static_cast<int>(rope->range.first));
        EXPECT_LT(id, static_cast<int>(rope->range.first + rope->range.count));
    }

    // The check names that frame and that object alone, exit 1.
    const fs::path report = dir / "report";
    const test::Ran r = test::shell(exe + " check showcase --physics-only --report " + report.string() + change);
    const std::string& out = r.out;
    EXPECT_NE(out.find("physics changed at frame " + std::to_string(first) + ","), std::string::npos) << out;
    EXPECT_NE(out.find("of 4 (t = "), std::string::npos) << "the substep and the time: " << out;
    EXPECT_NE(out.find("s): rope;"), std::string::npos) << "the rope and nothing else: " << out;
    EXPECT_EQ(r.status, 1) << out;
    std::ifstream in(report / "report.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    const nlohmann::json& c = j.at("scenes").at(0).at("physics_change");
    EXPECT_EQ(c.at("frame"), first);
    EXPECT_EQ(c.at("objects"), nlohmann::json::array({"rope"}));
    EXPECT_EQ(c.at("substeps"), 4);

    // The evidence: the actual run as a recording beside the report, which
    // replays to the same hashes, and the HTML says how to open it.
    EXPECT_EQ(j.at("scenes").at(0).at("actual_recording"), "showcase/actual.rec");
    const fs::path rec = report / "showcase" / "actual.rec";
    EXPECT_NE(out.find("plausible view " + rec.string()), std::string::npos) << out;
    const test::Ran replay = test::shell(exe + " run " + rec.string());
    EXPECT_EQ(replay.status, 0) << replay.out;
    EXPECT_NE(replay.out.find("identical to the recorded state hashes"), std::string::npos) << replay.out;
    std::ifstream html_in(report / "index.html");
    const std::string html((std::istreambuf_iterator<char>(html_in)), std::istreambuf_iterator<char>());
    EXPECT_NE(html.find("plausible view showcase/actual.rec</code>, run in this report's folder"), std::string::npos)
        << "the report's command, relative to the report";
    EXPECT_LT(html.find("<table class=\"summary\">"), html.find("<div class=\"scene fail\""))
        << "the summary table first";
    fs::remove_all(dir);
}

}  // namespace
