// Recordings (scenes/model/recording.h): a recording reads back as written;
// a truncated, corrupted or foreign file, or one of another format version,
// is refused with an InputError naming the file (never a crash, never a
// recording that reads wrong); the scene it replays is the scene it ran.
#include "scenes/model/recording.h"
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace scenes {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScene = R"(
description = "A bead on a spring."
frames = 20
[step]
integrator = "rk4"
dt = 0.01
substeps = 2
[[particles]]
name = "anchor"
position = [0, 1, 0]
pinned = true
[[particles]]
name = "bob"
position = [0.5, 1, 0]
[[forces.springs]]
a = "anchor"
b = "bob"
stiffness = 40
)";

class RecordingFile : public ::testing::Test {
protected:
    // A recording of kScene's first frames, states every 4 (made by hand: the
    // format is what is tested here; the command's recordings in
    // tests/scenes/cli/record_test.cpp).
    static Recording sample() {
        const SceneDef scene = parse_scene(kScene, "bead.toml", {{"particles[1].mass", "2"}});
        sim::World world(scene.model);
        Recording rec{.scene_name = "bead",
                      .scene_file = "bead.toml",
                      .scene_text = kScene,
                      .overrides = {{"particles[1].mass", "2"}},
                      .step = scene.step,
                      .every = 4};
        for (int f = 0; f <= 10; ++f) {
            if (f > 0) world.step(scene.step);
            rec.hashes.push_back(0x1000 + static_cast<std::uint64_t>(f));
            if (f % rec.every == 0) rec.states.emplace_back(f, world.snapshot());
        }
        rec.frames = 10;
        return rec;
    }
    static std::string bytes_of(const fs::path& file) {
        std::ifstream in(file, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    static void write_bytes(const fs::path& file, const std::string& bytes) {
        std::ofstream(file, std::ios::binary) << bytes;
    }
    // What read_recording says about the file, or "" when it reads.
    static std::string refusal(const fs::path& file) {
        try {
            read_recording(file);
        } catch (const sim::InputError& e) {
            return e.what();
        }
        return "";
    }
    test::TempDir temp_{"plausible-recording-test"};
    const fs::path& dir_ = temp_.path();
};

TEST_F(RecordingFile, ReadsBackWhatWasWritten) {
    const Recording rec = sample();
    write_recording(dir_ / "bead.rec", rec);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}), 1) << "no temporary left";
    EXPECT_TRUE(is_recording(dir_ / "bead.rec"));
    const Recording back = read_recording(dir_ / "bead.rec");
    EXPECT_EQ(back.scene_name, "bead");
    EXPECT_EQ(back.scene_text, rec.scene_text);
    ASSERT_EQ(back.overrides.size(), 1u);
    EXPECT_EQ(back.overrides[0].value, "2");
    EXPECT_EQ(back.step.integrator, sim::Integrator::rk4);
    EXPECT_EQ(back.step.substeps, 2);
    EXPECT_EQ(back.frames, 10);
    EXPECT_EQ(back.every, 4);
    EXPECT_EQ(back.hashes, rec.hashes);
    ASSERT_EQ(back.states.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
        const sim::World::Snapshot &a = rec.states[k].second, &b = back.states[k].second;
        EXPECT_EQ(back.states[k].first, rec.states[k].first);
        EXPECT_EQ(b.state.t, a.state.t);
        EXPECT_EQ(b.state.x.flat(), a.state.x.flat()) << "bit-exact";
        EXPECT_EQ(b.state.v.flat(), a.state.v.flat()) << "bit-exact";
        EXPECT_EQ(b.state.inv_mass, a.state.inv_mass);
        EXPECT_EQ(b.steps, a.steps);
        EXPECT_EQ(b.memory_integrator, a.memory_integrator);
    }
    // A stored state restored and stepped on gives the bits of the run that made it.
    const SceneDef scene = scene_of(back, dir_ / "bead.rec");
    EXPECT_EQ(scene.model.particles[1].mass, 2.0) << "the recorded overrides apply";
    sim::World from_state(scene.model), from_start(scene.model);
    from_state.restore(back.states[1].second);  // frame 4
    for (int f = 0; f < 8; ++f) from_start.step(scene.step);
    for (int f = 4; f < 8; ++f) from_state.step(scene.step);
    EXPECT_EQ(from_state.state().x.flat(), from_start.state().x.flat()) << "bit-exact";
}

TEST_F(RecordingFile, BadFilesAreRefusedNamingTheFile) {
    write_recording(dir_ / "good.rec", sample());
    const std::string good = bytes_of(dir_ / "good.rec");
    const fs::path bad = dir_ / "bad.rec";
    // Truncated anywhere: refused, never read short.
    for (std::size_t cut : {std::size_t{0}, std::size_t{5}, std::size_t{12}, std::size_t{40}, good.size() / 2,
                            good.size() - 9, good.size() - 1}) {
        write_bytes(bad, good.substr(0, cut));
        const std::string why = refusal(bad);
        EXPECT_NE(why.find(bad.string() + ": "), std::string::npos) << "cut at " << cut << ": " << why;
    }
    // Any byte changed: refused (its section's check, or the checksum at the end).
    for (std::size_t at = 8; at < good.size(); at += good.size() / 37) {
        std::string flipped = good;
        flipped[at] = static_cast<char>(flipped[at] ^ 0x10);
        write_bytes(bad, flipped);
        EXPECT_FALSE(refusal(bad).empty()) << "a flip at byte " << at << " was read as a recording";
    }
    // Foreign files.
    write_bytes(bad, "\x89PNG\r\n\x1a\n....");
    EXPECT_NE(refusal(bad).find("not a recording"), std::string::npos) << refusal(bad);
    write_bytes(bad, kScene);
    EXPECT_NE(refusal(bad).find("not a recording"), std::string::npos) << refusal(bad);
    // Another version: both named.
    std::string v2 = good;
    v2[8] = 2;
    write_bytes(bad, v2);
    EXPECT_NE(refusal(bad).find("format version 2, and this build reads version 1"), std::string::npos) << refusal(bad);
    EXPECT_NE(refusal(dir_ / "none.rec").find("cannot read"), std::string::npos);
    // Overrides cannot be laid over a recording.
    EXPECT_THROW(load_scene_or_recording((dir_ / "good.rec").string(), {{"step.dt", "0.02"}}), sim::InputError);
}

TEST(RecordingInterval, StatesStayWithinAFewMegabytesAndSixtyFramesApart) {
    EXPECT_EQ(recording_interval(600, 1000), 1) << "small states: every frame";
    EXPECT_EQ(recording_interval(600, 100'000), 30) << "600 x 100 kB in 2 MB: every 30";
    EXPECT_EQ(recording_interval(600, 10'000'000), 60) << "at most 60 frames apart";
    for (int frames : {10, 600, 6000}) {
        for (std::size_t bytes : {std::size_t{1000}, std::size_t{50'000}, std::size_t{300'000}}) {
            const int k = recording_interval(frames, bytes);
            const double total = static_cast<double>(frames / k + 1) * static_cast<double>(bytes);
            EXPECT_TRUE(total <= 2.2e6 || k == 60) << frames << " frames of " << bytes << " B: every " << k;
        }
    }
}

}  // namespace
}  // namespace scenes
