#include "scenes/report/report_growth.h"
#include "scenes/report/report_stages.h"

#include "sim/mass_spring.h"
#include "sim/ragdoll.h"
#include "sim/random.h"
#include "sim/world.h"

#include <time.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

// Sections: the systems (one builder each, then the table of them); timing
// (every size of a system built and warmed up, then the repetitions round
// the sizes in turn); what the report writes; the public functions.

namespace scenes {
namespace {

using report::fmt;
using sim::Vec3;

// --- the systems -----------------------------------------------------------------------------

// A system at one size, and how to step it.
struct Built {
    sim::ParticleModel model;
    double dt = 1.0 / 60.0;  // s, one step (symplectic Euler, one substep)
    long warmup = 3;         // steps before timing: caches, and the motion's start-up
};

// n particles of 1 kg in a 10 m cube, thrown at up to 1 m/s, falling under
// gravity against linear drag of 5 N·s/m (terminal speed m g / c = 2 m/s).
// At dt = 1 ms a million steps (1000 s) fall 2 km: inside the watchdog's
// 10 km box, so no timing run can leave it.
Built free_particles(int n) {
    Built b;
    b.dt = 1e-3;
    sim::Random random(17);
    for (int i = 0; i < n; ++i) {
        sim::ParticleDef p;
        p.position = Vec3(random.uniform(-5.0, 5.0), random.uniform(0.0, 10.0), random.uniform(-5.0, 5.0));
        p.velocity = Vec3(random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0));
        b.model.particles.push_back(p);
    }
    b.model.forces.push_back(sim::UniformGravity{});
    b.model.forces.push_back(sim::LinearDrag{5.0});
    return b;
}

// The benchmark's cloth (tests/bench/bench_mass_spring.cpp) at n x n nodes:
// a 2 m square of 1 kg held by the two corners of one side, with
// structural, shear (0.5) and bend (0.1) links of 20 N/m, Hooke springs or
// inextensible XPBD constraints (one iteration, no tethers). A node weighs
// 1/n² kg, so the stiffest spring mode ω ≈ sqrt(6.4 k n² / 1 kg) = 11.3 n
// rad/s grows with n: dt = 0.032 s / n keeps ω dt = 0.36 (stable for any
// number of steps), and the XPBD cloth takes the same steps.
Built cloth(int nodes, sim::LinkSettings::Kind kind) {
    const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(nodes))));
    Built b;
    b.dt = 0.032 / n;
    b.warmup = 10;
    sim::ClothDef def;
    def.nx = def.ny = n;
    def.corner = Vec3(-1, 2, 0);
    def.u = Vec3(2, 0, 0);
    def.v = Vec3(0, 0, 2);
    def.mass = 1.0;
    def.pins = sim::ClothDef::Pins::corners;
    def.links.kind = kind;
    def.links.stiffness = 20.0;  // N/m
    def.links.damping = 0.001;   // N·s/m
    def.links.compliance = 0.0;  // m/N
    def.links.tethers = false;
    sim::add_cloth(b.model, def);
    b.model.forces.push_back(sim::UniformGravity{});
    return b;
}
Built spring_cloth(int nodes) { return cloth(nodes, sim::LinkSettings::Kind::springs); }
Built xpbd_cloth(int nodes) { return cloth(nodes, sim::LinkSettings::Kind::constraints); }

// n droplets from n / 500 fountains 6 m apart in a row (the fountain
// scene's nozzle: 6.5 m/s in a 12° cone), 1 g and 2.5 cm each, colliding
// with each other (the hash grid) and the ground. Each nozzle feeds 250
// droplets a second, each lives 2 s: the density of droplets, and so the
// grid's work per droplet, does not change as fountains are added. The 150
// warm-up steps (2.5 s) give every droplet its first birth.
Built fountains(int n) {
    constexpr int kPerFountain = 500;
    Built b;
    b.warmup = 150;
    for (int k = 0; k < n / kPerFountain; ++k) {
        sim::Emitter e;
        e.first = static_cast<std::uint32_t>(b.model.particles.size());
        e.count = kPerFountain;
        e.position = Vec3(6.0 * k, 0.3, 0);
        e.cone = 12.0;
        e.speed = 6.5;
        e.speed_jitter = 0.15;
        e.rate = 250.0;  // droplets/s
        e.seed = 7 + static_cast<std::uint64_t>(k);
        for (int i = 0; i < kPerFountain; ++i) {
            sim::ParticleDef p;
            p.position = sim::parked_position(e);
            p.mass = 0.001;
            p.radius = 0.025;
            p.pinned = true;
            b.model.particles.push_back(p);
        }
        b.model.emitters.push_back(e);
    }
    b.model.forces.push_back(sim::UniformGravity{});
    b.model.collisions.colliders.push_back(sim::PlaneCollider{});
    b.model.collisions.particle_particle = true;
    b.model.collisions.restitution = 0.3;
    b.model.collisions.friction = 0.2;
    return b;
}

// n stars of 1/n kg in a ball of radius 1 m, G = 1 m³/(kg·s²), softened over
// 0.1 m, with random velocities of 0.45 m/s per axis (a uniform ball's
// virial speed, <v²> = 3 G M / (5 R)) and no net momentum: a cluster that
// stays bound. dt = 1 ms.
Built n_body(int n) {
    Built b;
    b.dt = 1e-3;
    sim::Random random(23);
    Vec3 momentum = Vec3::Zero();  // kg·m/s
    for (int i = 0; i < n; ++i) {
        sim::ParticleDef p;
        do {
            p.position = Vec3(random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0));
        } while (p.position.squaredNorm() > 1.0);
        p.velocity = Vec3(random.normal(0.0, 0.45), random.normal(0.0, 0.45), random.normal(0.0, 0.45));
        p.mass = 1.0 / n;
        momentum += p.mass * p.velocity;
        b.model.particles.push_back(p);
    }
    for (sim::ParticleDef& p : b.model.particles) p.velocity -= momentum / 1.0;  // over the total mass, 1 kg
    b.model.forces.push_back(sim::NewtonGravity{1.0, 0.1});
    return b;
}

// n ragdolls (1.8 m, 75 kg, the builder's) lying face down on the ground
// plane, 8 to a row, 1.5 m apart across and 2.5 m along, dropped from 30 cm
// with ODE's defaults (quickstep, 20 iterations). Sleep is off: an asleep
// ragdoll costs nothing a step. The 90 warm-up steps (1.5 s) land them.
Built ragdolls(int n) {
    Built b;
    b.warmup = 90;
    b.model.rigid.settings.sleep = false;
    for (int k = 0; k < n; ++k) {
        sim::RagdollDef def;
        def.position = Vec3(1.5 * (k % 8), 0.3, 2.5 * (k / 8));
        def.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitX()));
        const sim::RagdollParts parts = sim::ragdoll_parts(def, static_cast<int>(b.model.rigid.bodies.size()));
        b.model.rigid.bodies.insert(b.model.rigid.bodies.end(), parts.bodies.begin(), parts.bodies.end());
        b.model.rigid.joints.insert(b.model.rigid.joints.end(), parts.joints.begin(), parts.joints.end());
    }
    return b;
}

struct System {
    const char* name;
    const char* size_unit;
    double expected;         // the exponent theory gives
    std::vector<int> sizes;  // a geometric ladder, wide enough that a step's fixed cost is small at its foot
    Built (*build)(int size);
};

const std::vector<System>& systems() {
    static const std::vector<System> list = {
        {"free particles", "particles", 1.0, {4096, 8192, 16384, 32768, 65536}, free_particles},
        {"mass-spring cloth", "particles", 1.0, {32 * 32, 45 * 45, 64 * 64, 91 * 91, 128 * 128}, spring_cloth},
        {"XPBD cloth", "particles", 1.0, {32 * 32, 45 * 45, 64 * 64, 91 * 91, 128 * 128}, xpbd_cloth},
        {"fountains (particle collisions)", "particles", 1.0, {500, 1000, 2000, 4000, 8000}, fountains},
        {"N-body (Newton gravity)", "particles", 2.0, {64, 128, 256, 512}, n_body},
        {"ragdolls (ODE)", "ragdolls", 1.0, {2, 4, 8, 16, 32}, ragdolls},
    };
    return list;
}

// --- timing ---------------------------------------------------------------------------------

// This thread's CPU time, s. Not the wall clock: on a loaded machine (a CI
// runner's other jobs, a build beside the tests) the time the thread waits
// for a core would land on whichever sizes it happened to, and bend the
// fitted exponent (measured: 1.4 for free particles at a load of 8 on two
// cores, by the wall clock).
double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// CPU time of `steps` steps, s.
double run(sim::World& world, const sim::StepSettings& step, long steps) {
    const double start = cpu_seconds();
    for (long i = 0; i < steps; ++i) world.step(step);
    return cpu_seconds() - start;
}

// One size of a system being timed.
struct Timed {
    std::string what;  // "N-body (Newton gravity) at 512 particles": what an error names
    std::unique_ptr<sim::World> world;
    sim::StepSettings step;
    long asked = 0;                                         // steps asked of the World so far
    long steps = 1;                                         // per timed repetition
    double best = std::numeric_limits<double>::infinity();  // s per step, the fastest repetition
};

// Builds and warms up one size; a probe of doubling step counts finds how
// many steps last min_seconds.
Timed prepare(const System& system, int size, const GrowthTiming& timing) {
    Built built = system.build(size);
    Timed t{std::string(system.name) + " at " + std::to_string(size) + " " + system.size_unit,
            std::make_unique<sim::World>(std::move(built.model)),
            {sim::Integrator::symplectic_euler, built.dt, 1}};
    run(*t.world, t.step, built.warmup);
    t.asked = built.warmup;
    long probe = 1;
    double probed = run(*t.world, t.step, probe);  // s
    t.asked += probe;
    while (probed < timing.min_seconds / 4.0 && !t.world->verdict().exploded()) {
        probe *= 2;
        probed = run(*t.world, t.step, probe);
        t.asked += probe;
    }
    t.steps = std::max(1L, std::lround(std::ceil(timing.min_seconds * probe / probed)));
    return t;
}

// A stopped World does nothing a step: its time would be a lie.
void require_running(const Timed& t) {
    if (t.world->verdict().exploded()) {
        throw std::runtime_error("report: how cost grows: the World stopped, so its time is no measure: " +
                                 t.world->verdict().message(t.what));
    }
    if (t.world->steps() != static_cast<std::uint64_t>(t.asked)) {
        throw std::runtime_error("report: how cost grows: " + t.what + " made " + std::to_string(t.world->steps()) +
                                 " steps of the " + std::to_string(t.asked) + " asked");
    }
}

// Seconds per step of `system` at each of its sizes. The repetitions go
// round the sizes in turn, so that a burst of load from elsewhere on the
// machine slows one repetition of several sizes rather than every
// repetition of one (and bends the fitted line).
std::vector<double> time_system(const System& system, const GrowthTiming& timing) {
    std::vector<Timed> timed;
    for (const int size : system.sizes) timed.push_back(prepare(system, size, timing));
    for (int r = 0; r < timing.repetitions; ++r) {
        for (Timed& t : timed) {
            t.best = std::min(t.best, run(*t.world, t.step, t.steps) / t.steps);
            t.asked += t.steps;
        }
    }
    std::vector<double> seconds;
    for (const Timed& t : timed) {
        require_running(t);
        seconds.push_back(t.best);
    }
    return seconds;
}

// --- what the report writes --------------------------------------------------------------------

// One line per system, its fitted slope in the key. The y range reaches a
// decade below the cheapest point: room for the key, bottom right.
std::string plot_script(const std::vector<GrowthSeries>& series) {
    static const char* colors[] = {"#1f77b4", "#2ca02c", "#17becf", "#ff7f0e", "#d62728", "#9467bd"};
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;  // s
    for (const GrowthSeries& g : series) {
        for (const double t : g.seconds_per_step) lo = std::min(lo, t), hi = std::max(hi, t);
    }
    std::ostringstream s;
    s << "set output 'growth.png'\nset logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
      << "set yrange [" << fmt("%.0e", std::pow(10.0, std::floor(std::log10(lo)) - 1.0)) << ':'
      << fmt("%.0e", std::pow(10.0, std::ceil(std::log10(hi)))) << "]\n"
      << "set key bottom right box opaque\n"
         "set title 'How cost grows with size: CPU time of one step'\n"
         "set xlabel 'size (particles; ragdolls for ODE)'\nset ylabel 'CPU time per step (s)'\n";
    for (std::size_t k = 0; k < series.size(); ++k) {
        s << (k == 0 ? "plot " : ", \\\n     ") << "'growth.dat' index " << k
          << " using 1:2 with linespoints lw 2 lc rgb '" << colors[k % 6] << "' pt " << 5 + 2 * (k % 6) << " title '"
          << series[k].system << " (slope " << fmt("%.2f", series[k].exponent) << ")' noenhanced";
    }
    s << '\n';
    return s.str();
}

// The section's table and what it teaches, with the measured numbers.
std::string markdown(const std::vector<GrowthSeries>& series) {
    std::ostringstream md;
    md << "\n## How cost grows with size\n\n![how cost grows](growth.png)\n\n"
       << "CPU time of one step (this thread's, so that other work on the machine is left out; the fastest of repeated "
          "runs of many steps) against the system's size, both "
          "axes logarithmic: cost ∝ size^p is a line of slope p, the fitted exponent.\n\n"
       << "| system | sizes | fitted exponent | expected | per step at the largest size |\n|---|---|---|---|---|\n";
    for (const GrowthSeries& g : series) {
        md << "| " << g.system << " | " << g.sizes.front() << " to " << g.sizes.back() << ' ' << g.size_unit << " | "
           << fmt("%.2f", g.exponent) << " | " << fmt("%.0f", g.expected) << " | "
           << fmt("%.3g", g.seconds_per_step.back() * 1e3) << " ms |\n";
    }
    const GrowthSeries* all_pairs = nullptr;
    for (const GrowthSeries& g : series)
        if (g.expected == 2.0) all_pairs = &g;
    const GrowthSeries& free = series.front();
    md << "\nWhat it teaches: whatever is local (free particles, a cloth's springs or constraints, the joints and "
          "contacts of ragdolls) or spatially hashed (droplets colliding only with their neighbours) costs in "
          "proportion to its size: twice the particles, twice the time. All-pairs gravity costs in proportion to "
          "the square: twice the bodies, four times the time";
    if (all_pairs != nullptr) {
        const double per_body = all_pairs->seconds_per_step.back() / all_pairs->sizes.back();  // s
        const double per_free = free.seconds_per_step.back() / free.sizes.back();              // s
        md << " (at " << all_pairs->sizes.back() << " bodies, " << fmt("%.3g", per_body * 1e6) << " µs a body a step, "
           << fmt("%.0f", per_body / per_free) << " times a free particle's " << fmt("%.2g", per_free * 1e9) << " ns)";
    }
    md << ". So model only what a scene needs: a uniform field where mutual gravity does not show, collisions "
          "only between what can touch, and all pairs only for the handful of bodies that need them.\n";
    return md.str();
}

}  // namespace

GrowthTiming growth_timing(bool quick) { return {quick ? 0.02 : 0.1, 3}; }

std::size_t growth_system_count() { return systems().size(); }

std::vector<GrowthSeries> measure_growth(const GrowthTiming& timing,
                                         const std::function<void(const std::string&)>& done) {
    std::vector<GrowthSeries> out;
    for (const System& system : systems()) {
        GrowthSeries g{system.name, system.size_unit, system.sizes, time_system(system, timing), 0.0, system.expected};
        g.exponent = fit_exponent(g.sizes, g.seconds_per_step);
        out.push_back(g);
        done(system.name);
    }
    return out;
}

double fit_exponent(const std::vector<int>& sizes, const std::vector<double>& seconds) {
    const std::size_t n = std::min(sizes.size(), seconds.size());
    double mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < n; ++i) mx += std::log(sizes[i]) / n, my += std::log(seconds[i]) / n;
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = std::log(sizes[i]) - mx;
        sxy += dx * (std::log(seconds[i]) - my);
        sxx += dx * dx;
    }
    return sxx > 0.0 ? sxy / sxx : std::nan("");
}

GrowthFiles growth_files(const std::vector<GrowthSeries>& series) {
    GrowthFiles f;
    std::ostringstream csv, data;
    csv << "system,size,seconds_per_step\n";
    f.json = nlohmann::json::array();
    for (const GrowthSeries& g : series) {
        data << "# " << g.system << " (" << g.size_unit << ", seconds per step)\n";
        for (std::size_t i = 0; i < g.sizes.size(); ++i) {
            csv << g.system << ',' << g.sizes[i] << ',' << fmt("%.6e", g.seconds_per_step[i]) << '\n';
            data << g.sizes[i] << ' ' << fmt("%.6e", g.seconds_per_step[i]) << '\n';
        }
        data << "\n\n";
        f.json.push_back({{"system", g.system},
                          {"size_unit", g.size_unit},
                          {"sizes", g.sizes},
                          {"seconds_per_step", g.seconds_per_step},
                          {"exponent", g.exponent},
                          {"expected", g.expected}});
    }
    f.csv = csv.str();
    f.plot_data = data.str();
    f.plot_script = plot_script(series);
    f.markdown = markdown(series);
    return f;
}

}  // namespace scenes
