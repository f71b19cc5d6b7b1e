// What every benchmark that steps a World shares: the check, after timing,
// that it timed real work. A World the watchdog stopped returns from step()
// at once, and a benchmark of it would report picoseconds.
#pragma once

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

}  // namespace bench
