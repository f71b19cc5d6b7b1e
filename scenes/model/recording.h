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
// A truncated, corrupted or foreign file, one of another version, one larger
// than kMaxRecordingBytes, or a stored state that does not hash to its
// frame's recorded hash, is refused with an InputError naming the file and
// what is wrong.
#pragma once

#include "scenes/model/scene.h"
#include "sim/world.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
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

// Bytes the stored states of a recording stay within (RunRecorder), unless
// the state at frame 0 alone is larger: then it is the only one stored.
constexpr std::size_t kRecordingStatesBytes = 2'000'000;
// The largest recording read, and so the largest `run --record` writes
// (it refuses a longer run before running): 8 bytes a frame for the most
// frames a scene runs, a 16 MiB scene file and the states, with room over.
constexpr std::uint64_t kMaxRecordingBytes = 128ull << 20;

// The frames between stored states for a run of `frames` frames whose stored
// state takes `state_bytes`: states at 0, K, 2K, ... up to `frames` stay
// within kRecordingStatesBytes (one state at least: frame 0's).
int recording_interval(int frames, std::size_t state_bytes);

// Bytes of a snapshot's STAT section as the file stores it (header included).
std::size_t snapshot_bytes(const sim::World::Snapshot& snapshot);
// Bytes of a recording with no states: header, SCNE, STEP, HASH, END.
std::uint64_t recording_bytes_without_states(const Recording& recording, int frames);

// The state hash (SceneRun::state_hash) of a World restored from the
// snapshot: its particles' hash, folded with its rigid bodies' when
// `rigid` (the World has a rigid world).
std::uint64_t snapshot_hash(const sim::World::Snapshot& snapshot, bool rigid);

// Writes atomically (a temporary file renamed into place: nothing
// half-written). InputError when the folder cannot be written, or the
// recording is larger than kMaxRecordingBytes.
void write_recording(const std::filesystem::path& file, const Recording& recording);
// Reads and validates (see the top of this file). Only a regular file is
// read (a FIFO or a device is refused, never waited on), its header is
// checked before the rest is read, and its size before reading it.
Recording read_recording(const std::filesystem::path& file);
// The same over a file's bytes (`file` names it in messages).
Recording parse_recording(std::string_view bytes, const std::string& file);
// Whether the file is a regular file that starts with the recording magic
// (a .toml never does); never blocks on a FIFO.
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
