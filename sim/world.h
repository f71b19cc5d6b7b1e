// sim::World: a particle system's description (ParticleModel, fixed) and its
// state (ParticleState, stepped). A restart or a side-by-side comparison is
// another World built from the same model.
#pragma once

#include "sim/collisions.h"
#include "sim/constraints.h"
#include "sim/emitter.h"
#include "sim/forces.h"
#include "sim/integrators.h"
#include "sim/particles.h"
#include "sim/rigid.h"
#include "sim/watchdog.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace sim {

// What a particle system is: its particles, the forces acting on them, the
// constraints that hold them and what they collide with.
struct ParticleModel {
    std::vector<ParticleDef> particles;
    std::vector<ForceDef> forces;
    Constraints constraints;        // XPBD, solved after every integrator substep
    Collisions collisions;          // resolved after the constraints
    RigidModel rigid;               // rigid bodies and joints (ODE); none: no ODE world is made
    std::vector<Emitter> emitters;  // cosmetic particle sources (their particles start pinned, parked)
};

// Throws InputError for the first invalid particle or force.
void validate(const ParticleModel& model);

// How a frame advances: `substeps` steps of dt / substeps with one integrator.
// Substeps belong to the step, not to the integrator.
struct StepSettings {
    Integrator integrator = Integrator::symplectic_euler;
    double dt = 1.0 / 60.0;  // frame step, s (> 0 and finite)
    int substeps = 1;        // steps per frame step (>= 1)
};

// Throws InputError when dt <= 0 or not finite, or substeps < 1. Inline: it
// runs at every step (a call cost a bead-on-a-spring step a tenth of its time).
[[noreturn]] void refuse_step_settings(const StepSettings& settings);
inline void validate(const StepSettings& settings) {
    if (!(settings.dt > 0.0) || !std::isfinite(settings.dt) || settings.substeps < 1) refuse_step_settings(settings);
}

// The viewer's mouse (the control-force hook): a damped spring pulling one
// particle, or one point of a rigid body, towards a target. Scaled by the
// mass, so that it feels the same on a 1 g bead and a 70 kg ragdoll: the
// grabbed thing follows the mouse like a spring of this frequency.
struct Drag {
    enum class Kind { particle, body };
    Kind kind = Kind::particle;
    std::uint32_t index = 0;     // particle index, or model.rigid.bodies index
    Vec3 anchor = Vec3::Zero();  // m, body frame: the grabbed point (bodies only)
    Vec3 target = Vec3::Zero();  // m, world frame: where the mouse is
    double frequency = 3.0;      // Hz, natural frequency of the spring (> 0)
    double damping_ratio = 0.8;  // 1: critically damped (>= 0)
};

// The systems a World of `model` runs, decided once, here: World::step runs
// these stages and no others, and `run --json` lists them by name (docs/design.md:
// a scene pays only for what it declares).
struct Systems {
    bool particles = false;    // forces and integration (any particle)
    bool springs = false;      // a spring generator: inside the particles' force evaluations
    bool constraints = false;  // XPBD projection
    bool collisions = false;   // particles against colliders, each other and rigid bodies
    bool plasticity = false;   // plastic springs' rest lengths creep
    bool emitters = false;     // births at the nozzles
    bool rigid = false;        // ODE
    bool watchdog = false;
    // "particles", "springs", ... in stage order, the ones present.
    std::vector<std::string> names() const;
};
Systems systems_of(const ParticleModel& model, const WatchdogLimits& watchdog);

class World {
public:
    // Validates the model (InputError) and builds the state at t = 0.
    explicit World(ParticleModel model);
    // The force evaluation points into this object: not copyable or movable.
    // Build another World from model() instead.
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    // Advances one frame step: settings.substeps substeps of
    // settings.dt / settings.substeps, each the stages
    //   emit -> forces + integrate -> constraints -> collisions -> plasticity -> rigid -> watchdog
    // (a stage the model does not use costs nothing). Throws InputError for
    // bad settings. Once the watchdog has a verdict, does nothing.
    void step(const StepSettings& settings) {
        validate(settings);
        if (verdict_.exploded()) return;  // stopped cleanly: the state stays as the watchdog found it
        ++frames_;
        // Inline: the common step, a bare World's (bare_) of one substep in
        // a frame that is not sampled, goes straight to step_bare, without a
        // call that saves the registers the general step needs; every other
        // step to step_frame.
        if (frames_ < next_sample_ && bare_ && settings.substeps == 1) {
            step_bare(settings.integrator, settings.dt);
        } else {
            step_frame(settings);
        }
    }

    // Called after each substep of step(), once its stages (the watchdog's
    // too) have run, with the substep's number from 0: where a caller looks
    // at the state between substeps (`check` hashes it to say which substep
    // of a frame first differs). Empty: none (the default). It must not
    // step or edit the World.
    void set_substep_observer(std::function<void(int substep)> observer) {
        substep_observer_ = std::move(observer);
        refresh_bare();
    }

    // The watchdog (on by default with WatchdogLimits{}). Setting limits
    // validates them (InputError) and takes the current energy as E0.
    void set_watchdog(const WatchdogLimits& limits);
    const WatchdogLimits& watchdog() const { return watchdog_; }

    // Whether the particles' passes run their AVX2 builds (sim/cpu.h): on by
    // default where the CPU has AVX2. The same bits either way; tests and
    // benchmarks turn it off to compare.
    void set_wide(bool wide);
    bool wide() const { return wide_; }
    const Verdict& verdict() const { return verdict_; }
    // Explosions the watchdog contained (WatchdogLimits::contain), in order:
    // the verdict and the name of the range it froze.
    struct Contained {
        std::string name;
        Verdict verdict;
    };
    const std::vector<Contained>& contained() const { return contained_; }
    std::uint64_t frames() const { return frames_; }  // step() calls so far

    // Wall time per system, measured on a sample of frames, not on every
    // one: a clock read costs about 25 ns, as much as a whole step of a
    // one-particle problem. The second frame is timed (next_sample_), then
    // as often as keeps the clocks' own cost under 1% of the frames' time, as the
    // untimed frames between two sampled ones measure it (every frame of a
    // 10 µs step, one in about 500 of a 20 ns one). A sampled frame runs
    // the step every frame runs and reads the clock between its stages;
    // the cost of one read (calibrated once) is taken off each interval.
    // Divide by sampled_steps, never by steps(): ms_per_step() does.
    // Each system's time in the sampled frames (see step()): the entries
    // partition the step, with the glue between them only in `total`.
    // Springs evaluated inline (a list on at most kFewSpringParticles
    // particles: the few springs' and the pairs' paths) are no pass of
    // their own: their time is the particles', and `springs` stays 0.
    struct SystemTimes {
        double particles = 0.0;    // s, integration and the force evaluations (springs apart), and the
                                   // watchdog's per-particle rules when they run inside it (no
                                   // constraints or collisions: see step_once)
        double springs = 0.0;      // s, the spring generators' passes inside those force evaluations
        double constraints = 0.0;  // s, XPBD projection and its velocity update
        double collisions = 0.0;   // s
        double plasticity = 0.0;   // s, rest-length creep of plastic springs
        double emitters = 0.0;     // s, births at the nozzles
        double rigid = 0.0;        // s, ODE: collisions and the solver
        double watchdog = 0.0;     // s, the rest of the watchdog (or all of it, after constraints or collisions)
        double total = 0.0;        // s, whole frames: everything step() did in the sampled frames
        std::uint64_t sampled_frames = 0;
        std::uint64_t sampled_steps = 0;  // integrator steps (substeps) inside the sampled frames
        // ms per integrator step of a time above; 0 before the first sample.
        double ms_per_step(double seconds) const {
            return sampled_steps == 0 ? 0.0 : 1e3 * seconds / static_cast<double>(sampled_steps);
        }
        // The time of a system by its name in Systems::names(), s.
        double of(std::string_view system) const;
    };
    const SystemTimes& times() const { return times_; }
    const Systems& systems() const { return systems_; }

    const ParticleModel& model() const { return model_; }
    // The force generators as they are now: plastic springs' rest lengths
    // change as the body yields (the model keeps the built ones).
    const std::vector<ForceDef>& live_forces() const { return live_forces_; }
    std::size_t contacts() const { return collision_scratch_.contacts; }  // resolved in the last substep
    // The rigid bodies, when the model has any (else nullptr): body k of the
    // model is id {k, 0}.
    const RigidWorld* rigid() const { return rigid_.get(); }
    const ParticleState& state() const { return state_; }
    // Direct edits of x or v (a drag with the mouse, a teleport): the next step
    // rebuilds the integrator's memory from the edited state. Call it again
    // for each edit; a reference kept across step() may not be written: the
    // step would not know its arrays moved.
    ParticleState& edit_state();

    // Grabs (or with nullopt lets go of) a particle or a body. On a particle
    // the spring and its damping act implicitly at the start of each substep
    // (stable at any frequency and dt), on a body explicitly at its point; the
    // stretch saturates at 1 m. The work the drag does is added to the
    // watchdog's E0 (energy put in by hand is not an explosion; a blow-up
    // elsewhere still is). InputError for a pinned or unknown particle, an
    // unknown body, or bad numbers.
    void set_drag(const std::optional<Drag>& drag);
    const std::optional<Drag>& drag() const { return drag_; }

    // Everything that steps, integrator memory included: restoring a snapshot
    // and stepping gives the same bits as the run that made it (the lecture:
    // to go back in time accurately, store states; Euler does not run
    // backwards). Timings and force-evaluation counts are not rewound.
    struct Snapshot {
        ParticleState state;
        Vec3Array memory_a;
        Vec3Array memory_x_prev;
        bool memory_valid = false;
        Integrator memory_integrator = Integrator::symplectic_euler;
        double memory_h = 0.0;
        std::uint64_t steps = 0;
        std::uint64_t frames = 0;
        double initial_energy = 0.0;
        Verdict verdict;
        std::vector<double> plastic_rest;  // m, rest lengths of plastic springs, in force order
        std::vector<Contained> contained;
        std::vector<BodyState> bodies;  // rigid bodies, index order
        std::uint64_t rigid_steps = 0;
    };
    Snapshot snapshot() const;
    // Throws InputError, the world unchanged, when the snapshot is of another
    // model (its particles, plastic springs or rigid bodies do not fit).
    void restore(const Snapshot& snapshot);

    // The force generators' net force on each particle now, N (n): what force
    // arrows draw. Constraints, contacts and the mouse are not forces here.
    Vec3Array net_forces() const;

    double kinetic_energy() const;    // ½ Σ m v², J
    double potential_energy() const;  // every force's potential, J
    double energy() const { return kinetic_energy() + potential_energy(); }

    // Whole-system force evaluations so far: the machine-independent cost.
    double force_evaluations() const;
    std::uint64_t steps() const { return steps_; }  // integrator steps (substeps count)

    // Particles per block when every force is local and the method makes
    // more than one pass (sim::steps_in_one_pass): the step then runs block
    // by block, each block's arrays staying in cache (L2 for RK4's eleven
    // arrays) while the watchdog's quick pass reads it again.
    static constexpr std::size_t kBlock = 1024;

private:
    // The stages of one frame; the stopwatch reads the clock after each (a
    // sampled frame) or not at all.
    template <class Stopwatch>
    void run_substeps(const StepSettings& settings, Stopwatch& laps);
    void plan_next_sample();                          // after a sampled frame: when to sample again
    void step_bare(Integrator integrator, double h);  // step()'s common case: step_once and the watchdog
    void step_frame(const StepSettings& settings);    // step()'s others, frames_ counted
    // One integrator step; watch_blocks: count the watchdog's suspects block
    // by block (into watched_suspects_) as the integrator leaves each block.
    inline void step_once(Integrator integrator, double h, bool watch_blocks);  // defined in world.cpp only
    // step_once's one block (the watchdog's suspects in it), and every block;
    // `taken` set when the method left its new acceleration in s.a_next
    // (StepArrays::a_next_taken).
    std::size_t step_block(const IntegratorInfo& info, StepArrays& s, double h, bool watch_blocks, bool& taken);
    std::size_t step_blocks(const IntegratorInfo& info, double h, bool watch_blocks, bool& taken);
    // step_once's scratch, memory and (one block) arrays for the method, built
    // again when the method or the particle count changes, the arrays may
    // have moved (edit_state, restore), or the widths changed (set_wide).
    void prepare_step(Integrator integrator);
    StepArrays block_arrays(const IntegratorInfo& info, std::size_t first, std::size_t count);
    void solve_constraints(double h);  // positions projected, velocities corrected
    void plasticity(double h);
    // The watchdog after a substep, containing what it may. The common case
    // costs a few compares, inline: the integrator's pass counted no suspect
    // particle, and there is no energy rule and no body to check.
    void watch() {
        if (watched_suspects_ == std::size_t{0} && watchdog_.energy_growth == 0.0 && !rigid_) {
            watched_suspects_.reset();
            return;
        }
        watch_closely();
    }
    void watch_closely();          // the rules in full (check, check_bodies), containing what it may
    void update_body_colliders();  // the rigid bodies' parts where they are now, for the particles
    void apply_drag(double h);     // the mouse spring, for one substep of h s

    ParticleModel model_;
    ParticleState state_;
    std::vector<ForceDef> live_forces_;       // model_.forces, with plastic rest lengths as they are now
    std::vector<std::vector<double>> rest0_;  // built rest lengths per force (plastic springs only)
    ParticleForces forces_;
    std::vector<double> radius_;  // (n) m, collision radius
    Vec3Array x_start_;           // positions at the start of the substep
    Vec3Array x_predicted_;       // positions after the integrator, before the constraints
    std::vector<double> lambda_;  // XPBD multipliers of the substep
    Systems systems_;             // the stages step() runs (systems_of, the watchdog's as set)
    CollisionScratch collision_scratch_;
    std::unique_ptr<RigidWorld> rigid_;
    std::vector<MovingCollider> body_colliders_;  // rebuilt before each collision pass

    // Integrator memory and scratch (see StepArrays).
    Vec3Array memory_a_;
    Vec3Array memory_a_next_;  // Memory::two_accelerations: where the next step's a is written
    Vec3Array memory_x_prev_;
    std::vector<Vec3Array> scratch_;
    std::size_t scratch_arrays_ = 0, scratch_block_ = 0;  // scratch_[0, scratch_arrays_) hold scratch_block_ points
    struct PreparedStep {
        const IntegratorInfo* info = nullptr;  // nullptr: prepare_step first
        std::size_t n = 0;                     // particles when prepared
        std::size_t block = 0;                 // particles per block
        bool none_pinned = false;              // no particle pinned when prepared (StepArrays::none_pinned)
        // The force as a pair (StepArrays::pair) when n is 2, as the forces
        // give it now: looked up again while the sampled frames time the
        // springs (which then take the general path, and back).
        PairPath pair;
        StepArrays whole;  // the arrays of the one block, when 0 < n <= block
    };
    PreparedStep prepared_;
    bool memory_valid_ = false;
    bool wide_ = false;  // set_wide
    Integrator memory_integrator_ = Integrator::symplectic_euler;
    double memory_h_ = 0.0;
    std::uint64_t steps_ = 0;

    WatchdogLimits watchdog_;
    std::optional<std::size_t> watched_suspects_;  // counted inside the last step_once, for watch()
    double initial_energy_ = 0.0;                  // J, E0 for the watchdog's energy rule
    Verdict verdict_;
    std::vector<Contained> contained_;
    std::function<void(int)> substep_observer_;  // set_substep_observer
    // A substep is the forces, the integrator and the watchdog (on), nothing
    // else: no emitter, constraint, collision, plasticity, rigid body,
    // contained range, particle drag or substep observer. Kept by
    // refresh_bare, which everything that sets one of those calls.
    bool bare_ = false;
    void refresh_bare();
    std::uint64_t frames_ = 0;
    SystemTimes times_;
    double timer_cost_ = 0.0;  // s, what the clocks of the sampled frames cost
    // The frame (frames_ after ++) to time next. Not the first: it pays once
    // for what the later ones reuse (the integrator's arrays prepared, the
    // code and data brought into cache): 2.7 µs against 20-50 ns for a bead
    // on its spring, which a short run's figures would be mostly made of.
    std::uint64_t next_sample_ = 2;
    // The frames between two sampled ones, untimed: their wall time, s (the
    // caller's own work between steps included), and how many. What a frame
    // costs when no clock reads it, for plan_next_sample.
    struct Unsampled {
        double seconds = 0.0;
        std::uint64_t frames = 0;
        std::chrono::steady_clock::time_point since{};  // the last sampled frame's end
        std::uint64_t since_frame = 0;                  // its number; 0: none yet (or a restore since)
    };
    Unsampled unsampled_;
    std::optional<Drag> drag_;
};

}  // namespace sim
