// ns per particle-step of every integrator on a cloud of N free particles
// (gravity and linear drag, the particle-effect case), N = 1, 1e3, 1e5 and
// 1e6, three ways in one cell (cloud/METHOD/N): a hand-written loop of the
// method, the particles stage (the World with its watchdog off: forces and
// integration) and the whole step as a scene runs it, taking turns of about
// 1e6 particle-steps so that the load of the moment falls on all three
// (cloud_cell). The tables printed at the end are the figures to read
// (issue 17's targets at N >= 1e5: stage / hand <= 1.1 for the methods that
// evaluate forces once a step, world / hand <= 1.5, RK4 / symplectic Euler
// <= 4.5, four force evaluations to one). At N = 1 the ratio is mostly the
// fixed cost of a step (FixedCost below).
//
// Honest by construction: every kLapSteps steps (10 s simulated) the cloud is
// put back where it started, outside the timing, so it never leaves the
// watchdog's world box however many iterations run; the hand loop is put
// back the same way. After timing, the cell checks that both Worlds still
// run and took every step they were asked for (bench_world.h).
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
#include <chrono>
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

// --- hand-written loops -----------------------------------------------------------------

// The cloud as a student would write it: separate coordinate arrays
// (std::vector, each block 16 bytes into a cache line, where the World's
// start on one: sim::Vec3Array. In cache, at N = 1000, the World's stage
// reads 0.8-0.9 of this loop for that; at 1e5 and 1e6 it makes little
// difference. docs/fixed-cost-study.md, "Where the arrays start").
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

// --- the three, in turns ------------------------------------------------------------

// Particle-steps in one turn (10⁶: about 2 ms of a hand loop on this machine
// at any N; one step at N = 10⁶).
constexpr std::size_t kTurnParticleSteps = 1000000;

// One of a cell's three contestants: its step, its reset to the start, and
// where it is in its lap (it is put back every kLapSteps steps, untimed).
template <class Step, class Reset>
struct Contestant {
    Step step;
    Reset reset;
    int in_lap = 0;

    // Takes `steps` steps; returns the seconds they took (resets not counted).
    double run(std::size_t steps) {
        using Clock = std::chrono::steady_clock;
        double seconds = 0.0;
        while (steps > 0) {
            if (in_lap == kLapSteps) reset(), in_lap = 0;
            const auto now = std::min<std::size_t>(steps, static_cast<std::size_t>(kLapSteps - in_lap));
            const Clock::time_point start = Clock::now();
            for (std::size_t i = 0; i < now; ++i) step();
            seconds += std::chrono::duration<double>(Clock::now() - start).count();
            in_lap += static_cast<int>(now);
            steps -= now;
        }
        return seconds;
    }
};
template <class Step, class Reset>
Contestant(Step, Reset) -> Contestant<Step, Reset>;

// A World on the cloud, one step of `settings` a call; watchdog: the whole
// step as a scene runs it, without: the particles stage alone (forces and
// integration), which is what a hand loop does.
auto world_contestant(sim::World& world, const sim::StepSettings& settings, const sim::ParticleState& start) {
    return Contestant{[&world, &settings] {
                          world.step(settings);
                          benchmark::DoNotOptimize(world.state().x.span().c[0]);
                          benchmark::ClobberMemory();
                      },
                      [&world, &start] {
                          sim::ParticleState& s = world.edit_state();
                          s.x = start.x;
                          s.v = start.v;
                      }};
}

// One cell of the tables: the hand loop, the particles stage (a World with
// its watchdog off) and the whole step (a World with it on) on the same cloud
// take turns of kTurnParticleSteps particle-steps each, in rotating order,
// each turn after one untimed step that brings its arrays back into cache. The
// ratios are of times taken within milliseconds of each other, so that the
// load of the moment moves both sides alike (separate benchmarks half a
// second apart moved a ratio at N = 1e5 by a fifth from run to run). Counters:
// each one's ns per particle-step, and stage/hand, world/hand of the totals.
void cloud_cell(benchmark::State& state, sim::Integrator id) {
    const auto n = static_cast<std::size_t>(state.range(0));
    const std::size_t turn = std::max<std::size_t>(1, kTurnParticleSteps / n);
    const HandCloud hand_start = hand_cloud(n);
    HandCloud hand = hand_start;
    const HandStep hand_step_of = hand_step(id);
    Contestant by_hand{[&] {
                           hand_step_of(hand, kDt);
                           benchmark::DoNotOptimize(hand.x.data());
                           benchmark::ClobberMemory();
                       },
                       [&] { hand = hand_start; }};
    sim::World stage_world(cloud(n)), whole_world(cloud(n));
    stage_world.set_watchdog({.enabled = false});
    const sim::ParticleState start = stage_world.state();
    const sim::StepSettings settings{id, kDt, 1};
    auto stage = world_contestant(stage_world, settings, start);
    auto whole = world_contestant(whole_world, settings, start);

    double seconds[3] = {0.0, 0.0, 0.0};  // hand, stage, whole
    int first = 0;                        // who goes first this iteration
    for (auto _ : state) {                // the benchmark's own time: a round of three turns, with their untimed steps
        for (int k = 0; k < 3; ++k) {
            const int who = (first + k) % 3;
            auto take_turn = [&](auto& contestant) {
                contestant.run(1);  // untimed: the arrays back into cache
                seconds[who] += contestant.run(turn);
            };
            who == 0 ? take_turn(by_hand) : who == 1 ? take_turn(stage) : take_turn(whole);
        }
        first = (first + 1) % 3;
    }
    const std::uint64_t steps = state.iterations() * (turn + 1);
    if (!bench::still_running(state, stage_world, steps, "cloud, watchdog off") ||
        !bench::still_running(state, whole_world, steps, "cloud")) {
        return;
    }
    const double particle_steps = static_cast<double>(state.iterations() * turn) * static_cast<double>(n);
    state.counters["hand_ns"] = 1e9 * seconds[0] / particle_steps;
    state.counters["stage_ns"] = 1e9 * seconds[1] / particle_steps;
    state.counters["world_ns"] = 1e9 * seconds[2] / particle_steps;
    state.counters["stage/hand"] = seconds[1] / seconds[0];
    state.counters["world/hand"] = seconds[2] / seconds[0];
}

// --- the fixed cost ---------------------------------------------------------------------

void fixed_cost(benchmark::State& state, sim::Integrator id) {
    sim::World world(bench::fixed_cost_bead());
    const sim::StepSettings settings{id, kDt, 1};
    for (auto _ : state) {
        world.step(settings);
        benchmark::DoNotOptimize(world.state().x.span().c[0]);
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

// Prints the usual console table, keeps the counters of every run that did
// its work, and at the end the ratios the targets are stated in, each
// the median over --benchmark_repetitions=R (make bench: 3) of a cell's
// ratio (each repetition's own, of turns taken together: cloud_cell). Only
// the ratios of the repetitions' counters are medians here: a cell's
// stage_ns and hand_ns medians need not come from the same repetition.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    using ConsoleReporter::ConsoleReporter;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (failed(run)) failures_.push_back(run.benchmark_name());
            // Each repetition, or only their median where the console shows
            // aggregates alone (--benchmark_report_aggregates_only=true).
            const bool median_only = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
            if (failed(run) || (run.run_type != Run::RT_Iteration && !median_only)) continue;
            for (const auto& [name, counter] : run.counters) {
                samples_[run.run_name.str() + ":" + name].push_back(counter.value);
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }

    void print_ratios(const std::vector<std::size_t>& sizes) const {
        print_table(
            "The particles stage (World, watchdog off) / hand-written loop, per particle-step\n"
            "(target <= 1.1 at N >= 1e5; at N = 1 it is the fixed cost of a step):",
            "stage/hand", sizes);
        print_table("The whole step (World, watchdog on) / hand-written loop (target <= 1.5 at N >= 1e5):",
                    "world/hand", sizes);
        std::printf("%-18s", "rk4 / sympl. Euler");  // target <= 4.5: four force evaluations to one
        for (std::size_t n : sizes) {
            print_ratio(median(cell("rk4", n) + ":world_ns") / median(cell("symplectic_euler", n) + ":world_ns"));
        }
        std::printf("\n");
        std::printf(
            "\nThe fixed cost: a whole World step of one bead on one spring, ns, and in steps of the same\n"
            "bead hand-written (the same run; the targets are 50 ns and 120 ns on the machine of the issue):\n");
        for (const char* method : kFixedCostMethods) {
            const double world = median(std::string("FixedCost/") + method + ":per_step");
            const double hand = median(std::string("FixedCost/hand_") + method + ":per_step");
            if (!(world > 0.0) || !(hand > 0.0)) continue;
            std::printf("%-18s%9.1f ns = %6.1f hand steps of %.1f ns\n", method, 1e9 * world, world / hand, 1e9 * hand);
        }
    }

    void print_table(const char* title, const std::string& counter, const std::vector<std::size_t>& sizes) const {
        std::printf("\n%s\n%-18s", title, "method");
        for (std::size_t n : sizes) std::printf("%12s", ("N=" + std::to_string(n)).c_str());
        std::printf("\n");
        for (const sim::IntegratorInfo& info : sim::kIntegrators) {
            std::printf("%-18s", std::string(info.name).c_str());
            for (std::size_t n : sizes) print_ratio(median(cell(info.name, n) + ":" + counter));
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
    static std::string cell(std::string_view method, std::size_t n) {
        return "cloud/" + std::string(method) + "/" + std::to_string(n);
    }
    // The median of a counter's repetitions ("NAME:COUNTER"); NaN where none ran.
    double median(const std::string& name) const {
        const auto it = samples_.find(name);
        if (it == samples_.end() || it->second.empty()) return std::nan("");
        std::vector<double> v = it->second;
        const std::size_t mid = v.size() / 2;
        std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
        if (v.size() % 2 == 1) return v[mid];
        return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
    }
    static void print_ratio(double ratio) {
        if (std::isfinite(ratio)) {
            std::printf("%12.2f", ratio);
        } else {
            std::printf("%12s", "-");
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
            benchmark::RegisterBenchmark(("cloud/" + name).c_str(), cloud_cell, info.id)
                ->Arg(static_cast<std::int64_t>(n))
                ->Unit(benchmark::kMillisecond);
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
