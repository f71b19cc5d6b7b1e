// ns per particle-step of every integrator on N particles under gravity and
// linear drag, beside a plain hand-written loop over separate x/y/z arrays
// (the reference the library's symplectic Euler is held to: >= 0.9x its speed
// at N = 1e6). Run with `make bench`; the figure to read is per_particle_step
// (seconds, SI prefix: 2.4n is 2.4 ns).
#include "sim/world.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

constexpr double kDt = 1.0 / 60.0;  // s
constexpr double kDrag = 0.05;      // N·s/m
constexpr double kGravity = -9.81;  // m/s²

sim::ParticleModel cloud(std::size_t n) {
    sim::ParticleModel model;
    model.particles.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double s = static_cast<double>(i);
        model.particles.push_back({sim::Vec3(std::sin(s), std::cos(s), 0.001 * s),
                                   sim::Vec3(std::cos(0.5 * s), 5.0, std::sin(0.5 * s)), 1.0 + 0.001 * (i % 100),
                                   false});
    }
    model.forces = {sim::UniformGravity{sim::Vec3(0.0, kGravity, 0.0)}, sim::LinearDrag{kDrag}};
    return model;
}

void set_counters(benchmark::State& state, std::size_t n) {
    const double particle_steps = static_cast<double>(state.iterations()) * static_cast<double>(n);
    state.SetItemsProcessed(static_cast<std::int64_t>(particle_steps));
    // seconds per particle-step, printed with an SI prefix (1.6n = 1.6 ns)
    state.counters["per_particle_step"] =
        benchmark::Counter(particle_steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void integrator(benchmark::State& state, sim::Integrator id) {
    const auto n = static_cast<std::size_t>(state.range(0));
    sim::World world(cloud(n));
    const sim::StepSettings settings{id, kDt, 1};
    for (auto _ : state) {
        world.step(settings);
        benchmark::DoNotOptimize(world.state().x.raw().data());
        benchmark::ClobberMemory();
    }
    set_counters(state, n);
}

// The same physics as the library's symplectic Euler on the same model
// (f = m g - c v, a = f / m, v += h a, x += h v), written as one plain loop
// over separate coordinate arrays.
void hand_written_loop(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    const sim::ParticleModel model = cloud(n);
    std::vector<double> px(n), py(n), pz(n), vx(n), vy(n), vz(n), m(n), inv_m(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& p = model.particles[i];
        px[i] = p.position.x();
        py[i] = p.position.y();
        pz[i] = p.position.z();
        vx[i] = p.velocity.x();
        vy[i] = p.velocity.y();
        vz[i] = p.velocity.z();
        m[i] = p.mass;
        inv_m[i] = 1.0 / p.mass;
    }
    const double h = kDt;
    for (auto _ : state) {
        for (std::size_t i = 0; i < n; ++i) {
            const double ax = (m[i] * 0.0 - kDrag * vx[i]) * inv_m[i];
            const double ay = (m[i] * kGravity - kDrag * vy[i]) * inv_m[i];
            const double az = (m[i] * 0.0 - kDrag * vz[i]) * inv_m[i];
            vx[i] += h * ax;
            vy[i] += h * ay;
            vz[i] += h * az;
            px[i] += h * vx[i];
            py[i] += h * vy[i];
            pz[i] += h * vz[i];
        }
        benchmark::DoNotOptimize(px.data());
        benchmark::ClobberMemory();
    }
    set_counters(state, n);
}

void sizes(benchmark::internal::Benchmark* b) {
    b->Arg(1000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
}

const bool kRegistered = [] {
    benchmark::RegisterBenchmark("hand_written_loop", hand_written_loop)->Apply(sizes);
    for (const sim::IntegratorInfo& info : sim::kIntegrators) {
        benchmark::RegisterBenchmark(std::string(info.name).c_str(), integrator, info.id)->Apply(sizes);
    }
    return true;
}();

}  // namespace

BENCHMARK_MAIN();
