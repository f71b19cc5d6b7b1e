// Recordings through the real command: `run SCENE --record FILE` writes one
// that `run`, `render` and `check` replay with every frame's hash identical
// (`video` and `view` replay them too: the tampered one below, and
// tests/scenes/view),
// rendering the same bytes as the scene; a recording tampered with (one
// frame's recorded hash changed, its checksum made good again, as a
// recording from a machine that computed another state would be) is
// reported as diverged at exactly that frame, exit 1; bad recordings exit 2.
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

namespace {

namespace fs = std::filesystem;

std::string bytes_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint64_t little_u64(const std::string& b, std::size_t at) {
    std::uint64_t v = 0;
    for (int k = 7; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(k)]);
    return v;
}
void put_little_u64(std::string& b, std::size_t at, std::uint64_t v) {
    for (int k = 0; k < 8; ++k) b[at + static_cast<std::size_t>(k)] = static_cast<char>(v >> (8 * k));
}

// FNV-1a, 64 bits (written here from its definition, not the project's).
std::uint64_t fnv1a(const std::string& bytes, std::size_t n) {
    std::uint64_t h = 14695981039346656037ull;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
    return h;
}

// The recording with `edit(bytes, tag, payload)` applied to each section
// before END, and the END checksum recomputed (docs/design.md "Recordings":
// sections of a 4-byte tag and a u64 length after a 16-byte header).
template <class Edit>
std::string edited(std::string b, Edit edit) {
    for (std::size_t pos = 16; pos + 12 <= b.size();) {
        const std::string tag = b.substr(pos, 4);
        const std::uint64_t length = little_u64(b, pos + 4);
        if (tag == "END ") {
            put_little_u64(b, pos + 12, fnv1a(b, pos));
            return b;
        }
        edit(b, tag, pos + 12);
        pos += 12 + length;
    }
    ADD_FAILURE() << "no END section";
    return b;
}

// The recording with frame `frame`'s recorded hash changed.
std::string tampered(std::string b, int frame) {
    return edited(std::move(b), [&](std::string& bytes, const std::string& tag, std::size_t payload) {
        if (tag != "HASH") return;
        const std::size_t at = payload + 8 * static_cast<std::size_t>(frame);
        put_little_u64(bytes, at, little_u64(bytes, at) ^ 1);
    });
}

// The recording with one bit of stored state `which` (0: frame 0's) flipped:
// its first particle's x (after the STAT payload's frame i32, t f64 and
// the count u64).
std::string state_edited(std::string b, int which) {
    return edited(std::move(b), [&](std::string& bytes, const std::string& tag, std::size_t payload) {
        if (tag == "STAT" && which-- == 0)
            bytes[payload + 4 + 8 + 8] = static_cast<char>(bytes[payload + 4 + 8 + 8] ^ 1);
    });
}

class Record : public ::testing::Test {
protected:
    test::Ran plausible(const std::string& args) const {
        return test::shell("cd '" + dir_.string() + "' && " PLAUSIBLE_EXE " " + args);
    }
    test::TempDir temp_{"plausible-record-test"};
    const fs::path& dir_ = temp_.path();
};

TEST_F(Record, ARecordingReplaysToTheSameHashesAndPixels) {
    // The showcase, whole: ragdolls (ODE), a cloth, a rope, an emitter, collisions.
    ASSERT_EQ(plausible("run showcase --record s.rec").status, 0);
    const std::uintmax_t size = fs::file_size(dir_ / "s.rec");
    EXPECT_LE(size, 2'000'000u + 8u * 361 + 65'536u) << "states within 2 MB, 8 bytes a frame, the scene";
    const test::Ran run = plausible("run s.rec");
    EXPECT_EQ(run.status, 0) << run.out;
    EXPECT_NE(run.out.find("frames 0 .. 360 of its 360 identical"), std::string::npos) << run.out;

    ASSERT_EQ(plausible("render showcase --frames 0,37,120 --out scene").status, 0);
    const test::Ran render = plausible("render s.rec --frames 0,37,120 --out rec");
    ASSERT_EQ(render.status, 0) << render.out;
    for (const char* png : {"showcase_f00000.png", "showcase_f00037.png", "showcase_f00120.png"}) {
        const std::string a = bytes_of(dir_ / "scene" / png), b = bytes_of(dir_ / "rec" / png);
        EXPECT_FALSE(a.empty()) << png;
        EXPECT_TRUE(a == b) << png << ": the recording's picture is the scene's, byte for byte";
    }
    const test::Ran check = plausible("check s.rec --physics-only --report report");
    EXPECT_EQ(check.status, 0) << check.out;
}

TEST_F(Record, ATamperedRecordingDivergesAtThatFrame) {
    // Long enough that states are stored every K > 1 frames: a hash changed
    // at a frame with a stored state is an edited file, refused (below).
    const test::Ran recorded = plausible("run rope --frames 3000 --record r.rec");
    ASSERT_EQ(recorded.status, 0) << recorded.out;
    const std::size_t every = recorded.out.find("(every ");
    ASSERT_NE(every, std::string::npos) << recorded.out;
    const int k = std::atoi(recorded.out.c_str() + every + 7);  // 0: "(every frame)"
    ASSERT_GT(k, 1) << recorded.out;
    const int frame = 57 % k != 0 ? 57 : 58;
    std::ofstream(dir_ / "t.rec", std::ios::binary) << tampered(bytes_of(dir_ / "r.rec"), frame);
    for (const std::string command : {"run t.rec", "render t.rec --frames 80 --out t", "check t.rec --physics-only",
                                      "video t.rec -o t.mp4 --size 160x120 --fps 60 --seconds 1.2"}) {
        const test::Ran r = plausible(command);
        EXPECT_EQ(r.status, 1) << command << ": " << r.out;
        const std::string at = " at frame " + std::to_string(frame);
        const bool said = r.out.find("DIVERGED" + at) != std::string::npos ||  // run, render, video
                          r.out.find("diverged" + at) != std::string::npos;    // check
        EXPECT_TRUE(said) << command << ": " << r.out;
    }
}

TEST_F(Record, BadRecordingsExit2) {
    ASSERT_EQ(plausible("run oscillator --frames 30 --record o.rec").status, 0);
    const std::string good = bytes_of(dir_ / "o.rec");
    std::ofstream(dir_ / "cut.rec", std::ios::binary) << good.substr(0, good.size() / 2);
    std::string flipped = good;
    flipped[good.size() / 3] = static_cast<char>(flipped[good.size() / 3] ^ 0x40);
    std::ofstream(dir_ / "flip.rec", std::ios::binary) << flipped;
    std::string v9 = good;
    v9[8] = 9;
    std::ofstream(dir_ / "v9.rec", std::ios::binary) << v9;
    std::ofstream(dir_ / "png.rec", std::ios::binary) << "\x89PNG\r\n\x1a\n0000";
    for (const auto& [file, says] :
         {std::pair{"cut.rec", "not a readable recording"}, std::pair{"flip.rec", "not a readable recording"},
          std::pair{"v9.rec", "a recording of format version 9, and this build reads version 1"},
          std::pair{"png.rec", "not a recording"}}) {
        for (const std::string command : {"run ", "render ", "check --physics-only "}) {
            const test::Ran r = plausible(command + file);
            EXPECT_EQ(r.status, 2) << command << file << ": " << r.out;
            EXPECT_NE(r.out.find(std::string(file) + ": " + says), std::string::npos)
                << command << file << ": " << r.out;
        }
    }
    const test::Ran set = plausible("run o.rec --dt 0.01");
    EXPECT_EQ(set.status, 2) << set.out;
    EXPECT_NE(set.out.find("a recording replays the scene it ran"), std::string::npos) << set.out;
}

TEST_F(Record, AnEditedStoredStateIsRefused) {
    // A stored state is where a replay or the viewer's seek starts from: one
    // edited (its checksum made good) is refused, not replayed as "identical".
    ASSERT_EQ(plausible("run rope --frames 80 --record r.rec").status, 0);
    for (int which : {0, 2}) {
        std::ofstream(dir_ / "e.rec", std::ios::binary) << state_edited(bytes_of(dir_ / "r.rec"), which);
        for (const std::string command :
             {"run e.rec", "check e.rec --physics-only", "render e.rec --frames 3 --out e"}) {
            const test::Ran r = plausible(command);
            EXPECT_EQ(r.status, 2) << command << ": " << r.out;
            EXPECT_NE(r.out.find("e.rec: not a readable recording: the stored state is not the one"), std::string::npos)
                << command << ": " << r.out;
            EXPECT_NE(r.out.find("section STAT of frame "), std::string::npos) << command << ": " << r.out;
            EXPECT_EQ(r.out.find("identical"), std::string::npos) << command << ": " << r.out;
        }
    }
}

TEST_F(Record, OnlyRegularFilesOfAtMost128MiBAreRead) {
    // A FIFO with no writer, a device, 4 GiB (sparse) with the recording's
    // header: each refused at once, naming the file (timeout: a wait would
    // be a hang, not a pass).
    ASSERT_EQ(mkfifo((dir_ / "fifo.rec").c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", dir_ / "zero.rec");
    ASSERT_EQ(plausible("run oscillator --frames 3 --record o.rec").status, 0);
    std::ofstream(dir_ / "big.rec", std::ios::binary) << bytes_of(dir_ / "o.rec").substr(0, 16);
    fs::resize_file(dir_ / "big.rec", 4ull << 30);
    for (const auto& [file, says] :
         {std::pair{"fifo.rec", "not a regular file"}, std::pair{"zero.rec", "not a regular file"},
          std::pair{"big.rec", "4294967296 bytes is too large for a recording (at most 128.0 MiB)"}}) {
        for (const std::string command : {"run ", "render ", "check --physics-only "}) {
            const test::Ran r =
                test::shell("cd '" + dir_.string() + "' && timeout 60 " PLAUSIBLE_EXE " " + command + file);
            EXPECT_EQ(r.status, 2) << command << file << ": " << r.out;
            EXPECT_NE(r.out.find(std::string(file) + ": " + says), std::string::npos)
                << command << file << ": " << r.out;
        }
    }
    for (const std::string command : {"run", "render", "video", "view", "check"}) {
        const test::Ran help = plausible(command + " --help");
        EXPECT_NE(help.out.find("128 MiB"), std::string::npos) << command << " --help states the limit: " << help.out;
    }
}

TEST_F(Record, ALongRunsRecordingStaysWithinItsStatedBound) {
    // States within 2 MB however long the run, plus 8 bytes a frame; the
    // command says the size it wrote, and the recording replays.
    const int frames = 200'000;
    const test::Ran run = plausible("run oscillator --frames " + std::to_string(frames) + " --record long.rec");
    ASSERT_EQ(run.status, 0) << run.out;
    const std::uintmax_t size = fs::file_size(dir_ / "long.rec");
    EXPECT_LE(size, 2'000'000u + 8u * (frames + 1) + 65'536u) << "2 MB of states, 8 bytes a frame, the scene";
    EXPECT_NE(run.out.find("recorded long.rec: 200000 frames, "), std::string::npos) << run.out;
    EXPECT_NE(run.out.find(" MiB"), std::string::npos) << run.out;
    const test::Ran replay = plausible("run long.rec");
    EXPECT_EQ(replay.status, 0) << replay.out;
    EXPECT_NE(replay.out.find("frames 0 .. 200000 of its 200000 identical"), std::string::npos) << replay.out;
    const test::Ran help = plausible("run --help");
    EXPECT_NE(help.out.find("8 bytes a"), std::string::npos) << help.out;
}

TEST_F(Record, StatesThatGrowAfterFrame0AreThinnedToStayWithinTheBound) {
    // velocity_verlet keeps two accelerations from frame 1 on: frame 0's
    // state, which K is chosen from, is the smallest. The recorder doubles K
    // (keeping every other state) rather than exceed the 2 MB of states.
    const int frames = 2000;
    const test::Ran run = plausible("run cloth --integrator velocity_verlet --frames 2000 --record c.rec");
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_LE(fs::file_size(dir_ / "c.rec"), 2'000'000u + 8u * (frames + 1) + 65'536u) << run.out;
    const test::Ran replay = plausible("run c.rec");
    EXPECT_EQ(replay.status, 0) << replay.out;
    EXPECT_NE(replay.out.find("frames 0 .. 2000 of its 2000 identical"), std::string::npos) << replay.out;
}

TEST_F(Record, ARunWhoseRecordingWouldBeTooLargeIsRefusedBeforeItRuns) {
    // A million particles (a 64 MB state) for the most frames a scene runs
    // (8 bytes each): over 128 MiB, refused before the first step.
    std::ofstream(dir_ / "many.toml")
        << "description = \"A million particles.\"\nframes = 10000000\n[step]\ndt = 0.01\n[[groups]]\nname = \"p\"\n"
           "count = 1000000\nspacing = [0.001, 0, 0]\n";
    const test::Ran r =
        test::shell("cd '" + dir_.string() + "' && timeout 120 " PLAUSIBLE_EXE " run many.toml --record many.rec");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("--record: 10000000 frames of many could make a recording of "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("more than a recording may hold (128.0 MiB)"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "many.rec"));
}

}  // namespace
