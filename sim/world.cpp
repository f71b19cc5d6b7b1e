#include "sim/world.h"

#include "sim/cpu.h"
#include "sim/error.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

namespace sim {

void validate(const ParticleModel& model) {
    validate_particles(model.particles);
    validate_forces(model.forces, model.particles.size());
    validate(model.constraints, model.particles.size());
    validate(model.collisions);
    for (std::size_t k = 0; k < model.emitters.size(); ++k) validate(model.emitters[k], model.particles.size(), k);
}

void refuse_step_settings(const StepSettings& settings) {
    if (!(settings.dt > 0.0) || !std::isfinite(settings.dt)) {
        throw InputError("dt must be > 0 and finite, in s (got " + format_value(settings.dt) + ")");
    }
    throw InputError("substeps must be >= 1 (got " + std::to_string(settings.substeps) + ")");
}

namespace {

ParticleModel validated(ParticleModel model) {
    validate(model);
    return model;
}

}  // namespace

Systems systems_of(const ParticleModel& model, const WatchdogLimits& watchdog) {
    Systems s;
    s.particles = !model.particles.empty();
    for (const ForceDef& f : model.forces) {
        if (const auto* springs = std::get_if<Springs>(&f)) {
            s.springs = true;
            s.plasticity = s.plasticity || (springs->plasticity.enabled() && !springs->list.empty());
        }
    }
    s.constraints = !model.constraints.empty();
    // Particles collide with the colliders, each other, and (one way) the
    // rigid bodies (which meet the colliders inside ODE).
    s.collisions = s.particles && (!model.collisions.empty() || !model.rigid.empty());
    s.emitters = !model.emitters.empty();
    s.rigid = !model.rigid.empty();
    s.watchdog = watchdog.enabled;
    return s;
}

namespace {

// The systems in stage order, each once: its name, its flag in Systems and
// its time in SystemTimes.
struct SystemEntry {
    std::string_view name;
    bool Systems::*present;
    double World::SystemTimes::*seconds;
};
constexpr SystemEntry kSystems[] = {
    {"particles", &Systems::particles, &World::SystemTimes::particles},
    {"springs", &Systems::springs, &World::SystemTimes::springs},
    {"constraints", &Systems::constraints, &World::SystemTimes::constraints},
    {"collisions", &Systems::collisions, &World::SystemTimes::collisions},
    {"plasticity", &Systems::plasticity, &World::SystemTimes::plasticity},
    {"emitters", &Systems::emitters, &World::SystemTimes::emitters},
    {"rigid", &Systems::rigid, &World::SystemTimes::rigid},
    {"watchdog", &Systems::watchdog, &World::SystemTimes::watchdog},
};

}  // namespace

double World::SystemTimes::of(std::string_view system) const {
    for (const SystemEntry& e : kSystems) {
        if (e.name == system) return this->*e.seconds;
    }
    throw InputError("no system named '" + std::string(system) + "'");
}

std::vector<std::string> Systems::names() const {
    std::vector<std::string> out;
    for (const SystemEntry& e : kSystems) {
        if (this->*e.present) out.emplace_back(e.name);
    }
    return out;
}

World::World(ParticleModel model)
    : model_(validated(std::move(model))),
      state_(make_state(model_.particles)),
      live_forces_(model_.forces),
      forces_(live_forces_, state_.mass, state_.inv_mass) {
    scratch_.resize(kMaxScratch);
    rest0_.resize(live_forces_.size());
    for (std::size_t k = 0; k < live_forces_.size(); ++k) {
        if (const auto* springs = std::get_if<Springs>(&live_forces_[k]); springs && springs->plasticity.enabled()) {
            for (const Spring& sp : springs->list) rest0_[k].push_back(sp.rest);
        }
    }
    if (!model_.rigid.empty()) {
        rigid_ = std::make_unique<RigidWorld>(model_.rigid);
        // One static world: what particles collide with, bodies collide with too.
        for (const Collider& c : model_.collisions.colliders) rigid_->add_static(c);
    }
    radius_.reserve(model_.particles.size());
    for (const ParticleDef& p : model_.particles) radius_.push_back(p.radius);
    systems_ = systems_of(model_, watchdog_);
    refresh_bare();
    initial_energy_ = energy();
    set_wide(true);
}

void World::refresh_bare() {
    bare_ = watchdog_.enabled && !systems_.emitters && !systems_.constraints && !systems_.collisions &&
            !systems_.plasticity && !rigid_ && watchdog_.contain.empty() &&
            !(drag_ && drag_->kind == Drag::Kind::particle) && !substep_observer_;
}

void World::set_wide(bool wide) {
    wide_ = wide && avx2_available();
    forces_.set_wide(wide_);
    prepared_.info = nullptr;
}

void World::set_watchdog(const WatchdogLimits& limits) {
    validate(limits);
    for (const ContainedRange& r : limits.contain) {
        if (static_cast<std::size_t>(r.first) + r.count > state_.size()) {
            throw InputError("watchdog.contain (" + r.name + ") covers particles up to " +
                             std::to_string(static_cast<std::size_t>(r.first) + r.count) + ", but there are only " +
                             std::to_string(state_.size()));
        }
    }
    watchdog_ = limits;
    systems_.watchdog = limits.enabled;
    refresh_bare();
    initial_energy_ = energy();
}

ParticleState& World::edit_state() {
    memory_valid_ = false;
    prepared_.info = nullptr;  // the caller may move arrays
    forces_.masses_changed();  // and write masses
    return state_;
}

void World::set_drag(const std::optional<Drag>& drag) {
    if (drag) {
        const Drag& d = *drag;
        if (!d.anchor.allFinite() || !d.target.allFinite() || !std::isfinite(d.frequency) || d.frequency <= 0.0 ||
            !std::isfinite(d.damping_ratio) || d.damping_ratio < 0.0) {
            throw InputError("drag: anchor and target must be finite, frequency > 0 Hz, damping ratio >= 0 (got " +
                             format_value(d.frequency) + " Hz, " + format_value(d.damping_ratio) + ")");
        }
        if (d.kind == Drag::Kind::particle) {
            if (d.index >= state_.size())
                throw InputError("drag: no particle " + std::to_string(d.index) + " (the world has " +
                                 std::to_string(state_.size()) + ")");
            if (state_.inv_mass[d.index] == 0.0)
                throw InputError("drag: particle " + std::to_string(d.index) + " is pinned");
        } else if (!rigid_ || d.index >= model_.rigid.bodies.size()) {
            throw InputError("drag: no rigid body " + std::to_string(d.index));
        }
    }
    drag_ = drag;
    refresh_bare();
}

void World::apply_drag(double h) {
    const Drag& d = *drag_;
    const double w = 2.0 * std::numbers::pi * d.frequency;  // rad/s
    // The spring's stretch saturates at kMaxStretch: a flick across the room
    // pulls as hard as a 1 m one, so the speed it gives stays near w · 1 m.
    constexpr double kMaxStretch = 1.0;  // m
    auto saturated = [](Vec3 pull) {
        return pull.norm() > kMaxStretch ? Vec3(pull * (kMaxStretch / pull.norm())) : pull;
    };
    if (d.kind == Drag::Kind::particle) {
        // A particle the watchdog froze (contained) since it was grabbed: let go.
        if (state_.inv_mass[d.index] == 0.0) return;
        // x'' = w² (target - x) - 2 ζ w x' per unit mass, backward Euler over
        // the substep: v1 (1 + 2ζw h + w² h²) = v0 + w² h (target - x0). The
        // velocity change is the spring's impulse; the integrator adds the rest.
        const Vec3 x = state_.x.get(d.index), v = state_.v.get(d.index);
        const Vec3 v1 =
            (v + w * w * h * saturated(d.target - x)) / (1.0 + 2.0 * d.damping_ratio * w * h + w * w * h * h);
        state_.v.set(d.index, v1);
        memory_valid_ = false;
        // The work the mouse did (the impulse's kinetic energy) moves the
        // watchdog's E0 with it: energy put in by hand is not an explosion.
        initial_energy_ += 0.5 * state_.mass[d.index] * (v1.squaredNorm() - v.squaredNorm());
        return;
    }
    // A body: the same spring, explicit, on the grabbed point, with the
    // body's mass; capped at 30 g per kg so that a lost grip cannot fling it.
    const BodyId id{d.index, 0};
    const BodyState b = rigid_->state(id);
    const Vec3 point = b.position + b.orientation * d.anchor;
    const Vec3 point_velocity = b.velocity + b.angular_velocity.cross(point - b.position);
    const double m = rigid_->mass(id);
    Vec3 force = m * (w * w * saturated(d.target - point) - 2.0 * d.damping_ratio * w * point_velocity);
    const double cap = 30.0 * 9.81 * m;  // N
    if (force.norm() > cap) force *= cap / force.norm();
    rigid_->add_force_at(id, force, point);
    initial_energy_ += force.dot(point_velocity) * h;  // J, the force's work over the substep (E0 follows it)
}

World::Snapshot World::snapshot() const {
    Snapshot snap{.state = state_,
                  .memory_a = memory_a_,
                  .memory_x_prev = memory_x_prev_,
                  .memory_valid = memory_valid_,
                  .memory_integrator = memory_integrator_,
                  .memory_h = memory_h_,
                  .steps = steps_,
                  .frames = frames_,
                  .initial_energy = initial_energy_,
                  .verdict = verdict_};
    for (std::size_t k = 0; k < live_forces_.size(); ++k) {
        if (rest0_[k].empty()) continue;
        for (const Spring& sp : std::get<Springs>(live_forces_[k]).list) snap.plastic_rest.push_back(sp.rest);
    }
    snap.contained = contained_;
    if (rigid_) {
        snap.bodies = rigid_->body_states();
        snap.rigid_steps = rigid_->steps();
    }
    return snap;
}

void World::restore(const Snapshot& snapshot) {
    if (snapshot.state.size() != state_.size()) {
        throw InputError("snapshot has " + std::to_string(snapshot.state.size()) + " particles, the world has " +
                         std::to_string(state_.size()));
    }
    // The rest checked before anything changes (a snapshot read from a file may be anything).
    const std::size_t n = state_.size();
    std::size_t plastic = 0;
    for (const auto& rest : rest0_) plastic += rest.size();
    if (snapshot.state.x.size() != n || snapshot.state.v.size() != n || snapshot.state.inv_mass.size() != n ||
        snapshot.plastic_rest.size() != plastic ||
        snapshot.bodies.size() != (rigid_ ? rigid_->bodies().size() : std::size_t{0})) {
        throw InputError("snapshot's arrays do not fit the world (" + std::to_string(n) + " particles, " +
                         std::to_string(plastic) + " plastic springs, " +
                         std::to_string(rigid_ ? rigid_->bodies().size() : 0) + " rigid bodies)");
    }
    state_ = snapshot.state;
    prepared_.info = nullptr;
    forces_.masses_changed();
    memory_a_ = snapshot.memory_a;
    memory_x_prev_ = snapshot.memory_x_prev;
    memory_valid_ = snapshot.memory_valid;
    memory_integrator_ = snapshot.memory_integrator;
    memory_h_ = snapshot.memory_h;
    steps_ = snapshot.steps;
    frames_ = snapshot.frames;
    next_sample_ = frames_ + 1;  // timings are not rewound; sampling starts again from here
    unsampled_.since_frame = 0;  // (frames_ went back: no stretch to the next sample)
    initial_energy_ = snapshot.initial_energy;
    verdict_ = snapshot.verdict;
    contained_ = snapshot.contained;
    if (rigid_) rigid_->set_body_states(snapshot.bodies, snapshot.rigid_steps);
    std::size_t next = 0;
    for (std::size_t k = 0; k < live_forces_.size(); ++k) {
        if (rest0_[k].empty()) continue;
        for (Spring& sp : std::get<Springs>(live_forces_[k]).list) sp.rest = snapshot.plastic_rest[next++];
    }
}

namespace {

using Clock = std::chrono::steady_clock;

// The cost of one clock read as two reads in a row see it, s: the median of
// a few hundred pairs, measured once per process (about 25 ns here).
double clock_read_cost() {
    static const double cost = [] {
        std::array<double, 301> pairs;
        for (double& d : pairs) {
            const auto a = Clock::now();
            const auto b = Clock::now();
            d = std::chrono::duration<double>(b - a).count();
        }
        std::nth_element(pairs.begin(), pairs.begin() + pairs.size() / 2, pairs.end());
        return pairs[pairs.size() / 2];
    }();
    return cost;
}

// A sampled frame's stopwatch: reads the clock after each stage and adds the
// interval since the last read, less the cost of a read, to that stage.
class FrameClock {
public:
    FrameClock() : read_cost_(clock_read_cost()), start_(Clock::now()), last_(start_) {}
    void lap(double& total) {
        const auto now = Clock::now();
        total += std::max(0.0, std::chrono::duration<double>(now - last_).count() - read_cost_);
        last_ = now;
        ++reads_;
    }
    // Ends the frame with a last read (after the last stage, nothing is timed).
    void finish() {
        last_ = Clock::now();
        ++reads_;
    }
    // The whole frame, s (less the reads inside it), and what the reads cost, s.
    double elapsed() const {
        return std::max(0.0, std::chrono::duration<double>(last_ - start_).count() - reads_ * read_cost_);
    }
    double cost() const { return (reads_ + 1) * read_cost_; }
    double read_cost() const { return read_cost_; }  // s, one clock read
    Clock::time_point start() const { return start_; }
    Clock::time_point end() const { return last_; }  // after finish()

private:
    double read_cost_;
    Clock::time_point start_, last_;
    int reads_ = 0;
};

// A frame that is not sampled reads no clock.
struct NoClock {
    void lap(double&) {}
};

}  // namespace

// step()'s common case, a bare World's step of one substep in a frame that
// is not sampled (run_substeps' first case, without the
// clocks). Out of line, so that step() is small enough to inline: its call
// and the pushes of the registers the general step needs cost velocity
// Verlet's bead a fortieth of its instructions (329 -> 321 a step).
void World::step_bare(Integrator integrator, double h) {
    step_once(integrator, h, true);
    watch();
}

void World::step_frame(const StepSettings& settings) {
    if (frames_ < next_sample_) {
        NoClock none;
        run_substeps(settings, none);
        return;
    }
    const std::uint64_t steps_before = steps_;
    ParticleForces::SpringTime springs;
    if (systems_.springs) forces_.time_springs(&springs);
    FrameClock laps;
    run_substeps(settings, laps);
    laps.finish();
    if (systems_.springs) forces_.time_springs(nullptr);
    // The spring passes ran inside the particles' laps: their time moves from
    // there to springs. Each pass's interval holds about one of its two clock
    // reads; all of them count as the clocks' cost, not as physics.
    const double spring_reads = springs.reads * laps.read_cost();  // s
    const double spring_seconds = std::max(0.0, springs.seconds - 0.5 * spring_reads);
    times_.springs += spring_seconds;
    times_.particles = std::max(0.0, times_.particles - spring_seconds - spring_reads);
    times_.total += std::max(0.0, laps.elapsed() - spring_reads);
    timer_cost_ += laps.cost() + spring_reads;
    ++times_.sampled_frames;
    times_.sampled_steps += steps_ - steps_before;
    // The frames since the last sampled one ran untimed: what they took.
    if (unsampled_.since_frame != 0 && frames_ > unsampled_.since_frame + 1) {
        unsampled_.seconds += std::chrono::duration<double>(laps.start() - unsampled_.since).count();
        unsampled_.frames += frames_ - unsampled_.since_frame - 1;
    }
    unsampled_.since = laps.end();
    unsampled_.since_frame = frames_;
    plan_next_sample();
}

void World::plan_next_sample() {
    constexpr double kTimerShare = 0.01;  // the clocks' cost at most this share of the frames' time
    // The next frame at which the clocks will have cost kTimerShare of the
    // time the frames took. A frame's time: the untimed frames' mean, as the
    // stretches between the sampled ones measure it, or the sampled frames'
    // own mean where that is less. A small step reads longer when it is
    // sampled (the clock reads stop its overlap with its neighbours: a
    // bead's step of 19 ns reads 45-90 ns; sampled by that figure, one frame
    // in 130-180, sampling cost 5-7% of the run, against 1-2% now). A stretch
    // can hold more than frames (the caller's work between steps, a
    // preemption, a first run's page faults): the sampled frames' mean,
    // which every sample updates, bounds it then.
    const double sampled = times_.total / static_cast<double>(times_.sampled_frames);  // s
    const double frame = unsampled_.frames > 0
                             ? std::min(sampled, unsampled_.seconds / static_cast<double>(unsampled_.frames))
                             : sampled;  // s
    const double frames = timer_cost_ / (kTimerShare * std::max(frame, 1e-12));
    next_sample_ = std::max(frames_ + 1, static_cast<std::uint64_t>(std::min(frames, 1e18)));
}

template <class Stopwatch>
void World::run_substeps(const StepSettings& settings, Stopwatch& laps) {
    // (One substep: h is dt, not dt / 1, which is the same bits and no
    // division: its latency held up the whole of a small step, every stage
    // waiting on h.)
    const double h = settings.substeps == 1 ? settings.dt : settings.dt / settings.substeps;
    // The common step of a bare World (bare_), of one substep:
    // the loop below without the stages it would skip, one test instead of a
    // dozen, which on the smallest systems (the report's single copies) is
    // a seventh of velocity Verlet's instructions (402 -> 345 a step). An
    // unsampled frame's never gets here: step() calls step_bare.
    if (bare_ && settings.substeps == 1) {
        step_once(settings.integrator, h, true);
        laps.lap(times_.particles);
        watch();
        laps.lap(times_.watchdog);
        return;
    }
    const bool constrained = systems_.constraints, colliding = systems_.collisions, plastic = systems_.plasticity;
    for (int i = 0; i < settings.substeps && !verdict_.exploded(); ++i) {
        if (systems_.emitters) {
            for (const Emitter& emitter : model_.emitters) {
                if (emit(emitter, state_.t, state_.t + h, state_) > 0) {
                    memory_valid_ = false;
                    // (Births only unpin, so a fan found of one mass stays so;
                    // said anyway, so that every write of a mass is.)
                    forces_.masses_changed();
                }
            }
            laps.lap(times_.emitters);
        }
        // Continuous collision detection sweeps from here; a contained explosion freezes here.
        if (colliding || !watchdog_.contain.empty()) x_start_ = state_.x;
        if (drag_ && drag_->kind == Drag::Kind::particle) apply_drag(h);
        // Forces and integration; when no later stage moves a particle, the
        // watchdog's per-particle rules run block by block inside it.
        step_once(settings.integrator, h, watchdog_.enabled && !constrained && !colliding);
        laps.lap(times_.particles);
        if (constrained) {
            solve_constraints(h);
            laps.lap(times_.constraints);
        }
        if (colliding) {
            if (rigid_) update_body_colliders();
            if (collide(model_.collisions, x_start_.span(), state_.x.span(), state_.v.span(), radius_.data(),
                        state_.inv_mass.data(), h, collision_scratch_, body_colliders_) > 0) {
                memory_valid_ = false;  // positions and velocities were edited
            }
            laps.lap(times_.collisions);
        }
        if (plastic) {
            plasticity(h);
            laps.lap(times_.plasticity);
        }
        if (rigid_) {
            if (drag_ && drag_->kind == Drag::Kind::body) apply_drag(h);
            rigid_->step(h);
            laps.lap(times_.rigid);
        }
        if (watchdog_.enabled || rigid_) {  // bodies past ODE's reach stop the run even without it
            watch();
            laps.lap(times_.watchdog);
        }
        if (substep_observer_) substep_observer_(i);
    }
}

void World::update_body_colliders() {
    body_colliders_.clear();
    for (const PlacedPart& part : rigid_->placed_parts()) {
        const BodyState body = rigid_->state(part.body);
        MovingCollider m{SphereCollider{part.center, part.size.x()}, body.velocity, body.angular_velocity,
                         body.position, 0.0};
        double bound = part.size.x();  // m, the part's extent from its centre
        switch (part.shape) {
            case RigidShape::sphere:
                break;
            case RigidShape::box:
                m.shape = BoxCollider{part.center, 0.5 * part.size, part.orientation.toRotationMatrix()};
                bound = 0.5 * part.size.norm();
                break;
            case RigidShape::capsule:
            case RigidShape::cylinder: {  // a cylinder collides with particles as the capsule around it
                const Vec3 half = part.orientation * Vec3(0, 0, 0.5 * part.size.y());
                m.shape = CapsuleCollider{part.center - half, part.center + half, part.size.x()};
                bound = 0.5 * part.size.y() + part.size.x();
                break;
            }
        }
        m.reach = (part.center - body.position).norm() + bound;
        body_colliders_.push_back(m);
    }
}

void World::watch_closely() {
    // Each pass contains a range not yet contained in this call, or returns:
    // a range frozen where it is still outside the limits stops the run.
    std::vector<const ContainedRange*> frozen;
    for (;;) {
        // The energy rule costs a potential-energy pass: only when asked for.
        const double e = watchdog_.energy_growth > 0.0 ? energy() : 0.0;
        verdict_ = check(watchdog_, state_, e, initial_energy_, frames_, watched_suspects_);
        watched_suspects_.reset();  // a contained range changes the state: look again in full
        if (!verdict_.exploded() && rigid_) {
            std::vector<Vec3> positions, velocities, angular_velocities;
            for (const BodyState& b : rigid_->body_states()) {
                positions.push_back(b.position);
                velocities.push_back(b.velocity);
                angular_velocities.push_back(b.angular_velocity);
            }
            verdict_ = check_bodies(watchdog_, positions, velocities, frames_, angular_velocities);
            return;  // bodies are never contained
        }
        if (!verdict_.exploded() || verdict_.quantity == "energy") return;
        const auto range = std::find_if(watchdog_.contain.begin(), watchdog_.contain.end(), [&](const auto& r) {
            return verdict_.index >= r.first && verdict_.index < r.first + r.count;
        });
        if (range == watchdog_.contain.end()) return;
        if (std::find(frozen.begin(), frozen.end(), &*range) != frozen.end()) return;
        frozen.push_back(&*range);
        // Contained: freeze the range where it was before this substep (finite,
        // within the limits), pinned and at rest, and look again.
        contained_.push_back({range->name, verdict_});
        for (std::uint32_t i = range->first; i < range->first + range->count; ++i) {
            state_.x.set(i, x_start_.get(i));
            state_.v.set(i, Vec3::Zero());
            state_.inv_mass[i] = 0.0;
        }
        memory_valid_ = false;
        prepared_.info = nullptr;  // the blocks now hold pinned particles
        forces_.masses_changed();
        verdict_ = {};
    }
}

void World::solve_constraints(double h) {
    // XPBD after any integrator: the integrator predicted x; the projection
    // moves it by Δx; the velocity takes the same correction, v += Δx / h.
    // With symplectic Euler this is exactly XPBD's v = (x_new - x_old) / h.
    x_predicted_ = state_.x;
    project(model_.constraints, state_.x.span(), state_.inv_mass.data(), h, lambda_);
    const double inv_h = 1.0 / h;
    for (int k = 0; k < 3; ++k) {
        const double* xp = x_predicted_.span().c[k];
        const double* x = state_.x.span().c[k];
        double* v = state_.v.span().c[k];
        for (std::size_t i = 0; i < state_.size(); ++i) v[i] += (x[i] - xp[i]) * inv_h;
    }
    memory_valid_ = false;  // the integrator's cached acceleration or x_prev no longer matches x
}

void World::plasticity(double h) {
    for (std::size_t k = 0; k < live_forces_.size(); ++k) {
        if (!rest0_[k].empty()) apply_plasticity(std::get<Springs>(live_forces_[k]), rest0_[k], state_.x.span(), h);
    }
}

void World::prepare_step(Integrator integrator) {
    const IntegratorInfo& info = integrator_info(integrator);
    const std::size_t n = state_.size();
    // Scratch is allocated for the largest block the method will see (the
    // arrays below scratch_arrays_ already hold scratch_block_ particles);
    // a method that steps a uniform field in one pass takes the system as
    // one block and uses none.
    const UniformField* field = forces_.uniform_field();
    const bool one_pass = field != nullptr && steps_in_one_pass(integrator, *field);
    const std::size_t block = forces_.all_local() && !one_pass ? std::min(n, kBlock) : n;
    if (!one_pass && (info.scratch_arrays > scratch_arrays_ || block > scratch_block_)) {
        scratch_arrays_ = std::max(scratch_arrays_, info.scratch_arrays);
        scratch_block_ = std::max(scratch_block_, block);
        for (std::size_t i = 0; i < scratch_arrays_; ++i) scratch_[i].resize(scratch_block_);
    }
    // Integrator memory is allocated the first time a method that keeps it runs.
    const bool two = info.memory == Memory::two_accelerations;
    Vec3Array* memory = info.memory == Memory::acceleration || two ? &memory_a_
                        : info.memory == Memory::previous_position ? &memory_x_prev_
                                                                   : nullptr;
    if (memory != nullptr && memory->size() != n) memory->resize(n);
    if (two && memory_a_next_.size() != n) memory_a_next_.resize(n);
    // Pinned particles: edit_state and restore prepare again, and so does a
    // contained range (it pins); an emitter's birth only unpins, which leaves
    // a false "no" here, the safe side.
    const bool none_pinned =
        std::none_of(state_.inv_mass.begin(), state_.inv_mass.end(), [](double w) { return w == 0.0; });
    prepared_ = {.info = &info,
                 .n = n,
                 .block = block,
                 .none_pinned = none_pinned,
                 .pair = n == 2 ? forces_.pair_path(2) : PairPath{}};
    if (n > 0 && n <= block) prepared_.whole = block_arrays(info, 0, n);
}

StepArrays World::block_arrays(const IntegratorInfo& info, std::size_t first, std::size_t count) {
    return {.first = first,
            .x = state_.x.span().block(first, count),
            .v = state_.v.span().block(first, count),
            .a = info.memory == Memory::acceleration || info.memory == Memory::two_accelerations
                     ? memory_a_.span().block(first, count)
                     : Vec3Span{},
            .a_next = info.memory == Memory::two_accelerations ? memory_a_next_.span().block(first, count) : Vec3Span{},
            .x_prev = info.memory == Memory::previous_position ? memory_x_prev_.span().block(first, count) : Vec3Span{},
            .memory_valid = false,
            .temporaries = scratch_.data(),
            .wide = wide_,
            .none_pinned = prepared_.none_pinned,
            .watch = nullptr,
            .pair = &prepared_.pair};
}

// One block's step; the suspects the watchdog's per-particle rules found in
// it (0 unless watch_blocks): inside a fused pass where the method has one,
// else in a pass of their own, while the block is still in cache.
std::size_t World::step_block(const IntegratorInfo& info, StepArrays& s, double h, bool watch_blocks, bool& taken) {
    StepArrays::Watch watch{watchdog_.max_speed * watchdog_.max_speed, watchdog_.world_half_extent};
    s.memory_valid = memory_valid_;
    s.watch = watch_blocks ? &watch : nullptr;
    s.a_next_taken = &taken;
    info.step(forces_, s, state_.t, h);
    s.watch = nullptr, s.a_next_taken = nullptr;  // (locals' addresses)
    if (!watch_blocks) return 0;
    return watch.counted ? watch.suspects : count_suspects(watchdog_, s.x, s.v);
}

std::size_t World::step_blocks(const IntegratorInfo& info, double h, bool watch_blocks, bool& taken) {
    std::size_t suspects = 0;
    const std::size_t n = state_.size();
    for (std::size_t first = 0; first < n; first += prepared_.block) {
        StepArrays s = block_arrays(info, first, std::min(prepared_.block, n - first));
        suspects += step_block(info, s, h, watch_blocks, taken);
    }
    return suspects;
}

// Inline in run_substeps: on a bead on a spring the call cost a tenth of
// the step (the blocks of a large system go through step_blocks).
[[gnu::always_inline]] inline void World::step_once(Integrator integrator, double h, bool watch_blocks) {
    if (memory_integrator_ != integrator || memory_h_ != h) memory_valid_ = false;
    const std::size_t n = state_.size();
    if (prepared_.info == nullptr || prepared_.info->id != integrator || prepared_.n != n) prepare_step(integrator);
    const IntegratorInfo& info = *prepared_.info;
    // One block (every small system): its arrays as prepare_step built them.
    bool taken = false;  // the method left the new acceleration in a_next (every block alike)
    const std::size_t suspects = n > 0 && n <= prepared_.block
                                     ? step_block(info, prepared_.whole, h, watch_blocks, taken)
                                     : step_blocks(info, h, watch_blocks, taken);
    if (taken) {
        std::swap(memory_a_, memory_a_next_);  // the vectors' buffers trade places: the spans follow by hand
        std::swap(prepared_.whole.a, prepared_.whole.a_next);
    }
    watched_suspects_ = watch_blocks ? std::optional<std::size_t>(suspects) : std::nullopt;

    state_.t += h;
    memory_valid_ = true;
    memory_integrator_ = integrator;
    memory_h_ = h;
    ++steps_;
}

Vec3Array World::net_forces() const {
    Vec3Array f(state_.size());
    forces_.net_force(state_.t, state_.x.span(), state_.v.span(), f.span());
    return f;
}

double World::kinetic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < state_.size(); ++i) {
        if (state_.inv_mass[i] != 0.0) {
            e += 0.5 * state_.mass[i] * state_.v.get(i).squaredNorm();
        }
    }
    if (rigid_) e += rigid_->kinetic_energy();
    return e;
}

double World::potential_energy() const {
    return forces_.potential_energy(state_.t, state_.x.span(), state_.v.span()) +
           sim::potential_energy(model_.constraints, state_.x.span()) + (rigid_ ? rigid_->potential_energy() : 0.0);
}

double World::force_evaluations() const {
    return state_.size() == 0
               ? 0.0
               : static_cast<double>(forces_.particle_evaluations()) / static_cast<double>(state_.size());
}

}  // namespace sim
