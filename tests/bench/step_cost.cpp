// The fixed cost of a step in instructions, a figure a shared, noisy machine
// does not move (bench_sim's FixedCost times the same step in ns, which it
// does). Steps the fixed-cost bead (bench_world.h) STEPS times with METHOD and
// does nothing else, so that two runs under callgrind differ by the steps
// alone: tools/step-instructions.sh runs it twice and prints the difference
// per step. Exit 1 when the World stopped or took fewer steps (it would
// count nothing), 2 for bad arguments.
//   usage: step_cost METHOD STEPS
#include "bench_world.h"
#include "sim/integrators.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>

int main(int argc, char** argv) {
    const std::optional<sim::Integrator> method = argc == 3 ? sim::integrator_from_name(argv[1]) : std::nullopt;
    char* end = nullptr;
    errno = 0;
    const long long steps = argc == 3 ? std::strtoll(argv[2], &end, 10) : 0;
    if (!method || end == argv[2] || *end != '\0' || errno == ERANGE || steps < 0) {
        std::fprintf(stderr, "usage: step_cost METHOD STEPS (METHOD one of %s; STEPS >= 0)\n",
                     sim::integrator_names().c_str());
        return 2;
    }
    sim::World world(bench::fixed_cost_bead());
    const sim::StepSettings settings{*method, 1.0 / 60.0, 1};
    for (long long i = 0; i < steps; ++i) world.step(settings);
    if (world.verdict().exploded() || world.steps() != static_cast<std::uint64_t>(steps)) {
        std::fprintf(stderr, "step_cost: the World took %llu of %lld steps (%s)\n",
                     static_cast<unsigned long long>(world.steps()), steps,
                     world.verdict().exploded() ? world.verdict().message("bead").c_str() : "running");
        return 1;
    }
    std::printf("x = %.17g m after %lld steps\n", world.state().x.get(1).x(), steps);  // the work, observable
    return 0;
}
