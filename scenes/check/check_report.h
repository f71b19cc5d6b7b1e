// The report of a golden check: report.json (every scene, every number) and a
// static index.html (failures first; expected and actual flicker on click).
// Plain structs: nothing here knows the physics.
#pragma once

#include "render/golden.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace scenes {

struct CheckpointHash {
    int frame = 0;
    std::string expected;  // hex; empty when there is no golden
    std::string actual;
};

struct SceneCheck {
    std::string scene;
    enum class Status { pass, fail, missing, exploded, updated, error } status = Status::pass;
    std::string message;                      // one line
    std::optional<render::GoldenDiff> image;  // metrics, when an image comparison happened
    std::vector<CheckpointHash> hashes;
    int first_hash_mismatch = -1;  // checkpoint index, -1: none
    // Where the physics first changed, from the golden's frame-by-frame
    // hashes (golden/<scene>.hashes); changed_frame -1: no change found, or
    // no such file (then `hashes_note` says so).
    int changed_frame = -1;
    int changed_substep = -1;                    // from 0; -1: not known (or frame 0, the start)
    int frames_expected = 0, frames_actual = 0;  // the last frame of each run, when their lengths differ
    int substeps = 1;                            // the scene's, per frame
    double changed_time = 0.0;                   // s, at the end of that substep
    int objects_frame = -1;                      // the frame where the objects were compared; -1: none
    std::vector<std::string> changed_objects;    // the objects that differ there, by their scene names
    std::string hashes_note;                     // why the frame-by-frame hashes were not compared; "" when they were
    std::string actual_recording;  // the actual run as a recording (run --record), relative to the report; "" none
    std::string expected_png, actual_png, diff_png, side_png;  // relative to the report folder; empty: not written
    std::string fingerprint_expected, fingerprint_actual;      // renderer fingerprints, one line each
    std::string arch_expected, arch_actual;                    // the golden's and this build's architecture
    // Hashes are judged only on the golden's architecture; a golden without
    // "arch" (written before it was recorded) is taken as comparable.
    bool hashes_comparable() const { return arch_expected.empty() || arch_expected == arch_actual; }
    double seconds = 0;  // s, wall time of the scene's check
};

const char* status_name(SceneCheck::Status status);

// Which part of a sharded check a report is (check --shard I/N): its scenes
// are the I-th of N equal parts of `of` scenes. count 0: not sharded.
struct ShardInfo {
    int index = 0;  // from 1
    int count = 0;
    int of = 0;  // scenes in all the shards
};

// Writes <dir>/report.json and <dir>/index.html, each atomically. Throws
// std::runtime_error naming the path when the folder cannot be written.
void write_check_report(const std::filesystem::path& dir, const std::vector<SceneCheck>& scenes,
                        const ShardInfo& shard = {});

// check --junit (check_junit.cpp): one testcase per scene, a failure or
// error carrying the verdict line and the evidence's paths under `report`.
std::string junit_xml(const std::vector<SceneCheck>& scenes, const ShardInfo& shard,
                      const std::filesystem::path& report);
// Writes it atomically (output_file.h); throws InputError naming the file.
void write_junit(const std::filesystem::path& file, const std::vector<SceneCheck>& scenes, const ShardInfo& shard,
                 const std::filesystem::path& report);

}  // namespace scenes
