#include "sim/world.h"

#include "sim/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

namespace sim {

void validate(const ParticleModel& model) {
    validate_particles(model.particles);
    validate_forces(model.forces, model.particles.size());
}

void validate(const StepSettings& settings) {
    if (!(settings.dt > 0.0) || !std::isfinite(settings.dt)) {
        throw InputError("dt must be > 0 and finite, in s (got " + format_value(settings.dt) + ")");
    }
    if (settings.substeps < 1) {
        throw InputError("substeps must be >= 1 (got " + std::to_string(settings.substeps) + ")");
    }
}

namespace {

ParticleModel validated(ParticleModel model) {
    validate(model);
    return model;
}

}  // namespace

World::World(ParticleModel model)
    : model_(validated(std::move(model))),
      state_(make_state(model_.particles)),
      forces_(model_.forces, state_.mass, state_.inv_mass) {
    scratch_.resize(kMaxScratch);
    initial_energy_ = energy();
}

void World::set_watchdog(const WatchdogLimits& limits) {
    validate(limits);
    watchdog_ = limits;
    initial_energy_ = energy();
}

ParticleState& World::edit_state() {
    memory_valid_ = false;
    return state_;
}

World::Snapshot World::snapshot() const {
    return {state_,    memory_a_, memory_x_prev_, memory_valid_,   memory_integrator_,
            memory_h_, steps_,    frames_,        initial_energy_, verdict_};
}

void World::restore(const Snapshot& snapshot) {
    if (snapshot.state.size() != state_.size()) {
        throw InputError("snapshot has " + std::to_string(snapshot.state.size()) + " particles, the world has " +
                         std::to_string(state_.size()));
    }
    state_ = snapshot.state;
    memory_a_ = snapshot.memory_a;
    memory_x_prev_ = snapshot.memory_x_prev;
    memory_valid_ = snapshot.memory_valid;
    memory_integrator_ = snapshot.memory_integrator;
    memory_h_ = snapshot.memory_h;
    steps_ = snapshot.steps;
    frames_ = snapshot.frames;
    initial_energy_ = snapshot.initial_energy;
    verdict_ = snapshot.verdict;
}

void World::step(const StepSettings& settings) {
    validate(settings);
    if (verdict_.exploded()) return;  // stopped cleanly: the state stays as the watchdog found it
    ++frames_;
    using Clock = std::chrono::steady_clock;
    const double h = settings.dt / settings.substeps;
    for (int i = 0; i < settings.substeps && !verdict_.exploded(); ++i) {
        const auto start = Clock::now();
        step_once(settings.integrator, h);  // forces and integration
        const auto integrated = Clock::now();
        if (watchdog_.enabled) {
            // The energy rule costs a potential-energy pass: only when asked for.
            const double e = watchdog_.energy_growth > 0.0 ? energy() : 0.0;
            verdict_ = check(watchdog_, state_, e, initial_energy_, frames_);
        }
        times_.particles += std::chrono::duration<double>(integrated - start).count();
        times_.watchdog += std::chrono::duration<double>(Clock::now() - integrated).count();
    }
}

void World::step_once(Integrator integrator, double h) {
    const IntegratorInfo& info = integrator_info(integrator);
    const std::size_t n = state_.size();
    if (memory_integrator_ != integrator || memory_h_ != h) {
        memory_valid_ = false;
    }
    // Scratch is allocated for the largest block the method will see.
    const bool blocked = forces_.all_local();
    const std::size_t block = blocked ? std::min(n, kBlock) : n;
    for (std::size_t i = 0; i < info.scratch_arrays; ++i) {
        if (scratch_[i].size() < block) {
            scratch_[i].resize(block);
        }
    }
    // Integrator memory is allocated the first time a method that keeps it runs.
    Vec3Array* memory = info.memory == Memory::acceleration        ? &memory_a_
                        : info.memory == Memory::previous_position ? &memory_x_prev_
                                                                   : nullptr;
    if (memory != nullptr && memory->size() != n) {
        memory->resize(n);
    }

    StepArrays whole;
    whole.x = state_.x.span();
    whole.v = state_.v.span();
    whole.a = memory_a_.span();
    whole.x_prev = memory_x_prev_.span();
    whole.memory_valid = memory_valid_;
    for (std::size_t i = 0; i < info.scratch_arrays; ++i) {
        whole.scratch[i] = scratch_[i].span();
    }

    for (std::size_t first = 0; first < n; first += block) {
        const std::size_t count = std::min(block, n - first);
        StepArrays part = whole;
        part.first = first;
        part.x = whole.x.block(first, count);
        part.v = whole.v.block(first, count);
        part.a = info.memory == Memory::acceleration ? whole.a.block(first, count) : Vec3Span{};
        part.x_prev = info.memory == Memory::previous_position ? whole.x_prev.block(first, count) : Vec3Span{};
        info.step(forces_, part, state_.t, h);
    }

    state_.t += h;
    memory_valid_ = true;
    memory_integrator_ = integrator;
    memory_h_ = h;
    ++steps_;
}

double World::kinetic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < state_.size(); ++i) {
        if (state_.inv_mass[i] != 0.0) {
            e += 0.5 * state_.mass[i] * state_.v.get(i).squaredNorm();
        }
    }
    return e;
}

double World::potential_energy() const { return forces_.potential_energy(state_.t, state_.x.span(), state_.v.span()); }

double World::force_evaluations() const {
    return state_.size() == 0
               ? 0.0
               : static_cast<double>(forces_.particle_evaluations()) / static_cast<double>(state_.size());
}

}  // namespace sim
