// The frame-by-frame record of a run that a golden keeps beside its
// checkpoint hashes (golden/<scene>.hashes, docs/design.md "Golden checks"):
// the state hash after every frame, a short one after every substep but the
// last, and one hash per named object at a sparse grid of frames. `check`
// compares an actual run's record with the golden's to say where the physics
// first changed: the frame, its substep, and the objects that differ.
//
// The file is text, one line per frame, so that a diff of two shows where
// they part:
//   plausible-hashes 1                       format and version
//   substeps 4                               substeps per frame
//   object rope                              the objects, in scene_objects' order
//   frame 0 59e7710315ff549f                 frame, state hash (16 hex digits)
//   frame 1 0c5e0b1d2a6f4e11 9f3a 1b2c 77d0  ... then each substep's but the last (its top 4 hex digits)
//   objects 1 5a1f02c4 ...                   at a grid frame: one hash per object (8 hex digits), in order
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace scenes {

struct SceneObject;

struct FrameRecord {
    std::uint64_t hash = 0;               // the state hash after the frame (at frame 0: the start)
    std::vector<std::uint16_t> substeps;  // the top 16 bits of the state hash after each substep but the last
};

struct RunHashes {
    int substeps = 1;                                         // per frame
    std::vector<FrameRecord> frames;                          // frame 0 (the start), 1, 2, ...
    std::vector<std::string> objects;                         // names, scene_objects' order
    std::map<int, std::vector<std::uint32_t>> object_hashes;  // at the grid frames: one per object
};

// The frames whose object hashes are kept: 0, the powers of two, and the
// checkpoints. Dense where a change starts to spread, a few lines in all.
bool object_grid_frame(int frame, const std::vector<int>& checkpoints);

// The file's text, and back. parse_run_hashes throws SceneError naming
// `file`, the line and what is wrong there.
std::string format_run_hashes(const RunHashes& hashes);
RunHashes parse_run_hashes(std::string_view text, const std::string& file);

// Where an actual run first differs from the expected one.
struct HashChange {
    int frame = -1;          // the first frame whose state differs (or that only one run reached); -1: none
    int substep = -1;        // its first substep that differs, from 0; -1: not known (the substep counts differ)
    bool ended = false;      // one run stops there: every frame both reached is the same (another length)
    int objects_frame = -1;  // the grid frame where the objects were compared; -1: none at or after
    std::vector<std::string> objects;  // those that differ there ("name", "name (new)", "name (gone)")
};
HashChange locate_change(const RunHashes& expected, const RunHashes& actual);

// The changed objects as a reader wants them: in the scene's order, and a
// ragdoll or chain whose every body changed as one entry ("ragdoll1 (all 11
// bodies)") rather than each of its bones.
std::vector<std::string> group_changed(const std::vector<std::string>& changed,
                                       const std::vector<SceneObject>& objects);

}  // namespace scenes
