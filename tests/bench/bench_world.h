// What every benchmark that steps a World shares: the check, after timing,
// that it timed real work. A World the watchdog stopped returns from step()
// at once, and a benchmark of it would report picoseconds.
#pragma once

#include "sim/problems.h"
#include "sim/world.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

namespace bench {

// Marks the benchmark as failed (SkipWithError: the figures are not shown,
// the error is) unless `world` is still running and has taken `steps`
// integrator steps. Returns true when it is.
inline bool still_running(benchmark::State& state, const sim::World& world, std::uint64_t steps,
                          const std::string& name) {
    if (world.verdict().exploded()) {
        state.SkipWithError(("the World stopped, timing nothing: " + world.verdict().message(name)).c_str());
        return false;
    }
    if (world.steps() != steps) {
        state.SkipWithError((name + ": the World took " + std::to_string(world.steps()) + " steps of the " +
                             std::to_string(steps) + " asked for")
                                .c_str());
        return false;
    }
    return true;
}

// The fixed-cost bead (issue 17): one 1 kg particle on a zero-length spring
// of 1 N/m to a pinned anchor, released 1 m out at rest, bounded for ever (a
// 2π s period, 0.5 J). FixedCost times its step; step_cost counts its
// instructions.
inline sim::ParticleModel fixed_cost_bead() {
    const sim::analytic::Oscillator o{1.0, 1.0, 0.0};  // kg, N/m, N·s/m
    return sim::problems::oscillator_model(o, sim::Vec3(1.0, 0.0, 0.0), sim::Vec3::Zero());
}

}  // namespace bench
