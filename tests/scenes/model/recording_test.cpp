// Recordings (scenes/model/recording.h): a recording reads back as written;
// a truncated, corrupted or foreign file, or one of another format version,
// is refused with an InputError naming the file (never a crash, never a
// recording that reads wrong); the scene it replays is the scene it ran.
#include "scenes/model/recording.h"
#include "sim/state_hash.h"
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
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
            rec.hashes.push_back(sim::state_hash(world.state()));  // SceneRun's, for a world of particles only
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

TEST_F(RecordingFile, OnlyRegularFilesAreReadAndTheHeaderFirst) {
    // A FIFO with no writer: refused at once, never waited on (a wait would hang the test).
    const fs::path fifo = dir_ / "fifo.rec";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_FALSE(is_recording(fifo));
    EXPECT_NE(refusal(fifo).find(fifo.string() + ": not a regular file"), std::string::npos) << refusal(fifo);
    // A device that never ends.
    fs::create_symlink("/dev/zero", dir_ / "zero.rec");
    EXPECT_FALSE(is_recording(dir_ / "zero.rec"));
    EXPECT_NE(refusal(dir_ / "zero.rec").find("not a regular file"), std::string::npos) << refusal(dir_ / "zero.rec");
    // 4 GiB (sparse): the header is checked first, then the size, before reading on.
    write_recording(dir_ / "good.rec", sample());
    const std::string good = bytes_of(dir_ / "good.rec");
    for (const std::string& head : {good.substr(0, 16), std::string("not a recording!")}) {
        const fs::path big = dir_ / "big.rec";
        write_bytes(big, head);
        fs::resize_file(big, 4ull << 30);
        const std::string why = refusal(big);
        const bool ours = head == good.substr(0, 16);
        EXPECT_NE(why.find(ours ? big.string() + ": 4294967296 bytes is too large for a recording (at most 128.0 MiB)"
                                : big.string() + ": not a recording"),
                  std::string::npos)
            << why;
        fs::remove(big);
    }
}

TEST_F(RecordingFile, AnEditedStoredStateIsRefused) {
    // A stored state changed and the file written whole (its checksum good):
    // the state no longer hashes to its frame's recorded hash.
    Recording rec = sample();
    rec.states[1].second.state.x.set(1, rec.states[1].second.state.x.get(1) + sim::Vec3(1e-9, 0, 0));
    write_recording(dir_ / "edited.rec", rec);
    const std::string why = refusal(dir_ / "edited.rec");
    EXPECT_NE(why.find((dir_ / "edited.rec").string() + ": not a readable recording: the stored state is not the one"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("section STAT of frame 4"), std::string::npos) << why;
    // A stored state at a frame out of order, or beyond the recorded ones.
    rec = sample();
    std::swap(rec.states[0], rec.states[1]);
    write_recording(dir_ / "order.rec", rec);
    EXPECT_NE(refusal(dir_ / "order.rec").find("out of order"), std::string::npos) << refusal(dir_ / "order.rec");
    rec = sample();
    rec.states[2].first = 11;
    write_recording(dir_ / "beyond.rec", rec);
    EXPECT_NE(refusal(dir_ / "beyond.rec").find("beyond the 10 recorded"), std::string::npos)
        << refusal(dir_ / "beyond.rec");
}

TEST(RecordingInterval, StatesStayWithinTheirBudgetHoweverLongTheRun) {
    EXPECT_EQ(recording_interval(600, 1000), 1) << "small states: every frame";
    EXPECT_EQ(recording_interval(600, 100'000), 31) << "601 frames, 20 states of 100 kB in 2 MB";
    EXPECT_EQ(recording_interval(600, 10'000'000), 601) << "a state over the budget: frame 0's alone";
    for (int frames : {0, 1, 10, 600, 6000, 100'000, 10'000'000}) {
        for (std::size_t bytes :
             {std::size_t{200}, std::size_t{1000}, std::size_t{50'000}, std::size_t{300'000}, std::size_t{5'000'000}}) {
            const int k = recording_interval(frames, bytes);
            ASSERT_GE(k, 1);
            const double stored = static_cast<double>(frames / k + 1);
            const double budget = std::max(static_cast<double>(kRecordingStatesBytes), static_cast<double>(bytes));
            EXPECT_LE(stored * static_cast<double>(bytes), budget)
                << frames << " frames of " << bytes << " B: every " << k;
            // And not needlessly sparse: one more state would not fit.
            if (k > 1) {
                EXPECT_GT((frames / (k - 1) + 1) * static_cast<double>(bytes), budget) << frames << ", " << bytes;
            }
        }
    }
}

}  // namespace
}  // namespace scenes
