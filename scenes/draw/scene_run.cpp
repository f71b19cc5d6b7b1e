// A run of a scene: stepping, the step settings, snapshots for the viewer's
// step back, the trails and the energy curve recorded after each step, and the
// state hash. What a frame shows is in draw_list.cpp.
#include "scenes/draw/scene_run.h"

#include "scenes/model/recording.h"
#include "sim/state_hash.h"

#include <cinttypes>
#include <cstdio>

namespace scenes {

SceneRun::SceneRun(const SceneDef& scene) : scene_(scene), step_(scene.step), world_(scene.model) {
    world_.set_watchdog(scene.watchdog);
    trails_.resize(scene.model.particles.size());
    record();
    compare_with_recording();
}

bool SceneRun::advance() {
    if (world_.verdict().exploded()) return false;
    world_.step(step_);
    ++frame_;
    record();
    compare_with_recording();
    return !world_.verdict().exploded();
}

void SceneRun::compare_with_recording() {
    const RecordedRun* rec = scene_.recorded.get();
    if (rec == nullptr || diverged_ >= 0 || frame_ >= static_cast<int>(rec->hashes.size())) return;
    if (state_hash() != rec->hashes[static_cast<std::size_t>(frame_)]) diverged_ = frame_;
}

bool SceneRun::seek(int frame) {
    const RecordedRun* rec = scene_.recorded.get();
    if (rec == nullptr || frame < 0 || frame >= static_cast<int>(rec->hashes.size())) return false;
    const std::pair<int, sim::World::Snapshot>* nearest = nullptr;  // the last stored state at or before it
    for (const auto& state : rec->states) {
        if (state.first <= frame) nearest = &state;
    }
    // Step on from where the run is, unless a stored state is nearer.
    const bool step_on = frame_ <= frame && (nearest == nullptr || frame_ >= nearest->first);
    if (!step_on) {
        if (nearest == nullptr) return false;
        world_.restore(nearest->second);
        frame_ = nearest->first;
        for (auto& trail : trails_) trail.clear();
        energy_.clear();
        record();
    }
    while (frame_ < frame && advance()) {
    }
    return frame_ == frame;
}

void SceneRun::set_step(const sim::StepSettings& step) {
    sim::validate(step);
    step_ = step;
}

SceneRun::Snapshot SceneRun::snapshot() const {
    Snapshot s{world_.snapshot(), frame_, {}, {}};
    std::size_t points = 0;
    for (const auto& trail : trails_) points += trail.size();
    s.trail_points.reserve(points);
    s.trail_ends.reserve(trails_.size());
    for (const auto& trail : trails_) {
        s.trail_points.insert(s.trail_points.end(), trail.begin(), trail.end());
        s.trail_ends.push_back(static_cast<std::uint32_t>(s.trail_points.size()));
    }
    return s;
}

std::size_t SceneRun::Snapshot::bytes() const {
    const sim::World::Snapshot& w = world;
    return sizeof(*this) + sizeof(double) * 3 * (2 * w.state.size() + w.memory_a.size() + w.memory_x_prev.size()) +
           sizeof(double) * (2 * w.state.size() + w.plastic_rest.size()) + sizeof(sim::BodyState) * w.bodies.size() +
           sizeof(render::Vec3) * trail_points.size() + sizeof(std::uint32_t) * trail_ends.size();
}

void SceneRun::restore(const Snapshot& snapshot) {
    world_.restore(snapshot.world);
    frame_ = snapshot.frame;
    std::uint32_t begin = 0;
    for (std::size_t i = 0; i < trails_.size() && i < snapshot.trail_ends.size(); ++i) {
        const auto first = snapshot.trail_points.begin() + begin;
        const auto last = snapshot.trail_points.begin() + snapshot.trail_ends[i];
        trails_[i].assign(first, last);
        begin = snapshot.trail_ends[i];
    }
    while (!energy_.empty() && energy_.back().x() > static_cast<float>(time()) + 1e-6f) energy_.pop_back();
}

void SceneRun::record() {
    if (scene_.view.energy_plot) energy_.emplace_back(static_cast<float>(time()), static_cast<float>(world_.energy()));
    if (scene_.view.trail_frames <= 0) return;
    const sim::ParticleState& s = world_.state();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.inv_mass[i] == 0.0) continue;
        auto& trail = trails_[i];
        trail.push_back(s.x.get(i).cast<float>());
        if (static_cast<int>(trail.size()) > scene_.view.trail_frames + 1) trail.pop_front();
    }
}

bool SceneRun::advance(std::vector<std::uint64_t>& substep_hashes) {
    substep_hashes.clear();
    world_.set_substep_observer([&](int) { substep_hashes.push_back(state_hash()); });
    const bool running = advance();
    world_.set_substep_observer({});
    return running;
}

std::vector<std::uint32_t> SceneRun::object_hashes(const std::vector<SceneObject>& objects) const {
    const sim::ParticleState& state = world_.state();
    const sim::RigidWorld* rigid = world_.rigid();
    std::vector<sim::BodyId> bodies;  // by model.rigid.bodies index (a removed body's stays invalid)
    for (const sim::BodyId id : rigid != nullptr ? rigid->bodies() : std::vector<sim::BodyId>{}) {
        if (id.index >= bodies.size()) bodies.resize(id.index + 1);
        bodies[id.index] = id;
    }
    std::vector<std::uint32_t> hashes;
    for (const SceneObject& object : objects) {
        sim::Fnv1a h;
        for (std::size_t i = object.first; i < object.first + object.count; ++i) {
            if (!object.rigid && i < state.size()) {
                for (const sim::Vec3& value : {state.x.get(i), state.v.get(i)}) {
                    for (int k = 0; k < 3; ++k) h.add(value[k]);
                }
            } else if (object.rigid && i < bodies.size() && bodies[i].index == i) {
                const sim::BodyState body = rigid->state(bodies[i]);
                for (const sim::Vec3& value : {body.position, body.velocity, body.angular_velocity}) {
                    for (int k = 0; k < 3; ++k) h.add(value[k]);
                }
                for (int k = 0; k < 4; ++k) h.add(body.orientation.coeffs()[k]);
            }
        }
        hashes.push_back(static_cast<std::uint32_t>(h.value()));
    }
    return hashes;
}

std::uint64_t SceneRun::state_hash() const {
    const std::uint64_t particles = sim::state_hash(world_.state());
    // Rigid bodies folded in, so that either part changing changes the hash.
    return world_.rigid() != nullptr ? sim::fold_hashes(particles, world_.rigid()->hash()) : particles;
}

std::string SceneRun::state_hash_hex() const {
    char text[32];
    std::snprintf(text, sizeof text, "%016" PRIx64, state_hash());
    return text;
}

}  // namespace scenes
