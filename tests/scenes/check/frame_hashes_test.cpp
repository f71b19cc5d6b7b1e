// The golden's frame-by-frame hashes (scenes/check/frame_hashes.h): the file
// reads back what was written; a truncated, corrupted or foreign file, or one
// of another format version, is refused naming the file and the line; the
// first differing frame and substep, and the objects that differ, are found.
#include "scenes/check/frame_hashes.h"

#include "scenes/model/scene.h"

#include <gtest/gtest.h>

#include <string>

namespace scenes {
namespace {

RunHashes sample() {
    RunHashes h;
    h.substeps = 3;
    h.objects = {"rope", "r0.pelvis", "r0.head", "a name with spaces"};
    for (int f = 0; f <= 5; ++f) {
        FrameRecord r{.hash = 0x1234'5678'9abc'def0ull + static_cast<std::uint64_t>(f), .substeps = {}};
        if (f > 0) r.substeps = {static_cast<std::uint16_t>(f), static_cast<std::uint16_t>(0xff00 + f)};
        h.frames.push_back(r);
        if (object_grid_frame(f, {5})) h.object_hashes[f] = {1u + f, 2u + f, 3u + f, 0xffff'ffffu};
    }
    return h;
}

TEST(FrameHashes, ReadBackWhatWasWritten) {
    const RunHashes h = sample();
    const std::string text = format_run_hashes(h);
    const RunHashes back = parse_run_hashes(text, "x.hashes");
    EXPECT_EQ(format_run_hashes(back), text);
    EXPECT_EQ(back.substeps, 3);
    EXPECT_EQ(back.objects, h.objects);
    ASSERT_EQ(back.frames.size(), 6u);
    EXPECT_EQ(back.frames[4].hash, h.frames[4].hash);
    EXPECT_EQ(back.frames[4].substeps, h.frames[4].substeps);
    EXPECT_EQ(back.object_hashes, h.object_hashes);
    // The grid: 0, the powers of two and the checkpoints.
    for (int f : {0, 1, 2, 4, 5}) EXPECT_EQ(back.object_hashes.count(f), 1u) << "frame " << f;
    EXPECT_EQ(back.object_hashes.count(3), 0u);
}

// Each bad file: the error names the file, the line, and what is wrong.
TEST(FrameHashes, BadFilesAreRefusedNamingFileAndLine) {
    const std::string good = format_run_hashes(sample());
    struct Case {
        std::string text, expected;
    };
    const std::string frame3 = "frame 3 123456789abcdef3 0003 ff03\n";
    ASSERT_NE(good.find(frame3), std::string::npos);
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string t = good;
        t.replace(t.find(from), from.size(), to);
        return t;
    };
    for (const Case& c : {
             Case{"", "x.hashes:1: empty"},
             Case{"\x89PNG\r\n\x1a\n", "x.hashes:1: not a hashes file"},
             Case{replaced("plausible-hashes 1", "plausible-hashes 2"),
                  "x.hashes:1: format version 2, and this build reads version 1"},
             Case{replaced(frame3, "frame 3 123456789abcdeg3 0003 ff03\n"),
                  "x.hashes:13: a state hash must be 16 hex digits (got \"123456789abcdeg3\")"},
             Case{replaced(frame3, "frame 3 123456789abcdef3 0003\n"),
                  "x.hashes:13: frame 3 has 1 substep hashes, 2 expected"},
             Case{replaced(frame3, "frame 4 123456789abcdef3 0003 ff03\n"),
                  "x.hashes:13: frame 4 where frame 3 was expected"},
             Case{replaced(frame3, "frame 3 123456789abcdef3 0003 ff03 garbage\n"),
                  "x.hashes:13: frame 3 has 3 substep hashes"},
             Case{good.substr(0, good.find("objects 2")) + "objects 2 00000001\n",
                  "x.hashes:12: 1 object hashes for 4 objects"},
             Case{good.substr(0, good.find("frame 0")), "x.hashes:6: no frame lines"},
         }) {
        try {
            parse_run_hashes(c.text, "x.hashes");
            ADD_FAILURE() << "accepted: " << c.expected;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
                << "got: " << e.what() << "\nexpected: " << c.expected;
        }
    }
}

TEST(FrameHashes, LocateTheFirstFrameSubstepAndObjects) {
    const RunHashes expected = sample();
    EXPECT_EQ(locate_change(expected, expected).frame, -1) << "the same run: no change";

    RunHashes actual = expected;
    actual.frames[3].hash ^= 1;
    actual.frames[4].hash ^= 1;
    actual.frames[3].substeps[1] ^= 1;  // the second substep's
    actual.object_hashes[4][1] ^= 1;    // r0.pelvis, at the next grid frame
    HashChange c = locate_change(expected, actual);
    EXPECT_EQ(c.frame, 3);
    EXPECT_EQ(c.substep, 1);
    EXPECT_EQ(c.objects_frame, 4) << "frame 3 keeps no objects: the first grid frame after";
    EXPECT_EQ(c.objects, std::vector<std::string>{"r0.pelvis"});

    actual = expected;
    actual.frames[2].hash ^= 1;  // every substep's short hash the same: the last substep, the frame's own
    c = locate_change(expected, actual);
    EXPECT_EQ(c.frame, 2);
    EXPECT_EQ(c.substep, 2);

    actual = expected;
    actual.frames.resize(4);  // the run stopped early: the first frame only one run reached
    actual.object_hashes.erase(4);
    actual.object_hashes.erase(5);
    c = locate_change(expected, actual);
    EXPECT_EQ(c.frame, 4);
    EXPECT_EQ(c.objects_frame, -1) << "no grid frame at or after it in both";

    actual = expected;
    actual.objects[3] = "renamed";
    actual.frames[0].hash ^= 1;
    c = locate_change(expected, actual);
    EXPECT_EQ(c.frame, 0);
    EXPECT_EQ(c.substep, -1) << "frame 0 is the start: no substeps";
    EXPECT_EQ(c.objects, (std::vector<std::string>{"renamed (new)", "a name with spaces (gone)"}));
}

TEST(FrameHashes, AGroupWhoseEveryBodyChangedIsNamedOnce) {
    const std::vector<SceneObject> objects = {
        {.name = "rope"},
        {.name = "r0.pelvis", .group = "r0", .rigid = true},
        {.name = "r0.head", .group = "r0", .rigid = true},
        {.name = "r1.pelvis", .group = "r1", .rigid = true},
        {.name = "r1.head", .group = "r1", .rigid = true},
    };
    EXPECT_EQ(group_changed({"r0.pelvis", "r0.head", "r1.head"}, objects),
              (std::vector<std::string>{"r0 (all 2 bodies)", "r1.head"}));
    EXPECT_EQ(group_changed({"rope", "ball (new)"}, objects), (std::vector<std::string>{"rope", "ball (new)"}));
}

}  // namespace
}  // namespace scenes
