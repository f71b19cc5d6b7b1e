// SceneRun's snapshots (scenes/draw/scene_run.cpp): what the viewer's step
// back stores every step, and what it puts back.
#include "scenes/draw/scene_run.h"

#include "scenes/model/scene.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace {

std::vector<std::vector<render::Vec3>> ribbons_of(const scenes::SceneRun& run) {
    std::vector<std::vector<render::Vec3>> out;
    for (const render::Ribbon& r : run.draw_list(320, 180).ribbons) out.push_back(r.points);
    return out;
}

// The orbit keeps a trail behind its planet: frame 40's state and trail come
// back exactly after 30 more frames (the same state hash, the same ribbon
// points, frame 70's trail gone), and stepping on from there repeats frames
// 41 to 70 bit for bit.
TEST(SceneRunSnapshot, RestoresTheStateAndTheTrailsExactly) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("orbit"));
    ASSERT_GT(scene.view.trail_frames, 0) << "the orbit scene should keep a trail";
    scenes::SceneRun run(scene);
    for (int k = 0; k < 40; ++k) run.advance();
    const scenes::SceneRun::Snapshot at40 = run.snapshot();
    const auto ribbons40 = ribbons_of(run);
    const std::string hash40 = run.state_hash_hex();
    ASSERT_FALSE(ribbons40.empty());
    ASSERT_GE(ribbons40.front().size(), 2u);

    for (int k = 0; k < 30; ++k) run.advance();
    const auto ribbons70 = ribbons_of(run);
    const std::string hash70 = run.state_hash_hex();
    ASSERT_NE(ribbons70, ribbons40);

    run.restore(at40);
    EXPECT_EQ(run.frame(), 40);
    EXPECT_EQ(run.state_hash_hex(), hash40);
    EXPECT_EQ(ribbons_of(run), ribbons40);
    for (int k = 0; k < 30; ++k) run.advance();
    EXPECT_EQ(run.state_hash_hex(), hash70);
    EXPECT_EQ(ribbons_of(run), ribbons70);
}

// A snapshot holds the trails as two arrays: its size for the history's
// budget counts each stored point (12 bytes) and one end a particle, nothing
// a particle besides (a deque per particle cost 576 bytes each, empty).
TEST(SceneRunSnapshot, BytesCountTheTrailPointsAndOneEndAParticle) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene("orbit"));
    scenes::SceneRun run(scene);
    const scenes::SceneRun::Snapshot first = run.snapshot();
    for (int k = 0; k < 10; ++k) run.advance();
    const scenes::SceneRun::Snapshot later = run.snapshot();
    const std::size_t particles = scene.model.particles.size();
    EXPECT_EQ(later.trail_ends.size(), particles);
    ASSERT_GT(later.trail_points.size(), first.trail_points.size());
    EXPECT_EQ(later.bytes() - first.bytes(),
              sizeof(render::Vec3) * (later.trail_points.size() - first.trail_points.size()))
        << "10 more frames add only their trail points";
}

}  // namespace
