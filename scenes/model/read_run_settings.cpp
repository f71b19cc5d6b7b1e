// The loader's reader of how a scene runs: frames and checkpoints (how long,
// and which frames the golden filmstrip shows), [step] (integrator, dt,
// substeps) and [watchdog] (what counts as an explosion).
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

void read_timing(SceneBuilder& b, const Section& top) {
    SceneDef& scene = b.scene;
    scene.frames = static_cast<int>(top.integer("frames", 600, 1, kMaxFrames));
    const toml::node* n = top.node("checkpoints");
    if (n == nullptr) {
        for (int k = 0; k <= 3; ++k) scene.checkpoints.push_back(scene.frames * k / 3);
        return;
    }
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty() || a->size() > kMaxCheckpoints) {
        top.fail("checkpoints", "must be an array of 1 .. " + std::to_string(kMaxCheckpoints) + " frame numbers (got " +
                                    describe(*n) + ")");
    }
    for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::node& e = *a->get(i);
        // as_integer, not value<long long>: toml++ converts a float such as
        // 1e308 to an integer by a cast, undefined out of range (the fuzzer's find).
        const auto* f = e.as_integer();
        if (f == nullptr || f->get() < 0 || f->get() > scene.frames ||
            (!scene.checkpoints.empty() && *f <= scene.checkpoints.back())) {
            b.r.fail(&e, "checkpoints[" + std::to_string(i) + "] must be an integer frame within 0 .. frames (" +
                             std::to_string(scene.frames) + "), ascending (got " + describe(e) + ")");
        }
        scene.checkpoints.push_back(static_cast<int>(f->get()));
    }
}

void read_step(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("step");
    if (t == nullptr) return;
    const Section s(b.r, *t, "step");
    s.only(keys::step);
    sim::StepSettings& step = b.scene.step;
    if (s.node("integrator") != nullptr) {
        const std::string name = s.string("integrator", "");
        const auto id = sim::integrator_from_name(name);
        if (!id) s.fail("integrator", "must be one of " + sim::integrator_names() + " (got " + quote(name) + ")");
        step.integrator = *id;
    }
    step.dt = s.positive("dt", step.dt, 10.0, "s");
    step.substeps = static_cast<int>(s.integer("substeps", 1, 1, kMaxSubsteps));
}

namespace {

// A contained explosion is frozen where the rope was before it: a rope that
// starts outside the world box would be frozen outside it, again and again.
void refuse_contained_outside(const SceneBuilder& b) {
    const sim::WatchdogLimits& w = b.scene.watchdog;
    if (!w.enabled) return;
    for (const Section& s : b.contained_ropes) {
        const sim::RopeDef d;
        for (const auto& [key, fallback] : {std::pair{"start", d.start}, std::pair{"end", d.end}}) {
            const sim::Vec3 x = s.vec3(key, fallback, "m");
            if (x.cwiseAbs().maxCoeff() <= w.world_half_extent) continue;
            s.fail(key, "= [" + sim::format_value(x.x()) + ", " + sim::format_value(x.y()) + ", " +
                            sim::format_value(x.z()) + "] is outside the world box (watchdog.world_half_extent = " +
                            sim::format_value(w.world_half_extent) +
                            " m): a rope with contain_explosion = true must start inside it");
        }
    }
}

}  // namespace

void read_watchdog(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("watchdog");
    if (t == nullptr) return refuse_contained_outside(b);
    const Section s(b.r, *t, "watchdog");
    s.only(keys::watchdog);
    sim::WatchdogLimits& w = b.scene.watchdog;
    w.enabled = s.boolean("enabled", w.enabled);
    w.max_speed = s.positive("max_speed", w.max_speed, kHuge, "m/s");
    w.world_half_extent = s.positive("world_half_extent", w.world_half_extent, kHuge, "m");
    w.energy_growth = s.number("energy_growth", w.energy_growth, 0.0, kHuge, "(a factor; 0 is off)");
    if (w.energy_growth != 0.0 && w.energy_growth < 1.0) {
        s.fail("energy_growth", "must be 0 (off) or >= 1 (got " + sim::format_value(w.energy_growth) + ")");
    }
    w.energy_floor = s.positive("energy_floor", w.energy_floor, kHuge, "J");
    refuse_contained_outside(b);
}

}  // namespace scenes::loader
