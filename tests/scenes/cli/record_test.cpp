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

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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

// The recording with frame `frame`'s recorded hash changed and the END
// checksum recomputed (docs/design.md "Recordings": sections of a 4-byte
// tag and a u64 length after a 16-byte header).
std::string tampered(std::string b, int frame) {
    for (std::size_t pos = 16; pos + 12 <= b.size();) {
        const std::string tag = b.substr(pos, 4);
        const std::uint64_t length = little_u64(b, pos + 4);
        if (tag == "HASH") {
            const std::size_t at = pos + 12 + 8 * static_cast<std::size_t>(frame);
            put_little_u64(b, at, little_u64(b, at) ^ 1);
        } else if (tag == "END ") {
            put_little_u64(b, pos + 12, fnv1a(b, pos));
            return b;
        }
        pos += 12 + length;
    }
    ADD_FAILURE() << "no END section";
    return b;
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
    EXPECT_LT(size, 4'000'000u) << "a few MB";
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
    ASSERT_EQ(plausible("run rope --frames 80 --record r.rec").status, 0);
    const int frame = 57;
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

}  // namespace
