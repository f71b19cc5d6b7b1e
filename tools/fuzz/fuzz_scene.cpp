// libFuzzer target: the bytes of a scene file through the loader, then the
// World it describes for a few frames. What a scene file may do is the
// command's contract: load and run, or be refused with an InputError (the
// loader's SceneError, "file:line:column: ...", exit 2). Everything else is a
// finding: a crash, a sanitizer report, any other exception (exit 1), a run
// past libFuzzer's -timeout (a hang) or its -rss_limit_mb.
// Built by `make fuzz` and the `fuzz.smoke` test (tools/fuzz/run.sh), with
// clang, -fsanitize=fuzzer,address,undefined, from sim and the loader only.
#include "scenes/model/scene.h"
#include "sim/world.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace {

// Frames stepped per input: enough to run every stage of the step (emitters
// born, collisions, the watchdog's energy rule, rigid contacts) on what the
// loader built; more only slows the fuzzer down.
constexpr int kFrames = 3;

std::optional<scenes::SceneDef> load(std::string_view text) {
    try {
        return scenes::parse_scene(text, "fuzz.toml");
    } catch (const sim::InputError&) {
        return std::nullopt;  // refused with a message: what bad input should get
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::optional<scenes::SceneDef> scene = load({reinterpret_cast<const char*>(data), size});
    if (!scene) return 0;
    scenes::scene_parameters(*scene);  // the viewer's sliders read the same file
    sim::World world(scene->model);
    world.set_watchdog(scene->watchdog);
    for (int frame = 0; frame < std::min(kFrames, scene->frames) && !world.verdict().exploded(); ++frame) {
        world.step(scene->step);
        world.energy();  // what run, check and the HUD report each frame
    }
    // The closed forms `run` measures the error against, at the time reached.
    for (const scenes::Ghost& ghost : scene->ghosts) ghost.exact(world.state().t);
    return 0;
}
