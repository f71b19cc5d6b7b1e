// Recordings (`plausible run SCENE --record FILE`): a run kept so that it can
// be replayed and checked anywhere. A recording holds the scene's text and
// the overrides it ran with (so that replaying builds the same scene), the
// step settings, the state hash after every frame, and the World's whole
// state at frame 0 and every K frames (so that the viewer can jump to any
// frame: the nearest stored state, then steps). Replaying recomputes each
// frame's hash; the first that differs is where the run diverged (another
// machine, another build).
//
// The file (docs/design.md "Recordings"), version 1, every number
// little-endian whatever the machine (IEEE 754 doubles, two's-complement
// integers):
//   "PLSBLREC"  8 bytes, the magic
//   u32 version (1), u32 0x01020304 (the byte order, as a check)
//   sections, each: 4-byte tag, u64 payload length, payload:
//     SCNE  scene name, the file it was read from, its text, the overrides
//           (u32 count, then key and value), as strings (u32 length, bytes)
//     STEP  integrator name, f64 dt (s), i32 substeps, i32 frames recorded,
//           i32 K (a state every K frames)
//     HASH  frames + 1 u64: the state hash after each frame, frame 0 first
//     STAT  one per stored state: i32 frame, then the World's snapshot
//     END   u64: FNV-1a of every byte before this section
// A truncated, corrupted or foreign file, or one of another version, is
// refused with an InputError naming the file and what is wrong.
#pragma once

#include "scenes/model/scene.h"
#include "sim/world.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace scenes {

// What a scene built from a recording carries (SceneDef::recorded).
struct RecordedRun {
    std::filesystem::path file;
    std::vector<std::uint64_t> hashes;                         // after each frame, frame 0 first
    int every = 1;                                             // frames between stored states
    std::vector<std::pair<int, sim::World::Snapshot>> states;  // (frame, the World then), ascending
};

struct Recording {
    static constexpr std::uint32_t kVersion = 1;

    std::string scene_name;
    std::string scene_file;  // where the scene was read from (for messages; replay needs only the text)
    std::string scene_text;  // the scene file's bytes
    std::vector<Override> overrides;
    sim::StepSettings step;
    int frames = 0;                                            // frames recorded
    int every = 1;                                             // K: states at frames 0, K, 2K, ...
    std::vector<std::uint64_t> hashes;                         // frames + 1: after each frame, frame 0 first
    std::vector<std::pair<int, sim::World::Snapshot>> states;  // (frame, the World then), ascending
};

// The frames between stored states for a run of `frames` frames whose state
// takes `state_bytes`: the states together stay within about 4 MB (a 10 s
// showcase: about 2 MB), and at most 60 frames apart for scrubbing.
int recording_interval(int frames, std::size_t state_bytes);

// Bytes of a snapshot as the file stores it.
std::size_t snapshot_bytes(const sim::World::Snapshot& snapshot);

// Writes atomically (a temporary file renamed into place: nothing
// half-written). InputError when the folder cannot be written.
void write_recording(const std::filesystem::path& file, const Recording& recording);
// Reads and validates (see the top of this file).
Recording read_recording(const std::filesystem::path& file);
// Whether the file starts with the recording magic (a .toml never does).
bool is_recording(const std::filesystem::path& file);

// The scene a recording ran: its text parsed with its overrides, and the
// recording attached (SceneDef::recorded) so that every run of it checks each
// frame against the recorded hashes. InputError when the text does not build
// the recorded step settings.
SceneDef scene_of(const Recording& recording, const std::filesystem::path& file);

// A catalogue name, a .toml path or a recording: the scene to run.
// Overrides are refused for a recording (they would not replay it).
SceneDef load_scene_or_recording(const std::string& name_or_path, const std::vector<Override>& overrides);

}  // namespace scenes
