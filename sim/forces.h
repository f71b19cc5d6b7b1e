// Every force generator in one closed set, and the Dynamics that sums them.
// Adding a generator: its own file with the verbs listed in force.h, then one
// entry in ForceDef.
#pragma once

#include "sim/buoyancy.h"
#include "sim/central_gravity.h"
#include "sim/control_force.h"
#include "sim/dynamics.h"
#include "sim/gravity.h"
#include "sim/linear_drag.h"
#include "sim/newton_gravity.h"
#include "sim/pair_forces.h"
#include "sim/quadratic_drag.h"
#include "sim/shock_wave.h"
#include "sim/spring.h"
#include "sim/spring_plan.h"
#include "sim/wind.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

namespace sim {

using ForceDef = std::variant<UniformGravity, NewtonGravity, Springs, LinearDrag, QuadraticDrag, Wind, Buoyancy,
                              ShockWave, ControlForces, CentralGravity>;

// The name scene files and messages use for a generator ("gravity", "springs", ...).
const char* force_name(const ForceDef& force);

// ParticleForces' description of a force that is one list of springs, with
// a uniform field or without, for a block of at most kFewSpringParticles
// particles: on one bead on one spring the general path's dispatch (the
// generator list, the plan, the spring clock, the widths) costs as much as
// the force, and this one is evaluated straight from it.
inline constexpr std::size_t kFewSpringParticles = 4;
struct FewSprings {
    const Springs* springs = nullptr;     // nullptr: the force is not such a list
    const UniformField* field = nullptr;  // nullptr: none
};

// Sums a list of generators over a system of particles. Holds pointers to the
// system's mass arrays and the generator list, which must outlive it.
class ParticleForces final : public Dynamics {
public:
    ParticleForces(const std::vector<ForceDef>& forces, const std::vector<double>& mass,
                   const std::vector<double>& inv_mass);
    // few_, pair_gravity_ and spring_pair_ point into this object: not copyable or movable.
    ParticleForces(const ParticleForces&) = delete;
    ParticleForces& operator=(const ParticleForces&) = delete;

    // True when every generator is local, so that a step may run block by block.
    bool all_local() const { return all_local_; }

    void acceleration(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                      const Vec3Span& a) override;
    void force_and_jacobians(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                             const Vec3Span& f, Jacobians& jac) override;
    const double* mass() const override { return mass_->data(); }
    const double* inv_mass() const override { return inv_mass_->data(); }
    // One spring on two particles, with the field, or Newton's gravity alone
    // between them, with the field.
    PairPath pair_path(std::size_t particles) const override {
        return {spring_pair(particles), particles == 2 && pair_gravity_.gravity != nullptr ? &pair_gravity_ : nullptr,
                mass_->data(), inv_mass_->data()};
    }
    const UniformField* uniform_field() const override { return others_.empty() && has_field_ ? &field_ : nullptr; }
    bool velocity_free() const override { return velocity_free_; }

    // The net force on every particle at (t, x, v), N, pinned ones included:
    // for drawing force arrows (not counted as an evaluation).
    void net_force(double t, ConstVec3Span x, ConstVec3Span v, Vec3Span f) const {
        sum_forces(input(t, 0, x, v), f, false);
    }

    // Potential energy of every generator at (t, x, v), J.
    double potential_energy(double t, ConstVec3Span x, ConstVec3Span v) const;

    // The spring generators' passes, timed while `time` is set (the World's
    // sampled frames; nullptr: not timed, no clock read): wall seconds and
    // the clock reads that took them. The few springs' and the pairs' paths
    // are no pass: a sampled frame takes them too (so that it times the step
    // that runs), and their springs' time stays in the caller's.
    struct SpringTime {
        double seconds = 0.0;  // s, the reads' own cost included
        int reads = 0;
    };
    void time_springs(SpringTime* time) { spring_time_ = time; }

    // Run the passes' AVX2 builds (sim/cpu.h), where the CPU has AVX2 (the
    // default); the same bits either way. Tests turn them off to compare.
    void set_wide(bool wide);

    // The inverse masses may have changed: call after every write to them
    // (the World does: edit_state, restore, a contained range pinned, an
    // emitter's births). Passes may keep what they found in them until then
    // (ForceInput::masses): one write without this call, and they would go
    // on with the old masses.
    void masses_changed() { ++masses_; }

private:
    const SpringPair* spring_pair(std::size_t particles) const {
        return spring_pair_.spring != nullptr && particles == 2 ? &spring_pair_ : nullptr;
    }
    // few_ where the block of `particles` is small enough, else nullptr.
    const FewSprings* few_springs(std::size_t particles) const {
        return few_.springs != nullptr && particles <= kFewSpringParticles ? &few_ : nullptr;
    }
    ForceInput input(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v) const;
    // acceleration() on every path but the few springs' (out of line, so that
    // the few springs' call saves and restores no more registers than it uses).
    void general_acceleration(const ForceInput& in, const Vec3Span& a) const;
    // f = field force (+ inverse mass applied when `to_acceleration`).
    void field_pass(const ForceInput& in, const Vec3Span& out, bool to_acceleration) const;
    // f = every generator's force; skip_pinned: pinned particles' sums may be
    // left out (for accelerations, see the spring pass).
    void sum_forces(const ForceInput& in, const Vec3Span& f, bool skip_pinned) const;
    // The same, inlined; to_acceleration: where the last generator is a
    // planned spring pass (springs_last_), it applies M⁻¹ too (and starts
    // from zero when it is the only force), one pass over f instead of three.
    // Returns true when f holds M⁻¹ f.
    bool add_forces(const ForceInput& in, const Vec3Span& f, bool skip_pinned, bool to_acceleration) const;
    // a = M⁻¹ (field + central_only_'s force), in one or two passes.
    void central_acceleration(const ForceInput& in, const Vec3Span& a) const;

    const std::vector<ForceDef>* forces_;
    // Uniform gravity and drag summed into one field (the sums of every
    // UniformGravity, LinearDrag and QuadraticDrag), evaluated in a single pass
    // over the arrays instead of one pass per generator.
    UniformField field_;
    bool has_field_ = false;
    std::vector<const ForceDef*> others_;  // generators outside the field, in scene order
    // (others_) each spring generator's plan for the fast pass, with its
    // scratch (empty for other generators); mutable: scratch, not state, and
    // net_force (const) takes the same path.
    mutable std::vector<SpringPlan> plans_;
    const std::vector<double>* mass_;
    const std::vector<double>* inv_mass_;
    std::uint64_t masses_ = 1;  // the stamp of inv_mass_'s contents (ForceInput::masses), never 0
    bool all_local_ = true;
    // No generator reads v: gravity of any kind, springs without dampers.
    bool velocity_free_ = true;
    const CentralGravity* central_only_ = nullptr;  // the one generator outside the field, if a CentralGravity
    // The one generator outside the field, if a Springs of a few springs (the
    // reference loop's), with the field: on a few particles its
    // acceleration goes straight through few_spring_acceleration (forces.cpp), without
    // the general dispatch (few_.springs: nullptr where it is not).
    FewSprings few_;
    // Newton's gravity alone (with the field), for two particles: straight
    // through pair::gravity_acceleration (pair_gravity_.gravity: nullptr where not).
    PairGravity pair_gravity_;
    SpringPair spring_pair_;     // one spring (few_'s list of one), with the field; .spring: nullptr where not
    bool springs_last_ = false;  // the last generator outside the field is a planned spring pass
    bool wide_ = false;          // the passes' AVX2 builds (the same bits), where the CPU has it
    SpringTime* spring_time_ = nullptr;
    using SpringClock = std::chrono::steady_clock;
};

// Validates every generator against a system of particle_count particles.
void validate_forces(const std::vector<ForceDef>& forces, std::size_t particle_count);

}  // namespace sim
