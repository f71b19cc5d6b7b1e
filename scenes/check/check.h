// Golden checks (docs/design.md "Golden checks"): a scene's checkpoint frames
// rendered off-screen as one filmstrip, compared with golden/<scene>.png, and
// the state hash at each checkpoint compared with golden/<scene>.json.
#pragma once

#include "render/golden.h"
#include "render/renderer.h"
#include "scenes/check/check_report.h"
#include "scenes/check/frame_hashes.h"
#include "scenes/model/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace scenes {

// A scene's checkpoints, rendered and hashed.
struct Filmstrip {
    render::Image image;              // the contact sheet, one tile per checkpoint
    std::vector<int> frames;          // the checkpoints reached
    std::vector<double> times;        // s
    std::vector<std::string> hashes;  // hex state hash at each
    sim::Verdict verdict;             // exploded: the run stopped at verdict.frame
    RunHashes record;                 // every frame's hash, up to the last checkpoint (golden/<scene>.hashes)
    int diverged_frame = -1;          // a recording's: where the run parted from it (SceneRun::diverged_frame)
};

struct FilmstripSettings {
    int width = 320;   // px per tile
    int height = 240;  // px per tile
    int msaa = 0;      // goldens: off
};

// Runs the scene from frame 0 and renders each checkpoint. When the watchdog
// stops the run, the last tile is the frame where it did.
Filmstrip render_filmstrip(const SceneDef& scene, render::Renderer& renderer, const FilmstripSettings& settings = {});

enum class UpdateMode { none, missing, changed, all };

struct CheckOptions {
    UpdateMode update = UpdateMode::none;
    std::filesystem::path golden_dir;  // default_golden_dir() unless set (check --golden)
    std::filesystem::path report_dir;  // out/check unless set
    ShardInfo shard;                   // the report says which part of a sharded check it is
};

// The index-th (from 1) of `count` equal parts of `names`, in their order
// (as Playwright's --shard): part sizes differ by at most one; a part may
// be empty when there are more parts than names. InputError unless
// 1 <= index <= count.
std::vector<std::string> shard_of(const std::vector<std::string>& names, int index, int count);

// The shipped goldens: data_dir()/golden (the source tree's golden/, or the
// installed share/plausible/golden).
std::filesystem::path default_golden_dir();

// Checks each scene (catalogue names or .toml paths), writes the report, and
// returns the per-scene results. Golden files are written only as `update`
// allows, never for an exploded scene.
std::vector<SceneCheck> check_scenes(const std::vector<std::string>& scenes, const std::vector<Override>& overrides,
                                     const CheckOptions& options, render::Renderer& renderer,
                                     const render::Fingerprint& fingerprint);

// The same without images: each checkpoint's state hash against the
// golden's, nothing rendered (no GL), so that it runs anywhere, fast (under
// an emulated CPU: tests/portability). Writes no goldens (InputError when
// options.update asks to).
std::vector<SceneCheck> check_physics(const std::vector<std::string>& scenes, const std::vector<Override>& overrides,
                                      const CheckOptions& options);

}  // namespace scenes
