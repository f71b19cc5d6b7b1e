// ns per particle-step of every integrator on a cloud of N free particles
// (gravity and linear drag, the particle-effect case), N = 1, 1e3, 1e5 and
// 1e6, three ways in the same run: hand/ a hand-written loop of the method,
// stage/ the World with its watchdog off (the particles stage: forces and
// integration), world/ the whole step as a scene runs it. The tables printed
// at the end are the figures to read (issue 17's targets at N >= 1e5:
// stage / hand <= 1.1, world / hand <= 1.5, RK4 / symplectic Euler <= 4.5,
// four force evaluations to one). At N = 1 the ratio is mostly the fixed
// cost of a step (FixedCost below).
//
// Honest by construction: every kLapSteps steps (10 s simulated) the cloud is
// put back where it started, outside the timing, so it never leaves the
// watchdog's world box however many iterations run; the hand loops are put
// back the same way. After timing, each World benchmark checks that the
// World still runs and took every step it was asked for (bench_world.h).
//
// Also here: FixedCost, one particle on one spring (the report's harmonic
// oscillator: a pinned anchor and a 1 kg bead), one whole step per iteration
// (issue 17: <= 50 ns with symplectic Euler, <= 120 ns with RK4), beside the
// same bead stepped by a hand-written loop of the method in the same run
// (FixedCost/hand_...): the last table gives the World's step in hand steps,
// a figure the machine's speed of the moment does not move.
#include "bench_world.h"
#include "sim/cpu.h"
#include "sim/world.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <unistd.h>

namespace {

constexpr double kDt = 1.0 / 60.0;  // s
constexpr double kDrag = 0.05;      // N·s/m
constexpr double kGravity = -9.81;  // m/s²
constexpr int kLapSteps = 600;      // steps between returns to the start: 10 s, a fall of about 500 m

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

// Seconds per particle-step, printed with an SI prefix (1.6n = 1.6 ns).
void set_counters(benchmark::State& state, std::size_t n) {
    const double particle_steps = static_cast<double>(state.iterations()) * static_cast<double>(n);
    state.SetItemsProcessed(static_cast<std::int64_t>(particle_steps));
    state.counters["per_particle_step"] =
        benchmark::Counter(particle_steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Runs step() once per iteration, and reset() (untimed) every kLapSteps.
template <class Step, class Reset>
void laps(benchmark::State& state, Step step, Reset reset) {
    int in_lap = 0;
    for (auto _ : state) {
        if (in_lap == kLapSteps) {
            state.PauseTiming();
            reset();
            in_lap = 0;
            state.ResumeTiming();
        }
        step();
        ++in_lap;
    }
}

// --- the library -------------------------------------------------------------------

// watchdog: the whole step as a scene runs it; without, the particles stage
// alone (forces and integration), which is what a hand loop does.
void world_cloud(benchmark::State& state, sim::Integrator id, bool watchdog) {
    const auto n = static_cast<std::size_t>(state.range(0));
    sim::World world(cloud(n));
    if (!watchdog) world.set_watchdog({.enabled = false});
    const sim::ParticleState start = world.state();
    const sim::StepSettings settings{id, kDt, 1};
    laps(
        state,
        [&] {
            world.step(settings);
            benchmark::DoNotOptimize(world.state().x.raw().data());
            benchmark::ClobberMemory();
        },
        [&] {
            sim::ParticleState& s = world.edit_state();
            s.x = start.x;
            s.v = start.v;
        });
    if (!bench::still_running(state, world, state.iterations(), "cloud")) return;
    set_counters(state, n);
}

// --- hand-written loops -----------------------------------------------------------------

// The cloud as a student would write it: separate coordinate arrays.
struct HandCloud {
    std::vector<double> x, y, z, vx, vy, vz, m, inv_m;  // m, m/s, kg, 1/kg
    std::vector<double> a[3];                           // m/s², the acceleration kept by leapfrog and velocity Verlet
    std::vector<double> prev[3];                        // m, the previous position (Störmer-Verlet)
    bool memory = false;                                // ax.. or px.. hold the last step's values
    std::size_t size() const { return x.size(); }
};

HandCloud hand_cloud(std::size_t n) {
    const sim::ParticleModel model = cloud(n);
    HandCloud c;
    for (const sim::ParticleDef& p : model.particles) {
        c.x.push_back(p.position.x()), c.y.push_back(p.position.y()), c.z.push_back(p.position.z());
        c.vx.push_back(p.velocity.x()), c.vy.push_back(p.velocity.y()), c.vz.push_back(p.velocity.z());
        c.m.push_back(p.mass), c.inv_m.push_back(1.0 / p.mass);
    }
    for (int k = 0; k < 3; ++k) c.a[k] = c.prev[k] = std::vector<double>(n, 0.0);
    return c;
}

// One particle of the hand loops, as values: the loop loads it, the method
// updates it, the loop stores it back.
struct Hand {
    double x, y, z, vx, vy, vz;  // m, m/s
    double mx, my, mz;           // the method's memory: acceleration (m/s²) or previous position (m)
    double m, inv_m;             // kg, 1/kg

    // a = (m g - c v) / m at velocity (wx, wy, wz), m/s².
    void accel(double wx, double wy, double wz, double& gx, double& gy, double& gz) const {
        gx = (m * 0.0 - kDrag * wx) * inv_m;
        gy = (m * kGravity - kDrag * wy) * inv_m;
        gz = (m * 0.0 - kDrag * wz) * inv_m;
    }
};

// The loop every hand-written method runs: plain arrays a compiler may
// vectorise (__restrict: they never overlap), `body` on each particle; the
// memory arrays are read and written only by the methods that keep one.
template <bool kMemory, class Body>
void hand_pass(double* __restrict x, double* __restrict y, double* __restrict z, double* __restrict vx,
               double* __restrict vy, double* __restrict vz, double* __restrict mx, double* __restrict my,
               double* __restrict mz, const double* __restrict m, const double* __restrict inv_m, std::size_t n,
               Body body) {
    for (std::size_t i = 0; i < n; ++i) {
        Hand p{x[i], y[i], z[i], vx[i], vy[i], vz[i], 0.0, 0.0, 0.0, m[i], inv_m[i]};
        if constexpr (kMemory) p.mx = mx[i], p.my = my[i], p.mz = mz[i];
        body(p);
        x[i] = p.x, y[i] = p.y, z[i] = p.z, vx[i] = p.vx, vy[i] = p.vy, vz[i] = p.vz;
        if constexpr (kMemory) mx[i] = p.mx, my[i] = p.my, mz[i] = p.mz;
    }
}

// memory: the arrays of the method's memory (c.ax.. or c.px..), or none.
template <bool kMemory = false, class Body>
void hand_loop(HandCloud& c, Body body, std::vector<double>* memory = nullptr) {
    double* mx = kMemory ? memory[0].data() : nullptr;
    double* my = kMemory ? memory[1].data() : nullptr;
    double* mz = kMemory ? memory[2].data() : nullptr;
    // At the World's width (AVX2 where the CPU has it: sim/cpu.h), so that
    // the ratio measures the World's overhead, not the instruction set.
    sim::run_at_width(
        sim::avx2_available(), [](auto... a) { hand_pass<kMemory>(a...); }, c.x.data(), c.y.data(), c.z.data(),
        c.vx.data(), c.vy.data(), c.vz.data(), mx, my, mz, c.m.data(), c.inv_m.data(), c.size(), body);
}

// The methods that keep memory (leapfrog and velocity Verlet the
// acceleration, Störmer the previous position): step(p, first), first a
// std::bool_constant, true on the step that must build the memory.
template <class Step>
void hand_loop_keeping(HandCloud& c, std::vector<double>* memory, Step step) {
    if (c.memory) {
        hand_loop<true>(
            c, [&](Hand& p) { step(p, std::false_type{}); }, memory);
    } else {
        hand_loop<true>(
            c, [&](Hand& p) { step(p, std::true_type{}); }, memory);
    }
    c.memory = true;
}

void hand_forward_euler(HandCloud& c, double h) {
    hand_loop(c, [h](Hand& p) {
        double ax, ay, az;
        p.accel(p.vx, p.vy, p.vz, ax, ay, az);
        p.x += h * p.vx, p.y += h * p.vy, p.z += h * p.vz;
        p.vx += h * ax, p.vy += h * ay, p.vz += h * az;
    });
}

void hand_symplectic_euler(HandCloud& c, double h) {
    hand_loop(c, [h](Hand& p) {
        double ax, ay, az;
        p.accel(p.vx, p.vy, p.vz, ax, ay, az);
        p.vx += h * ax, p.vy += h * ay, p.vz += h * az;
        p.x += h * p.vx, p.y += h * p.vy, p.z += h * p.vz;
    });
}

// The first step (memory false) evaluates the acceleration it did not keep.
void hand_leapfrog(HandCloud& c, double h) {
    auto step = [h](Hand& p, auto first) {
        if (first) p.accel(p.vx, p.vy, p.vz, p.mx, p.my, p.mz);
        p.vx += 0.5 * h * p.mx, p.vy += 0.5 * h * p.my, p.vz += 0.5 * h * p.mz;
        p.x += h * p.vx, p.y += h * p.vy, p.z += h * p.vz;
        p.accel(p.vx, p.vy, p.vz, p.mx, p.my, p.mz);
        p.vx += 0.5 * h * p.mx, p.vy += 0.5 * h * p.my, p.vz += 0.5 * h * p.mz;
    };
    hand_loop_keeping(c, c.a, step);
}

void hand_velocity_verlet(HandCloud& c, double h) {
    auto step = [h](Hand& p, auto first) {
        if (first) p.accel(p.vx, p.vy, p.vz, p.mx, p.my, p.mz);
        const double wx = p.vx + h * p.mx, wy = p.vy + h * p.my, wz = p.vz + h * p.mz;  // predicted v'
        p.x += h * p.vx + 0.5 * h * h * p.mx;
        p.y += h * p.vy + 0.5 * h * h * p.my;
        p.z += h * p.vz + 0.5 * h * h * p.mz;
        double nx, ny, nz;
        p.accel(wx, wy, wz, nx, ny, nz);
        p.vx += 0.5 * h * (p.mx + nx), p.vy += 0.5 * h * (p.my + ny), p.vz += 0.5 * h * (p.mz + nz);
        p.mx = nx, p.my = ny, p.mz = nz;
    };
    hand_loop_keeping(c, c.a, step);
}

// Störmer: x' = 2x - x_prev + h² a, v' = (x' - x)/h + h a / 2, per coordinate.
inline void stormer(double& x, double& v, double& prev, double a, double h, bool first) {
    if (first) prev = x - h * v + 0.5 * h * h * a;
    const double next = 2.0 * x - prev + h * h * a;
    v = (next - x) / h + 0.5 * h * a;
    prev = x;
    x = next;
}

void hand_position_verlet(HandCloud& c, double h) {
    auto step = [h](Hand& p, auto first) {
        double ax, ay, az;
        p.accel(p.vx, p.vy, p.vz, ax, ay, az);
        stormer(p.x, p.vx, p.mx, ax, h, first);
        stormer(p.y, p.vy, p.my, ay, h, first);
        stormer(p.z, p.vz, p.mz, az, h, first);
    };
    hand_loop_keeping(c, c.prev, step);
}

void hand_rk4(HandCloud& c, double h) {
    hand_loop(c, [h](Hand& p) {
        const double v1x = p.vx, v1y = p.vy, v1z = p.vz;
        double k1x, k1y, k1z, k2x, k2y, k2z, k3x, k3y, k3z, k4x, k4y, k4z;
        p.accel(v1x, v1y, v1z, k1x, k1y, k1z);
        const double v2x = v1x + 0.5 * h * k1x, v2y = v1y + 0.5 * h * k1y, v2z = v1z + 0.5 * h * k1z;
        p.accel(v2x, v2y, v2z, k2x, k2y, k2z);
        const double v3x = v1x + 0.5 * h * k2x, v3y = v1y + 0.5 * h * k2y, v3z = v1z + 0.5 * h * k2z;
        p.accel(v3x, v3y, v3z, k3x, k3y, k3z);
        const double v4x = v1x + h * k3x, v4y = v1y + h * k3y, v4z = v1z + h * k3z;
        p.accel(v4x, v4y, v4z, k4x, k4y, k4z);
        p.x += h / 6.0 * (v1x + 2.0 * v2x + 2.0 * v3x + v4x);
        p.y += h / 6.0 * (v1y + 2.0 * v2y + 2.0 * v3y + v4y);
        p.z += h / 6.0 * (v1z + 2.0 * v2z + 2.0 * v3z + v4z);
        p.vx += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        p.vy += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
        p.vz += h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z);
    });
}

// Backward Euler as the lecture states it, linearised: (m - h ∂f/∂v) Δv =
// h f(v), v' = v + Δv, x' = x + h v'; on this cloud ∂f/∂v = -c, so the
// system is one scalar per coordinate and Δv = h f / (m + h c).
void hand_backward_euler(HandCloud& c, double h) {
    hand_loop(c, [h](Hand& p) {
        const double fx = p.m * 0.0 - kDrag * p.vx, fy = p.m * kGravity - kDrag * p.vy, fz = p.m * 0.0 - kDrag * p.vz;
        const double inv_d = 1.0 / (p.m + h * kDrag);
        p.vx += h * fx * inv_d, p.vy += h * fy * inv_d, p.vz += h * fz * inv_d;
        p.x += h * p.vx, p.y += h * p.vy, p.z += h * p.vz;
    });
}

using HandStep = void (*)(HandCloud&, double);
HandStep hand_step(sim::Integrator id) {
    switch (id) {
        case sim::Integrator::forward_euler:
            return &hand_forward_euler;
        case sim::Integrator::symplectic_euler:
            return &hand_symplectic_euler;
        case sim::Integrator::leapfrog:
            return &hand_leapfrog;
        case sim::Integrator::velocity_verlet:
            return &hand_velocity_verlet;
        case sim::Integrator::position_verlet:
            return &hand_position_verlet;
        case sim::Integrator::rk4:
            return &hand_rk4;
        case sim::Integrator::backward_euler:
            return &hand_backward_euler;
    }
    return nullptr;
}

void hand_cloud_bench(benchmark::State& state, sim::Integrator id) {
    const auto n = static_cast<std::size_t>(state.range(0));
    const HandCloud start = hand_cloud(n);
    HandCloud c = start;
    const HandStep step = hand_step(id);
    laps(
        state,
        [&] {
            step(c, kDt);
            benchmark::DoNotOptimize(c.x.data());
            benchmark::ClobberMemory();
        },
        [&] { c = start; });
    set_counters(state, n);
}

// --- the fixed cost ---------------------------------------------------------------------

void fixed_cost(benchmark::State& state, sim::Integrator id) {
    sim::World world(bench::fixed_cost_bead());
    const sim::StepSettings settings{id, kDt, 1};
    for (auto _ : state) {
        world.step(settings);
        benchmark::DoNotOptimize(world.state().x.raw().data());
        benchmark::ClobberMemory();
    }
    if (!bench::still_running(state, world, state.iterations(), "oscillator")) return;
    state.counters["per_step"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The reference: the same bead (1 kg on a spring of 1 N/m to the origin, rest
// length 0) stepped by hand, its state in six doubles and its force -k x
// inline, the method's arithmetic and nothing else.
struct HandBead {
    double x[3] = {1.0, 0.0, 0.0};   // m
    double v[3] = {0.0, 0.0, 0.0};   // m/s
    double a[3] = {-1.0, 0.0, 0.0};  // m/s², velocity Verlet's kept acceleration (-k x / m at the start)
};

// Times `step` on a bead, one step an iteration (the method chosen before
// the loop, so that the reference carries no dispatch of its own).
template <class Step>
void time_hand_bead(benchmark::State& state, Step step) {
    HandBead bead;
    for (auto _ : state) {
        step(bead, kDt);
        benchmark::DoNotOptimize(bead);
        benchmark::ClobberMemory();
    }
    if (!(std::abs(bead.x[0]) <= 2.0)) {  // bounded for ever (energy 0.5 J): else the loop did not step the bead
        state.SkipWithError("the hand-stepped bead left its orbit");
        return;
    }
    state.counters["per_step"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void hand_fixed_cost(benchmark::State& state, sim::Integrator id) {
    constexpr double k_over_m = 1.0;  // 1/s²
    switch (id) {
        case sim::Integrator::symplectic_euler:
            return time_hand_bead(state, [](HandBead& b, double h) {
                for (int c = 0; c < 3; ++c) b.v[c] += h * (-k_over_m * b.x[c]), b.x[c] += h * b.v[c];
            });
        case sim::Integrator::velocity_verlet:
            return time_hand_bead(state, [](HandBead& b, double h) {
                for (int c = 0; c < 3; ++c) {
                    b.x[c] += h * b.v[c] + 0.5 * h * h * b.a[c];
                    const double a_new = -k_over_m * b.x[c];
                    b.v[c] += 0.5 * h * (b.a[c] + a_new);
                    b.a[c] = a_new;
                }
            });
        default:  // rk4, the third method FixedCost times: RK4 on (x, v), a(x) = -k x / m
            return time_hand_bead(state, [](HandBead& b, double h) {
                for (int c = 0; c < 3; ++c) {
                    const double x1 = b.x[c], v1 = b.v[c], a1 = -k_over_m * x1;
                    const double x2 = x1 + 0.5 * h * v1, v2 = v1 + 0.5 * h * a1, a2 = -k_over_m * x2;
                    const double x3 = x1 + 0.5 * h * v2, v3 = v1 + 0.5 * h * a2, a3 = -k_over_m * x3;
                    const double x4 = x1 + h * v3, v4 = v1 + h * a3, a4 = -k_over_m * x4;
                    b.x[c] += h / 6.0 * (v1 + 2.0 * v2 + 2.0 * v3 + v4);
                    b.v[c] += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
                }
            });
    }
}

// The methods FixedCost times (the two targets, and velocity Verlet).
constexpr const char* kFixedCostMethods[] = {"symplectic_euler", "velocity_verlet", "rk4"};

// --- the ratio table --------------------------------------------------------------------

// Prints the usual console table, keeps per_particle_step (per_step for the
// fixed cost) of every run that did its work, and at the end the ratios the
// issue's targets are stated in, each of two medians: with
// --benchmark_repetitions=R (make bench: 3, with
// --benchmark_enable_random_interleaving, so that a hand loop and its World
// take turns under the same load) the median of the R repetitions.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    using ConsoleReporter::ConsoleReporter;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (failed(run)) failures_.push_back(run.benchmark_name());
            if (failed(run) || run.run_type != Run::RT_Iteration) continue;
            for (const char* name : {"per_particle_step", "per_step"}) {  // a run has one or the other
                const auto counter = run.counters.find(name);
                if (counter != run.counters.end()) samples_[run.benchmark_name()].push_back(counter->second.value);
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }

    void print_ratios(const std::vector<std::size_t>& sizes) const {
        print_table(
            "The particles stage (World, watchdog off) / hand-written loop, per particle-step\n"
            "(target <= 1.1 at N >= 1e5; at N = 1 it is the fixed cost of a step):",
            "stage/", sizes);
        print_table("The whole step (World, watchdog on) / hand-written loop (target <= 1.5 at N >= 1e5):", "world/",
                    sizes);
        std::printf("%-18s", "rk4 / sympl. Euler");  // target <= 4.5: four force evaluations to one
        for (std::size_t n : sizes) print_ratio("world/", "world/", "rk4", "symplectic_euler", n);
        std::printf("\n");
        std::printf(
            "\nThe fixed cost: a whole World step of one bead on one spring, ns, and in steps of the same\n"
            "bead hand-written (the same run; the targets are 50 ns and 120 ns on the machine of the issue):\n");
        for (const char* method : kFixedCostMethods) {
            const double world = median(std::string("FixedCost/") + method);
            const double hand = median(std::string("FixedCost/hand_") + method);
            if (world <= 0.0 || hand <= 0.0) continue;
            std::printf("%-18s%9.1f ns = %6.1f hand steps of %.1f ns\n", method, 1e9 * world, world / hand, 1e9 * hand);
        }
    }

    void print_table(const char* title, const std::string& ours, const std::vector<std::size_t>& sizes) const {
        std::printf("\n%s\n%-18s", title, "method");
        for (std::size_t n : sizes) std::printf("%12s", ("N=" + std::to_string(n)).c_str());
        std::printf("\n");
        for (const sim::IntegratorInfo& info : sim::kIntegrators) {
            std::printf("%-18s", std::string(info.name).c_str());
            for (std::size_t n : sizes) print_ratio(ours, "hand/", info.name, info.name, n);
            std::printf("\n");
        }
    }

    // Benchmarks that reported an error (a stopped World): the run fails.
    const std::vector<std::string>& failures() const { return failures_; }

private:
    template <class R>
    static bool failed(const R& run) {
        if constexpr (requires { run.skipped; }) {
            return static_cast<int>(run.skipped) != 0;  // Google Benchmark >= 1.8
        } else {
            return run.error_occurred;
        }
    }
    // The median of a benchmark's repetitions, s per particle-step (0: none ran).
    double median(const std::string& name) const {
        const auto it = samples_.find(name);
        if (it == samples_.end() || it->second.empty()) return 0.0;
        std::vector<double> v = it->second;
        const std::size_t mid = v.size() / 2;
        std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
        if (v.size() % 2 == 1) return v[mid];
        return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
    }
    void print_ratio(const std::string& top, const std::string& bottom, std::string_view a, std::string_view b,
                     std::size_t n) const {
        const double p = median(top + std::string(a) + "/" + std::to_string(n));
        const double q = median(bottom + std::string(b) + "/" + std::to_string(n));
        if (p <= 0.0 || q <= 0.0) {
            std::printf("%12s", "-");
        } else {
            std::printf("%12.2f", p / q);
        }
    }
    std::map<std::string, std::vector<double>> samples_;
    std::vector<std::string> failures_;
};

const std::vector<std::size_t> kSizes{1, 1000, 100000, 1000000};

void register_benchmarks() {
    for (const sim::IntegratorInfo& info : sim::kIntegrators) {
        const std::string name(info.name);
        for (std::size_t n : kSizes) {
            const auto size = static_cast<std::int64_t>(n);
            benchmark::RegisterBenchmark(("hand/" + name).c_str(), hand_cloud_bench, info.id)
                ->Arg(size)
                ->Unit(benchmark::kMicrosecond);
            benchmark::RegisterBenchmark(("stage/" + name).c_str(), world_cloud, info.id, false)
                ->Arg(size)
                ->Unit(benchmark::kMicrosecond);
            benchmark::RegisterBenchmark(("world/" + name).c_str(), world_cloud, info.id, true)
                ->Arg(size)
                ->Unit(benchmark::kMicrosecond);
        }
    }
    for (const char* method : kFixedCostMethods) {
        const sim::Integrator id = *sim::integrator_from_name(method);
        benchmark::RegisterBenchmark((std::string("FixedCost/") + method).c_str(), fixed_cost, id)
            ->Unit(benchmark::kNanosecond);
        benchmark::RegisterBenchmark((std::string("FixedCost/hand_") + method).c_str(), hand_fixed_cost, id)
            ->Unit(benchmark::kNanosecond);
    }
}

}  // namespace

int main(int argc, char** argv) {
    // The console's options as the flags would set them (read before
    // Initialize, which takes its flags out of argv).
    int options = benchmark::ConsoleReporter::OO_None;
    if (isatty(fileno(stdout))) options |= benchmark::ConsoleReporter::OO_Color;
    for (int i = 1; i < argc; ++i) {
        if (std::string_view(argv[i]) == "--benchmark_counters_tabular=true")
            options |= benchmark::ConsoleReporter::OO_Tabular;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_benchmarks();
    RatioReporter reporter(static_cast<benchmark::ConsoleReporter::OutputOptions>(options));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.print_ratios(kSizes);
    benchmark::Shutdown();
    for (const std::string& name : reporter.failures()) std::fprintf(stderr, "bench_sim: %s failed\n", name.c_str());
    return reporter.failures().empty() ? 0 : 1;
}
