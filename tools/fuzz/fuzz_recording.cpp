// libFuzzer target: the bytes of a recording through its reader, then the
// scene it replays, each stored state restored into that scene's World and
// stepped a frame (what a replay and the viewer's seek do). A recording
// either reads and replays, or is refused with an InputError (exit 2);
// everything else is a finding, as for fuzz_scene.cpp.
#include "scenes/model/recording.h"
#include "sim/state_hash.h"
#include "sim/world.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace {

// The END section's checksum made good when the input ends in one, so that
// mutations reach the sections' readers, not only the checksum's test.
void fix_checksum(std::string& b) {
    constexpr std::size_t kEnd = 4 + 8 + 8;  // tag, length, FNV-1a
    if (b.size() < 16 + kEnd || b.compare(b.size() - kEnd, 4, "END ") != 0) return;
    sim::Fnv1a h;
    h.add(b.data(), b.size() - kEnd);
    for (int k = 0; k < 8; ++k) b[b.size() - 8 + static_cast<std::size_t>(k)] = static_cast<char>(h.value() >> (8 * k));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    fix_checksum(bytes);
    std::optional<scenes::SceneDef> scene;
    scenes::Recording rec;
    try {
        rec = scenes::parse_recording(bytes, "fuzz.rec");
        scene = scenes::scene_of(rec, "fuzz.rec");
    } catch (const sim::InputError&) {
        return 0;  // refused with a message: what bad input should get
    }
    sim::World world(scene->model);
    world.set_watchdog(scene->watchdog);
    for (const auto& [frame, state] : rec.states) {
        try {
            world.restore(state);
        } catch (const sim::InputError&) {
            continue;
        }
        if (!world.verdict().exploded()) world.step(scene->step);
    }
    return 0;
}
