#include "scenes/report/report.h"

#include "render/gl_context.h"
#include "render/renderer.h"
#include "scenes/common/interrupt.h"
#include "scenes/common/progress.h"
#include "scenes/report/report_growth.h"
#include "scenes/report/report_peers.h"
#include "scenes/model/scene.h"
#include "scenes/draw/scene_run.h"

#include "sim/analytic.h"
#include "sim/error.h"
#include "sim/integrators.h"
#include "sim/mass_spring.h"
#include "sim/problems.h"
#include "sim/ragdoll.h"
#include "sim/world.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace scenes {
namespace {

namespace fs = std::filesystem;
using sim::Integrator;
using sim::IntegratorInfo;
using sim::Vec3;
using sim::analytic::PointState;
using Clock = std::chrono::steady_clock;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The fit of an order uses errors in this band: below it rounding dominates,
// above it the method is not yet in its asymptotic regime.
constexpr double kFitFloor = 1e-11;
constexpr double kFitCeiling = 5e-2;

// --- the problems ---------------------------------------------------------------------

struct Problem {
    std::string name;        // file and table name
    std::string title;       // what it is, one line
    std::string error_unit;  // of the global error
    double end = 1.0;        // s
    // The coarsest dt of the sweep for methods of order 1, 2 and 4 (s):
    // each starts where its error is about to enter its asymptotic regime.
    double dt1 = 0.0025, dt2 = 0.01, dt4 = 0.02;
    bool smooth = true;  // the fitted order should be the method's (no constraint projection)
    bool drag = false;   // a velocity-dependent force: kick-drift-kick leapfrog is first order then
    std::function<sim::ParticleModel()> model;
    std::size_t particle = 0;                   // the particle compared with the closed form
    std::function<PointState(double t)> exact;  // its closed form; empty: the pendulum's period
    double period = 0.0;                        // s, the pendulum's exact period
};

const sim::analytic::Oscillator kOscillator{1.0, 1.0, 0.0};  // ω = 1 rad/s
const sim::analytic::Oscillator kDamped{1.0, 1.0, 0.2};      // ζ = 0.1
const Vec3 kOscX0{1.0, 0.0, 0.0};
const Vec3 kOscV0{0.0, 0.5, 0.0};
constexpr double kPendulumLength = 1.0;                                  // m
constexpr double kPendulumAmplitude = 120.0 * std::numbers::pi / 180.0;  // rad
constexpr double kG = 9.81;                                              // m/s²

// A bob on an inextensible XPBD rod of length L from a pinned pivot at the
// origin, released at rest kPendulumAmplitude from the downward vertical.
sim::ParticleModel pendulum_model() {
    sim::ParticleModel model;
    model.particles.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, true});
    const Vec3 bob(kPendulumLength * std::sin(kPendulumAmplitude), -kPendulumLength * std::cos(kPendulumAmplitude), 0);
    model.particles.push_back({bob, Vec3::Zero(), 1.0, false});
    model.forces.push_back(sim::UniformGravity{Vec3(0, -kG, 0)});
    model.constraints.distance.push_back({0, 1, kPendulumLength, 0.0});
    return model;
}

std::vector<Problem> problems() {
    namespace pr = sim::problems;
    std::vector<Problem> out;
    out.push_back(
        {"ballistic", "ballistic shot, 1 s (exact for every method of order 2 or more)", "m", 1.0, 0.0125, 0.05, 0.1,
         true, false, [] { return pr::ballistic_model(); }, 0,
         [](double t) { return sim::analytic::ballistic(Vec3::Zero(), pr::kShotVelocity, pr::kShotGravity, t); }});
    out.push_back({"oscillator", "harmonic oscillator, ω = 1 rad/s, 10 s", "m", 10.0, 0.005, 0.02, 0.04, true, false,
                   [] { return pr::oscillator_model(kOscillator, kOscX0, kOscV0); }, 1,
                   [](double t) { return sim::analytic::oscillator(kOscillator, kOscX0, kOscV0, t); }});
    // The damper is linear drag on the bob (-c v, every direction), as the closed form has it.
    out.push_back({"damped", "damped oscillator, ζ = 0.1, 10 s", "m", 10.0, 0.005, 0.02, 0.04, true, true,
                   [] {
                       sim::ParticleModel m = pr::oscillator_model(kOscillator, kOscX0, kOscV0);
                       m.forces.push_back(sim::LinearDrag{kDamped.damping});
                       return m;
                   },
                   1, [](double t) { return sim::analytic::oscillator(kDamped, kOscX0, kOscV0, t); }});
    for (const double e : {0.5, 0.9}) {
        const std::string tag = e == 0.5 ? "kepler_e0.5" : "kepler_e0.9";
        out.push_back(
            {tag, "Kepler orbit, e = " + std::string(e == 0.5 ? "0.5" : "0.9") + ", 5 s of its 2π s period", "m", 5.0,
             e == 0.5 ? 0.00125 : 6.25e-5, e == 0.5 ? 0.005 : 0.001, e == 0.5 ? 0.01 : 0.002, true, false,
             [e] { return pr::kepler_model(e); }, 1,
             [e](double t) { return sim::analytic::kepler(pr::kKeplerMu, pr::kepler_r0(e), pr::kepler_v0(e), t); }});
    }
    Problem pendulum{"pendulum", "pendulum on an XPBD rod, released 120° out: its period against the elliptic integral",
                     "s",        0.0,
                     0.00125,    0.00125,
                     0.00125,    false,
                     false,      pendulum_model,
                     1,          {}};
    pendulum.period = sim::analytic::pendulum_period(kPendulumLength, kG, kPendulumAmplitude);
    pendulum.end = 2.0 * pendulum.period;
    out.push_back(pendulum);
    return out;
}

// The order theory gives the method on the problem; 0: none applies (the
// pendulum's projection), or the method is exact (order >= 2 on the ballistic shot).
int expected_order(const Problem& p, const IntegratorInfo& info) {
    if (!p.smooth || (p.name == "ballistic" && info.order >= 2)) return 0;
    // Kick-drift-kick leapfrog's second kick sees the half-step velocity: with
    // a velocity-dependent force its velocity, and so its orbit, is first order.
    if (p.drag && info.id == Integrator::leapfrog) return 1;
    return info.order;
}

double coarsest_dt(const Problem& p, const IntegratorInfo& info) {
    return info.order <= 1 ? p.dt1 : info.order >= 4 ? p.dt4 : p.dt2;
}

// --- one run ---------------------------------------------------------------------------

struct Sample {
    std::string problem;
    std::string integrator;
    double dt = 0.0;  // s
    long steps = 0;
    double error = kNaN;         // in the problem's unit; NaN: exploded
    double energy_error = kNaN;  // |E(T) - E_exact(T)| / |E0|
    double evaluations = 0.0;    // force evaluations per simulated second
    double seconds = 0.0;        // wall time per simulated second, median of the repetitions
    bool exploded = false;
};

double energy_of(const sim::ParticleModel& model, std::size_t particle, const PointState& s) {
    sim::ParticleModel at = model;
    at.particles[particle].position = s.x;
    at.particles[particle].velocity = s.v;
    return sim::World(at).energy();
}

// The times the particle crosses x = 0 going from -x to +x, interpolated.
struct Crossings {
    std::vector<double> times;
    double previous_x = 0.0;
    double previous_t = 0.0;
    void see(double t, double x) {
        if (previous_x < 0.0 && x >= 0.0)
            times.push_back(previous_t + (t - previous_t) * previous_x / (previous_x - x));
        previous_x = x, previous_t = t;
    }
};

// Timing: at least `repetitions` runs, and more while they add up to under
// min_seconds (short runs are at the mercy of the clock); the median of all.
struct Timing {
    int repetitions = 1;
    double min_seconds = 0.005;  // s
};

Sample measure(const Problem& p, const IntegratorInfo& info, double dt, Timing timing) {
    int repetitions = timing.repetitions;
    Sample s{p.name, std::string(info.name), dt};
    s.steps = std::lround(p.end / dt);
    const sim::ParticleModel model = p.model();
    std::vector<double> times;
    double total = 0.0;  // s, timed so far
    for (int r = 0; r < repetitions || (total < timing.min_seconds && r < 10000); ++r) {
        sim::World world(model);
        const double e0 = world.energy();
        Crossings crossings;
        crossings.previous_x = world.state().x.get(p.particle).x();
        const auto start = Clock::now();
        for (long i = 0; i < s.steps && !world.verdict().exploded(); ++i) {
            world.step({info.id, dt, 1});
            if (!p.exact) crossings.see(world.state().t, world.state().x.get(p.particle).x());
        }
        times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        total += times.back();
        // A run of half a second or more times itself well enough: no repetitions.
        if (times.back() >= 0.5) repetitions = r + 1;
        if (r + 1 < repetitions || (total < timing.min_seconds && r + 1 < 10000)) continue;
        const double t = world.state().t;
        s.evaluations = world.force_evaluations() / t;
        s.exploded = world.verdict().exploded() || !world.state().x.get(p.particle).allFinite();
        if (s.exploded) break;
        if (p.exact) {
            const PointState exact = p.exact(t);
            s.error = (world.state().x.get(p.particle) - exact.x).norm();
            s.energy_error = std::abs(world.energy() - energy_of(model, p.particle, exact)) / std::abs(e0);
        } else {
            s.error = crossings.times.size() >= 2 ? std::abs(crossings.times[1] - crossings.times[0] - p.period) : kNaN;
            s.energy_error = std::abs(world.energy() - e0) / std::abs(e0);
        }
    }
    std::sort(times.begin(), times.end());
    s.seconds = times[times.size() / 2] / p.end;
    return s;
}

// Least-squares slope of log(error) on log(dt) over the errors in the fit band.
struct Fit {
    double slope = kNaN;
    int points = 0;
};
Fit fit_order(const std::vector<Sample>& samples) {
    std::vector<std::pair<double, double>> xy;
    for (const Sample& s : samples) {
        if (std::isfinite(s.error) && s.error >= kFitFloor && s.error <= kFitCeiling) {
            xy.emplace_back(std::log(s.dt), std::log(s.error));
        }
    }
    Fit f;
    f.points = static_cast<int>(xy.size());
    if (xy.size() < 3) return f;
    double mx = 0, my = 0;
    for (const auto& [x, y] : xy) mx += x, my += y;
    mx /= static_cast<double>(xy.size()), my /= static_cast<double>(xy.size());
    double sxy = 0, sxx = 0;
    for (const auto& [x, y] : xy) sxy += (x - mx) * (y - my), sxx += (x - mx) * (x - mx);
    f.slope = sxy / sxx;
    return f;
}

// --- peers: boost::odeint on the same problems ----------------------------------------------

Sample measure_peer(const Problem& p, const PeerInfo& peer, double dt, Timing timing) {
    Sample s{p.name, peer.name, dt};
    s.steps = std::lround(p.end / dt);
    const sim::ParticleModel model = p.model();
    const Vec3 x0 = model.particles[p.particle].position, v0 = model.particles[p.particle].velocity;
    std::vector<double> times;
    PeerRun run;
    double total = 0.0;  // s, timed so far
    for (int r = 0; r < timing.repetitions || (total < timing.min_seconds && r < 10000); ++r) {
        run = run_peer(peer.name, p.name, x0, v0, dt, s.steps);
        times.push_back(run.seconds);
        total += run.seconds;
        if (run.seconds >= 0.5) break;
    }
    std::sort(times.begin(), times.end());
    const double t = static_cast<double>(s.steps) * dt;
    s.seconds = times[times.size() / 2] / p.end;
    s.evaluations = peer.evaluations * static_cast<double>(s.steps) / t;
    s.exploded = !run.x.allFinite();
    if (!s.exploded) s.error = (run.x - p.exact(t).x).norm();
    return s;
}

// Our cost at the peer's error, interpolated log-log along our sweep, over
// the peer's: the median over the peer's points in the fit band. NaN when
// the curves do not overlap.
double cost_ratio(const std::vector<Sample>& ours, const std::vector<Sample>& theirs) {
    std::vector<double> ratios;
    for (const Sample& t : theirs) {
        if (!std::isfinite(t.error) || t.error < kFitFloor || t.error > kFitCeiling) continue;
        for (std::size_t i = 0; i + 1 < ours.size(); ++i) {
            const Sample &a = ours[i], &b = ours[i + 1];  // a coarser than b: a.error > b.error
            if (!(std::isfinite(a.error) && std::isfinite(b.error)) || a.error <= 0 || b.error <= 0) continue;
            if (!(t.error <= a.error && t.error >= b.error) || a.error == b.error) continue;
            const double f = std::log(t.error / a.error) / std::log(b.error / a.error);
            const double seconds = std::exp(std::log(a.seconds) + f * (std::log(b.seconds) - std::log(a.seconds)));
            ratios.push_back(seconds / t.seconds);
            break;
        }
    }
    if (ratios.empty()) return kNaN;
    std::sort(ratios.begin(), ratios.end());
    return ratios[ratios.size() / 2];
}

// The target for the batch: our cost per copy at equal error at most
// this many times odeint's (the World's fixed cost spread over 1000 copies).
constexpr double kBatchTarget = 1.2;

// The batch's cost ratio at equal error. A step of a copy costs the same
// whatever the dt, and each copy is the problem (its error at a dt is the
// single copy's), so: (our seconds per step per copy / odeint's) x (the
// steps we need / the steps they need for the same error), the second
// factor read from the single copy's sweeps as cost_ratio reads seconds (1
// for the same method: the same error at the same dt). Where the sweeps'
// errors do not overlap the ratio is at equal dt: the ballistic shot (both
// methods exact: every error is round-off), or odeint's first-order velocity
// Verlet on the damped oscillator (ours is second order: more accurate at
// the same dt, so equal dt bounds the ratio at equal error from above).
struct BatchRatio {
    double steps_ratio = kNaN;  // our steps / theirs at equal error; NaN: no overlap
    double ratio = kNaN;
    std::string basis;  // "equal error", "equal dt, both exact", "equal dt, an upper bound"
};
BatchRatio batch_ratio(const BatchResult& batch, const std::vector<Sample>& ours, const std::vector<Sample>& theirs) {
    auto steps_of = [](std::vector<Sample> sweep) {
        for (Sample& s : sweep) s.seconds = 1.0 / s.dt;  // steps per simulated second
        return sweep;
    };
    auto exact = [](const std::vector<Sample>& sweep) {
        return std::all_of(sweep.begin(), sweep.end(), [](const Sample& s) { return s.error < kFitFloor; });
    };
    BatchRatio r;
    const double per_step = batch.ours_seconds / batch.theirs_seconds;
    r.steps_ratio = cost_ratio(steps_of(ours), steps_of(theirs));
    if (std::isfinite(r.steps_ratio)) {
        r.ratio = per_step * r.steps_ratio;
        r.basis = "equal error";
    } else if (exact(ours) && exact(theirs)) {
        r.ratio = per_step;
        r.basis = "equal dt, both exact";
    } else if (batch.ours_error < batch.theirs_error) {
        r.ratio = per_step;
        r.basis = "equal dt, an upper bound";
    }
    return r;
}

// --- energy drift over long runs ----------------------------------------------------------

struct Drift {
    std::string integrator;
    std::string problem;
    double first_half = 0.0;   // max |E - E0| / |E0| over the first half of the run
    double second_half = 0.0;  // ... over the second half
    bool exploded = false;
    std::vector<std::pair<double, double>> envelope;  // (t, running max of |E - E0| / |E0|), for the plot
    bool bounded() const { return !exploded && second_half <= 1.2 * first_half + 1e-13; }
};

Drift drift(const std::string& name, const sim::ParticleModel& model, const IntegratorInfo& info, double dt,
            double end) {
    Drift d{std::string(info.name), name};
    sim::World world(model);
    const double e0 = world.energy();
    const long steps = std::lround(end / dt);
    double running = 0.0;
    for (long i = 1; i <= steps; ++i) {
        world.step({info.id, dt, 1});
        if (world.verdict().exploded()) {
            d.exploded = true;
            break;
        }
        const double e = std::abs(world.energy() - e0) / std::abs(e0);
        running = std::max(running, e);
        (2 * i <= steps ? d.first_half : d.second_half) = std::max(2 * i <= steps ? d.first_half : d.second_half, e);
        if (i % std::max(1L, steps / 400) == 0) d.envelope.emplace_back(world.state().t, std::max(running, 1e-17));
    }
    return d;
}

// --- stability on a stiff spring -----------------------------------------------------------

constexpr double kStiffK = 1e6;    // N/m on 1 kg: ω = 1000 rad/s, ω h = 16.7 at 1/60 s
constexpr double kStiffEnd = 2.0;  // s

struct Stability {
    std::string integrator;
    double largest_dt = 0.0;       // s, the largest stable dt found (upper end of the search if never unstable)
    bool always_stable = false;    // stable up to the search's upper end
    bool stable_at_frame = false;  // at 1/60 s
    std::uint64_t exploded_frame = 0;
    std::string quantity;  // what the watchdog saw at 1/60 s
};

sim::Verdict stiff_run(const IntegratorInfo& info, double dt) {
    sim::World world(sim::problems::oscillator_model({1.0, kStiffK, 0.0}, Vec3(0.01, 0, 0), Vec3::Zero()));
    // Exploded once it moves 100 times faster than its own swing (ω A = 10 m/s):
    // an unstable method's amplitude grows without bound, a stable one's
    // energy may wobble (symplectic Euler's by a factor near 2/(1 - (ω h / 2)²)) but stays bounded.
    sim::WatchdogLimits limits;
    limits.max_speed = 100.0 * std::sqrt(kStiffK) * 0.01;  // m/s
    world.set_watchdog(limits);
    const long steps = std::max(1L, std::lround(kStiffEnd / dt));
    for (long i = 0; i < steps && !world.verdict().exploded(); ++i) world.step({info.id, dt, 1});
    return world.verdict();
}

Stability stability(const IntegratorInfo& info, int bisections) {
    Stability s{std::string(info.name)};
    const sim::Verdict at_frame = stiff_run(info, 1.0 / 60.0);
    s.stable_at_frame = !at_frame.exploded();
    s.exploded_frame = at_frame.frame;
    s.quantity = at_frame.quantity;
    double lo = 1e-6, hi = 0.25;  // s
    if (!stiff_run(info, hi).exploded()) {
        s.always_stable = true;
        s.largest_dt = hi;
        return s;
    }
    if (stiff_run(info, lo).exploded()) return s;  // unstable down to 1 µs
    for (int i = 0; i < bisections; ++i) {
        const double mid = std::sqrt(lo * hi);
        (stiff_run(info, mid).exploded() ? hi : lo) = mid;
    }
    s.largest_dt = lo;
    return s;
}

// --- stability maps: hard cases, per method --------------------------------------------------

// A hard case whose stiffness can be scaled: the largest stable dt at its own
// stiffness, and the largest stable stiffness at 1/60 s, per method, the
// watchdog deciding.
struct HardCase {
    std::string name;
    std::string title;
    double stiffness = 1.0;  // N/m, nominal
    double end = 1.0;        // s simulated per trial
    std::function<sim::ParticleModel(double k)> model;
    sim::WatchdogLimits limits;
};

std::vector<HardCase> hard_cases() {
    std::vector<HardCase> out;
    {
        HardCase c{"stiff_spring", "stiff spring, 1 kg", kStiffK, kStiffEnd, [](double k) {
                       return sim::problems::oscillator_model({1.0, k, 0.0}, Vec3(0.01, 0, 0), Vec3::Zero());
                   }};
        c.limits.max_speed = 100.0 * std::sqrt(kStiffK) * 0.01;  // m/s, as stiff_run
        out.push_back(c);
    }
    {
        HardCase c{"cloth", "cloth 12x12, 0.5 kg, hung by one edge", 2000.0, 1.0, [](double k) {
                       sim::ParticleModel m;
                       sim::ClothDef cloth;
                       cloth.nx = cloth.ny = 12;
                       cloth.mass = 0.5;
                       cloth.pins = sim::ClothDef::Pins::edge;
                       cloth.links.stiffness = k;
                       sim::add_cloth(m, cloth);
                       m.forces.push_back(sim::UniformGravity{Vec3(0, -kG, 0)});
                       return m;
                   }};
        c.limits.max_speed = 50.0;  // m/s: a 2 m cloth falling 2 m reaches 6
        c.limits.world_half_extent = 100.0;
        out.push_back(c);
    }
    {
        HardCase c{"chain_1000_1", "chain of 8 links of 1 g and a 1 kg ball (1000:1)", 2000.0, 1.0, [](double k) {
                       sim::ParticleModel m;
                       sim::RopeDef rope;
                       rope.segments = 8;
                       rope.mass = 0.009;  // kg: 1 g a node
                       rope.start = Vec3(0, 2, 0);
                       rope.end = Vec3(1.6, 2, 0);
                       rope.links.stiffness = k;
                       const sim::BodyRange r = sim::add_rope(m, rope);
                       const auto last = static_cast<std::uint32_t>(r.first + r.count - 1);
                       m.particles.push_back({Vec3(1.8, 2, 0), Vec3::Zero(), 1.0, false});
                       m.forces.push_back(
                           sim::Springs{{{last, static_cast<std::uint32_t>(m.particles.size() - 1), 0.2, k, 0.0}}});
                       m.forces.push_back(sim::UniformGravity{Vec3(0, -kG, 0)});
                       return m;
                   }};
        c.limits.max_speed = 50.0;
        c.limits.world_half_extent = 100.0;
        out.push_back(c);
    }
    return out;
}

bool explodes(const HardCase& c, const IntegratorInfo& info, double dt, double k) {
    sim::World world(c.model(k));
    world.set_watchdog(c.limits);
    const long steps = std::max(1L, std::lround(c.end / dt));
    for (long i = 0; i < steps && !world.verdict().exploded(); ++i) world.step({info.id, dt, 1});
    return world.verdict().exploded();
}

// The largest value in [lo, hi] at which `stable` holds, by bisection in log
// (stable below a threshold, unstable above it). `hi` when stable there;
// 0 when unstable at lo.
double largest_stable(double lo, double hi, int bisections, const std::function<bool(double)>& stable) {
    if (stable(hi)) return hi;
    if (!stable(lo)) return 0.0;
    for (int i = 0; i < bisections; ++i) {
        const double mid = std::sqrt(lo * hi);
        (stable(mid) ? lo : hi) = mid;
    }
    return lo;
}

struct MapCell {
    std::string hard_case, integrator;
    double largest_dt = 0.0;         // s; the search's upper end if always stable, 0 if unstable at its lower end
    double largest_stiffness = 0.0;  // N/m at 1/60 s (0: none; NaN: not a spring case)
};

constexpr double kDtLo = 1e-5, kDtHi = 0.25;  // s, the dt search
constexpr double kKLo = 1.0, kKHi = 1e10;     // N/m, the stiffness search at 1/60 s

// A ragdoll thrown at 10 m/s steps with ODE whatever the integrator: the
// largest dt of ODE's quickstep (the ragdoll scene's 40 iterations) at which
// it stays finite, under 100 m/s and with its joints within 10 cm after 2 s.
double ragdoll_largest_dt(int bisections) {
    const SceneDef scene = load_scene(resolve_scene("ragdoll"));
    auto stable = [&](double dt) {
        sim::RigidSettings settings = scene.model.rigid.settings;
        settings.sleep = false;
        sim::RigidWorld world(settings);
        sim::RagdollDef def;
        def.position = Vec3(0, 1.5, 0);
        def.velocity = Vec3(6, 8, 0);
        def.angular_velocity = Vec3(1, 0, -3);
        const sim::Ragdoll doll = sim::create_ragdoll(world, def);
        const long steps = std::max(1L, std::lround(2.0 / dt));
        for (long i = 0; i < steps; ++i) {
            world.step(dt);
            for (const sim::BodyId b : doll.bodies) {
                const sim::BodyState st = world.state(b);
                if (!st.position.allFinite() || st.velocity.norm() > 100.0) return false;
            }
        }
        for (const sim::JointId j : doll.joints)
            if (world.joint_separation(j) > 0.1) return false;
        return true;
    };
    return largest_stable(1e-3, kDtHi, bisections, stable);
}

// --- the XPBD "small steps" claim -----------------------------------------------------------

// Macklin et al. (2019): n substeps of one iteration beat one step of n
// iterations. A hanging rope and a cloth held by one edge, inextensible XPBD
// links without tethers, 2 s at 1/60 s frames: the largest strain at the end
// and the time per frame, either way.
struct SmallSteps {
    std::string body;  // rope, cloth
    std::string way;   // substeps, iterations
    int n = 1;
    double strain = 0.0;  // max |length / rest - 1| over the links at the end
    double ms_per_frame = 0.0;
};

SmallSteps small_steps(const std::string& body, bool substeps, int n) {
    sim::ParticleModel m;
    sim::LinkSettings links;
    links.kind = sim::LinkSettings::Kind::constraints;
    links.compliance = 0.0;
    links.tethers = false;
    if (body == "rope") {
        sim::RopeDef rope;
        rope.segments = 20;
        rope.links = links;
        sim::add_rope(m, rope);
    } else {
        sim::ClothDef cloth;
        cloth.nx = cloth.ny = 16;
        cloth.pins = sim::ClothDef::Pins::edge;
        cloth.links = links;
        sim::add_cloth(m, cloth);
    }
    m.forces.push_back(sim::UniformGravity{Vec3(0, -kG, 0)});
    m.constraints.iterations = substeps ? 1 : n;
    sim::World world(m);
    const sim::StepSettings step{Integrator::symplectic_euler, 1.0 / 60.0, substeps ? n : 1};
    const auto start = Clock::now();
    for (int f = 0; f < 120; ++f) world.step(step);
    SmallSteps r{body, substeps ? "substeps" : "iterations", n};
    r.ms_per_frame = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / 120.0;
    for (const sim::DistanceConstraint& c : m.constraints.distance) {
        const double length = (world.state().x.get(c.i) - world.state().x.get(c.j)).norm();
        r.strain = std::max(r.strain, std::abs(length / c.rest - 1.0));
    }
    return r;
}

// --- every shipped scene against the frame budget -----------------------------------------

// The lecture's budget: physics takes 5% to 30% of a 33 ms frame (30 FPS).
constexpr double kFrameMs = 1000.0 / 30.0;
constexpr double kPhysicsLow = 0.05 * kFrameMs, kPhysicsHigh = 0.30 * kFrameMs;  // ms

struct SceneCost {
    std::string scene;
    int frames = 0;                                       // frame steps run
    double steps_per_frame = 1.0;                         // frame steps per 1/30 s of simulated time
    std::vector<std::pair<std::string, double>> systems;  // ms per 30 FPS frame, per system built
    double physics = 0.0;                                 // ms per 30 FPS frame
    double render = 0.0;                                  // ms per rendered 1280x720 frame (4x MSAA), median
    double encode = kNaN;                                 // ms per frame of H.264 encoding (not measured by --quick)
    bool exploded = false;
};

constexpr int kVideoWidth = 1280, kVideoHeight = 720;  // px, what `plausible video` makes by default
constexpr int kClipFrames = 30;

// Wall time of ffmpeg encoding `frames` of the clip (cycled) to H.264, yuv420p, as a video would be.
double encode_seconds(const std::vector<render::Image>& clip, int frames, const fs::path& log) {
    const std::string pix_fmt = clip.front().channels == 4 ? "rgba" : "rgb24";
    const std::string command = "ffmpeg -nostdin -loglevel error -f rawvideo -pix_fmt " + pix_fmt + " -s " +
                                std::to_string(kVideoWidth) + "x" + std::to_string(kVideoHeight) +
                                " -r 30 -i - -c:v libx264 -preset medium -pix_fmt yuv420p -f null - 2> '" +
                                log.string() + "'";
    const auto start = Clock::now();
    FILE* pipe = popen(command.c_str(), "w");
    if (pipe == nullptr) throw sim::InputError("report: cannot start ffmpeg (Debian: apt-get install ffmpeg)");
    bool written = true;
    for (int f = 0; f < frames && written; ++f) {
        const render::Image& image = clip[static_cast<std::size_t>(f) % clip.size()];
        written = std::fwrite(image.pixels.data(), 1, image.pixels.size(), pipe) == image.pixels.size();
    }
    const int status = pclose(pipe);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::ifstream said(log);
    std::stringstream text;
    text << said.rdbuf();
    said.close();
    fs::remove(log);
    if (const int signal = child_interrupt(status); signal != 0) throw_interrupted("report", "a test clip", signal);
    check_interrupt("report", "a test clip");  // Ctrl+C reaches ffmpeg too, which stops reading
    if (!written || status != 0) {
        throw sim::InputError("report: ffmpeg failed encoding a test clip (exit status " + std::to_string(status) +
                              "): " + text.str());
    }
    return seconds;
}

// ms per frame of encoding, ffmpeg's start-up taken out: (T(n) - T(1)) / (n - 1).
double encode_ms_per_frame(const std::vector<render::Image>& clip, const fs::path& log) {
    const int n = 3 * kClipFrames;
    return 1e3 * (encode_seconds(clip, n, log) - encode_seconds(clip, 1, log)) / (n - 1);
}

// `scratch`: a folder for ffmpeg's messages.
SceneCost scene_cost(const std::string& name, render::Renderer& renderer, bool quick, const fs::path& scratch) {
    const SceneDef scene = load_scene(resolve_scene(name));
    SceneCost c{name};
    SceneRun run(scene);
    const int frames = quick ? std::min(scene.frames, 60) : scene.frames;
    const auto start = Clock::now();
    while (run.frame() < frames && run.advance()) {
    }
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    c.frames = std::max(run.frame(), 1);
    c.exploded = run.verdict().exploded();
    c.steps_per_frame = (1.0 / 30.0) / scene.step.dt;
    const double to_ms = 1e3 * c.steps_per_frame / c.frames;  // s over the run -> ms per 30 FPS frame
    const auto& t = run.world().times();                      // sampled frames (World::SystemTimes)
    for (const std::string& system : scene.systems()) {
        const double v = system == "particles"     ? t.particles
                         : system == "constraints" ? t.constraints
                         : system == "collisions"  ? t.collisions
                         : system == "plasticity"  ? t.plasticity
                         : system == "rigid"       ? t.rigid
                         : system == "watchdog"    ? t.watchdog
                                                   : -1.0;
        if (v >= 0.0) c.systems.emplace_back(system, t.ms_per_step(v) * c.steps_per_frame);
    }
    c.physics = wall * to_ms;  // everything advance() does, the systems and the glue between them
    // Rendering: the last frame a few times (--quick), or the scene's first 30
    // frames as a video would show them, each timed; the median.
    std::vector<double> renders;
    std::vector<render::Image> clip;
    auto render_now = [&](const SceneRun& at) {
        const auto r0 = Clock::now();
        render::Image image = renderer.render(at.draw_list(kVideoWidth, kVideoHeight),
                                              {.width = kVideoWidth, .height = kVideoHeight, .msaa_samples = 4});
        renders.push_back(1e3 * std::chrono::duration<double>(Clock::now() - r0).count());
        if (image.width != kVideoWidth) throw sim::InputError("report: render of " + name + " failed");
        return image;
    };
    if (quick) {
        for (int k = 0; k < 3; ++k) render_now(run);
    } else {
        SceneRun film(scene);
        for (int f = 0; f < kClipFrames; ++f) {
            clip.push_back(render_now(film));
            if (!film.advance()) break;
        }
    }
    std::sort(renders.begin(), renders.end());
    c.render = renders[renders.size() / 2];
    if (!clip.empty()) c.encode = encode_ms_per_frame(clip, scratch / "ffmpeg.log");
    return c;
}

// --- output helpers -------------------------------------------------------------------------

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    if (!f) throw sim::InputError("report: cannot write " + path.string());
}

// Runs gnuplot on a script in `dir`; its errors become an InputError.
void gnuplot(const fs::path& dir, const std::string& name, const std::string& script) {
    const fs::path gp = dir / (name + ".gp"), err = dir / (name + ".gnuplot-errors");
    write_file(gp, "cd '" + dir.string() + "'\n" + script);
    const std::string command = "gnuplot '" + gp.string() + "' 2> '" + err.string() + "'";
    const int status = std::system(command.c_str());
    std::ifstream e(err);
    std::stringstream text;
    text << e.rdbuf();
    fs::remove(err);
    fs::remove(gp);
    // system() ignores Ctrl+C here while gnuplot runs: a gnuplot ended by it says so.
    if (const int signal = child_interrupt(status); signal != 0) throw_interrupted("report", name + ".png", signal);
    if (status != 0) throw sim::InputError("report: gnuplot failed on " + name + ".png: " + text.str());
}

const char* kTerminal = "set terminal pngcairo size 960,680 enhanced font 'DejaVu Sans,12' linewidth 1.5\n";

// One colour per integrator, the same in every plot.
// A horizontal reference line across a bar chart of `bars` bars, at y.
std::string hline(double y, std::size_t bars, const std::string& look) {
    return "set arrow from -0.5," + fmt("%.6g", y) + " to " + std::to_string(bars) + "-0.5," + fmt("%.6g", y) +
           " nohead " + look + "\n";
}

std::string style(std::size_t k) {
    static const char* colors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#ff7f0e", "#17becf"};
    return "lc rgb '" + std::string(colors[k % 7]) + "' pt " + std::to_string(5 + static_cast<int>(k % 7) * 2);
}

}  // namespace

fs::path write_report(const ReportOptions& options) {
    if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
        throw sim::InputError(
            "report: gnuplot is not installed (Debian: apt-get install gnuplot-nox; `make test` does it)");
    }
    const fs::path out = options.out;
    if (fs::exists(out) && !fs::is_empty(out) && !fs::exists(out / "report.md")) {
        throw sim::InputError("report: --out " + out.string() +
                              " exists and holds no report: choose another directory");
    }
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    std::error_code ec;
    fs::create_directories(parent, ec);
    const fs::path tmp = parent / (".report-" + std::to_string(getpid()));
    const InterruptScope interrupts;  // Ctrl+C: stop after the step under way, remove the folder
    fs::remove_all(tmp, ec);
    if (!fs::create_directories(tmp, ec) || ec) throw sim::InputError("report: cannot write --out " + out.string());
    try {
        const int dt_count = options.quick ? 6 : 8;
        const int repetitions = options.quick ? 1 : 5;
        const Timing timing{repetitions, options.quick ? 0.005 : 0.02};
        const std::vector<Problem> list = problems();
        const auto& methods = sim::kIntegrators;
        // The steps the progress bar counts, one per progress.step() below.
        const auto peer_problems =
            std::count_if(list.begin(), list.end(), [](const Problem& p) { return peer_knows(p.name); });
        const std::size_t hard_case_count = hard_cases().size();
        Progress progress("report", options.progress,
                          static_cast<int>(list.size() * methods.size()               // work-precision sweeps
                                           + static_cast<std::size_t>(peer_problems)  // peers
                                           + list.size()                              // frame substeps
                                           + 2 * methods.size()                       // energy drift
                                           + methods.size()                           // stiff spring limits
                                           + hard_case_count + 1 + 1   // stability map, ragdoll, small steps
                                           + catalog().size()          // scene costs
                                           + growth_system_count()));  // how cost grows

        // 1. Work-precision.
        std::vector<Sample> samples;
        nlohmann::json orders = nlohmann::json::array();
        std::ostringstream orders_csv, wp_csv;
        orders_csv << "integrator,problem,fitted,expected,points\n";
        wp_csv << "problem,integrator,dt,steps,error,error_unit,energy_error,force_evaluations_per_simulated_second,"
                  "seconds_per_simulated_second,exploded\n";
        std::map<std::string, std::map<std::string, Fit>> fits;
        for (const Problem& p : list) {
            for (const IntegratorInfo& info : methods) {
                std::vector<Sample> run;
                double dt = coarsest_dt(p, info);
                for (int k = 0; k < dt_count; ++k, dt /= 2.0) run.push_back(measure(p, info, dt, timing));
                const Fit f = fit_order(run);
                fits[p.name][std::string(info.name)] = f;
                const int expected = expected_order(p, info);
                nlohmann::json o{{"integrator", info.name}, {"problem", p.name}, {"points", f.points}};
                o["fitted"] = std::isfinite(f.slope) ? nlohmann::json(f.slope) : nlohmann::json(nullptr);
                o["expected"] = expected > 0 ? nlohmann::json(expected) : nlohmann::json(nullptr);
                orders.push_back(o);
                orders_csv << info.name << ',' << p.name << ',' << (std::isfinite(f.slope) ? fmt("%.3f", f.slope) : "")
                           << ',' << (expected > 0 ? std::to_string(expected) : "") << ',' << f.points << '\n';
                samples.insert(samples.end(), run.begin(), run.end());
                progress.step(p.name + " " + std::string(info.name));
            }
        }

        // Peers: odeint's steppers on the same problems and dt sweeps, our cost at their error as a ratio;
        // then the same pairs on a batch of 1000 copies of each problem.
        struct PeerRow {
            std::string peer, problem, ours;
            Fit fit;
            double ratio = kNaN;  // our seconds / theirs at equal error, one particle
            std::optional<BatchResult> batch;
            double steps_ratio = kNaN;  // our steps / theirs at equal error (the single copy's sweeps)
            double ratio_batch = kNaN;  // our seconds / theirs at equal error, per copy of the batch
            std::string batch_basis;    // what "equal error" rests on (see batch_ratio)
        };
        const BatchTiming batch_timing{1000, options.quick ? 0.02 : 0.1, options.quick ? 3 : 5};
        std::vector<PeerRow> peer_rows;
        std::vector<Sample> peer_samples;
        for (const Problem& p : list) {
            if (!peer_knows(p.name)) continue;
            for (const PeerInfo& peer : peers()) {
                if (p.drag && !peer.velocity_forces) continue;
                std::vector<Sample> run;
                double dt = peer.order >= 4 ? p.dt4 : p.dt2;
                for (int k = 0; k < dt_count; ++k, dt /= 2.0) run.push_back(measure_peer(p, peer, dt, timing));
                std::vector<Sample> ours;
                for (const Sample& s : samples)
                    if (s.problem == p.name && s.integrator == peer.ours) ours.push_back(s);
                PeerRow row{peer.name, p.name, peer.ours, fit_order(run), cost_ratio(ours, run)};
                if (peer.batch) {
                    const sim::ParticleModel model = p.model();
                    const auto method = sim::integrator_from_name(peer.ours).value();
                    row.batch = measure_batch(p.name, method, peer.name, model.particles[p.particle].position,
                                              model.particles[p.particle].velocity, p.end,
                                              peer.order >= 4 ? p.dt4 : p.dt2, batch_timing);
                    const BatchRatio b = batch_ratio(*row.batch, ours, run);
                    row.steps_ratio = b.steps_ratio;
                    row.ratio_batch = b.ratio;
                    row.batch_basis = b.basis;
                }
                peer_rows.push_back(row);
                peer_samples.insert(peer_samples.end(), run.begin(), run.end());
            }
            progress.step("peers " + p.name);
        }

        // A game's frame: dt = 1/60 s split into 1 to 32 substeps, every method, every problem.
        const std::vector<int> substeps = {1, 2, 4, 8, 16, 32};
        std::vector<Sample> frame_samples;
        for (const Problem& p : list) {
            for (const IntegratorInfo& info : methods) {
                for (const int n : substeps) frame_samples.push_back(measure(p, info, 1.0 / 60.0 / n, timing));
            }
            progress.step("frame budget " + p.name);
        }
        samples.insert(samples.end(), frame_samples.begin(), frame_samples.end());

        // The Pareto front per problem: by measured time, each point beats every cheaper one.
        nlohmann::json pareto = nlohmann::json::object();
        std::map<std::string, std::vector<Sample>> fronts;
        for (const Problem& p : list) {
            std::vector<Sample> mine;
            for (const Sample& s : samples)
                if (s.problem == p.name && std::isfinite(s.error) && s.error > 0) mine.push_back(s);
            std::sort(mine.begin(), mine.end(), [](const Sample& a, const Sample& b) { return a.seconds < b.seconds; });
            double best = std::numeric_limits<double>::infinity();
            nlohmann::json front = nlohmann::json::array();
            for (const Sample& s : mine) {
                if (s.error >= best) continue;
                best = s.error;
                fronts[p.name].push_back(s);
                front.push_back({{"integrator", s.integrator},
                                 {"dt", s.dt},
                                 {"error", s.error},
                                 {"seconds_per_simulated_second", s.seconds},
                                 {"force_evaluations_per_simulated_second", s.evaluations}});
            }
            pareto[p.name] = front;
        }

        // 2. Energy drift over long runs: the oscillator for 100 periods, the e = 0.5 orbit for 20.
        std::vector<Drift> drifts;
        for (const IntegratorInfo& info : methods) {
            drifts.push_back(drift("oscillator", sim::problems::oscillator_model(kOscillator, kOscX0, kOscV0), info,
                                   0.1, options.quick ? 200.0 * std::numbers::pi : 400.0 * std::numbers::pi));
            progress.step("drift oscillator " + std::string(info.name));
            drifts.push_back(drift("kepler_e0.5", sim::problems::kepler_model(0.5), info, 0.005,
                                   (options.quick ? 10.0 : 20.0) * 2.0 * std::numbers::pi));
            progress.step("drift kepler " + std::string(info.name));
        }

        // 3. Stability on the stiff spring.
        std::vector<Stability> limits;
        for (const IntegratorInfo& info : methods) {
            limits.push_back(stability(info, options.quick ? 14 : 30));
            progress.step("stability " + std::string(info.name));
        }

        // 3b. The stability map: each hard case per method, and the ragdoll through ODE.
        std::vector<MapCell> cells;
        const std::vector<HardCase> cases = hard_cases();
        const int bisections = options.quick ? 8 : 16;
        for (const HardCase& c : cases) {
            for (const IntegratorInfo& info : methods) {
                MapCell cell{c.name, std::string(info.name)};
                cell.largest_dt = largest_stable(kDtLo, kDtHi, bisections,
                                                 [&](double dt) { return !explodes(c, info, dt, c.stiffness); });
                cell.largest_stiffness =
                    largest_stable(kKLo, kKHi, bisections, [&](double k) { return !explodes(c, info, 1.0 / 60.0, k); });
                cells.push_back(cell);
            }
            progress.step("stability map " + c.name);
        }
        const double ragdoll_dt = ragdoll_largest_dt(bisections);
        progress.step("stability map ragdoll");
        std::vector<SmallSteps> steps_claim;
        for (const std::string body : {"rope", "cloth"}) {
            for (const int n : {1, 2, 4, 8, 16}) {
                steps_claim.push_back(small_steps(body, true, n));
                steps_claim.push_back(small_steps(body, false, n));
            }
        }
        progress.step("XPBD small steps");

        // 4. Every shipped scene against the frame budget.
        std::vector<SceneCost> costs;
        {
            const auto context = render::create_context({});
            render::Renderer renderer(*context);
            for (const std::string& name : catalog()) {
                costs.push_back(scene_cost(name, renderer, options.quick, tmp));
                progress.step("scene " + name);
            }
        }

        // 5. How cost grows with size.
        const std::vector<GrowthSeries> growth =
            measure_growth(growth_timing(options.quick), [&](const std::string& s) { progress.step("growth " + s); });

        // --- files ---
        for (const Sample& s : samples) {  // the sweeps, then the frame substeps
            const Problem& p =
                *std::find_if(list.begin(), list.end(), [&](const Problem& q) { return q.name == s.problem; });
            wp_csv << s.problem << ',' << s.integrator << ',' << fmt("%.9g", s.dt) << ',' << s.steps << ','
                   << fmt("%.6e", s.error) << ',' << p.error_unit << ',' << fmt("%.6e", s.energy_error) << ','
                   << fmt("%.6g", s.evaluations) << ',' << fmt("%.6e", s.seconds) << ',' << s.exploded << '\n';
        }
        write_file(tmp / "orders.csv", orders_csv.str());
        write_file(tmp / "work_precision.csv", wp_csv.str());
        std::ostringstream st_csv;
        st_csv << "integrator,largest_stable_dt,always_stable,stable_at_1_60,exploded_frame,quantity\n";
        nlohmann::json stab = nlohmann::json::array();
        for (const Stability& s : limits) {
            st_csv << s.integrator << ',' << fmt("%.6g", s.largest_dt) << ',' << s.always_stable << ','
                   << s.stable_at_frame << ',' << s.exploded_frame << ',' << s.quantity << '\n';
            stab.push_back({{"integrator", s.integrator},
                            {"largest_stable_dt", s.largest_dt},
                            {"always_stable", s.always_stable},
                            {"stable_at_1_60", s.stable_at_frame},
                            {"exploded_frame", s.exploded_frame},
                            {"quantity", s.quantity}});
        }
        write_file(tmp / "stability.csv", st_csv.str());
        nlohmann::json drift_json = nlohmann::json::array();
        for (const Drift& d : drifts) {
            drift_json.push_back({{"integrator", d.integrator},
                                  {"problem", d.problem},
                                  {"first_half", d.first_half},
                                  {"second_half", d.second_half},
                                  {"exploded", d.exploded},
                                  {"bounded", d.bounded()}});
        }

        // Plots. Work-precision and error against dt, one PNG per problem.
        for (const Problem& p : list) {
            std::ostringstream data, wp, ed;
            // Our integrators, then odeint's (dashed, grey), one data block each.
            std::vector<std::pair<std::string, std::string>> series;  // name, gnuplot style
            for (std::size_t m = 0; m < methods.size(); ++m) series.emplace_back(methods[m].name, style(m));
            static const char* greys[] = {"#000000", "#555555", "#999999"};
            for (std::size_t m = 0; m < peers().size(); ++m) {
                series.emplace_back(peers()[m].name, "dt 2 lc rgb '" + std::string(greys[m % 3]) + "' pt " +
                                                         std::to_string(4 + 2 * static_cast<int>(m)));
            }
            std::size_t k = 0;
            for (const auto& [name, look] : series) {
                std::vector<const Sample*> line;  // the sweep and the frame substeps, by dt
                for (const std::vector<Sample>* from : {&samples, &peer_samples}) {
                    for (const Sample& s : *from) {
                        if (s.problem == p.name && s.integrator == name && std::isfinite(s.error) && s.error > 0) {
                            line.push_back(&s);
                        }
                    }
                }
                if (line.empty()) continue;
                data << "# " << name << "\n";
                std::sort(line.begin(), line.end(), [](const Sample* a, const Sample* b) { return a->dt > b->dt; });
                for (const Sample* s : line) {
                    data << fmt("%.9g", s->dt) << ' ' << fmt("%.6e", s->error) << ' ' << fmt("%.6e", s->seconds) << ' '
                         << fmt("%.6e", s->evaluations) << '\n';
                }
                data << "\n\n";
                const std::string sep = k == 0 ? "plot " : ", \\\n     ";
                wp << sep << "'" << p.name << ".dat' index " << k << " using 3:2 with linespoints " << look
                   << " title '" << name << "' noenhanced";
                ed << sep << "'" << p.name << ".dat' index " << k << " using 1:2 with linespoints " << look
                   << " title '" << name << "' noenhanced";
                ++k;
            }
            write_file(tmp / (p.name + ".dat"), data.str());
            const std::string axes =
                "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
                "set key outside right top\n";
            gnuplot(tmp, "work_precision_" + p.name,
                    std::string(kTerminal) + "set output 'work_precision_" + p.name + ".png'\n" + axes +
                        "set title \"Work-precision: " + p.title +
                        "\" noenhanced\n"
                        "set xlabel 'cost: wall time per simulated second (s)'\n"
                        "set ylabel 'global error at the end (" +
                        p.error_unit + ")'\n" + wp.str() + "\n");
            // Reference slopes through the middle of the dt range.
            const double mid_dt = p.dt2 / 8.0;  // s
            gnuplot(tmp, "error_vs_dt_" + p.name,
                    std::string(kTerminal) + "set output 'error_vs_dt_" + p.name + ".png'\n" + axes +
                        "set title \"Error against dt: " + p.title +
                        "\" noenhanced\n"
                        "set xlabel 'dt (s)'\nset ylabel 'global error at the end (" +
                        p.error_unit + ")'\n" + ed.str() + ", \\\n     1e-3*(x/" + fmt("%.6g", mid_dt) +
                        ") dt 2 lc rgb '#999999' title 'slope 1', \\\n     1e-5*(x/" + fmt("%.6g", mid_dt) +
                        ")**2 dt 3 lc rgb '#999999' title 'slope 2', \\\n     1e-9*(x/" + fmt("%.6g", mid_dt) +
                        ")**4 dt 4 lc rgb '#999999' title 'slope 4'\n");
        }
        // Energy over time on the oscillator (the envelope of |E - E0| / E0).
        {
            std::ostringstream data, plot;
            std::size_t k = 0;
            for (const Drift& d : drifts) {
                if (d.problem != "oscillator") continue;
                data << "# " << d.integrator << "\n";
                for (const auto& [t, e] : d.envelope) data << fmt("%.6g", t) << ' ' << fmt("%.6e", e) << '\n';
                data << "\n\n";
                plot << (k == 0 ? "plot " : ", \\\n     ") << "'energy.dat' index " << k << " using 1:2 with lines "
                     << style(k) << " lw 2 title '" << d.integrator << "' noenhanced";
                ++k;
            }
            write_file(tmp / "energy.dat", data.str());
            gnuplot(tmp, "energy",
                    std::string(kTerminal) +
                        "set output 'energy.png'\nset logscale y\nset format y '10^{%L}'\nset grid\n"
                        "set key outside right top\nset yrange [1e-8:1e3]\n"
                        "set title 'Energy error over time: harmonic oscillator, dt = 0.1 s (ω dt = 0.1)'\n"
                        "set xlabel 'simulated time (s)'\nset ylabel 'largest |E - E_0| / E_0 so far'\n" +
                        plot.str() + "\n");
        }
        // Stability limits on the stiff spring.
        {
            std::ostringstream data;
            for (std::size_t k = 0; k < limits.size(); ++k) {
                data << k << " \"" << limits[k].integrator << "\" " << fmt("%.6e", std::max(limits[k].largest_dt, 1e-7))
                     << '\n';
            }
            write_file(tmp / "stability.dat", data.str());
            gnuplot(tmp, "stability",
                    std::string(kTerminal) +
                        "set output 'stability.png'\nset logscale y\nset format y '10^{%L}'\nset grid y\n"
                        "set style fill solid 0.8\nset boxwidth 0.6\nset yrange [1e-7:1]\nset xtics rotate by -30 "
                        "noenhanced\n"
                        "set title 'Largest stable dt on a stiff spring (k = 10^6 N/m, m = 1 kg, ω = 1000 rad/s)'\n"
                        "set ylabel 'largest dt whose speed stays under 100 ω A for 2 s (s)'\n" +
                        hline(1.0 / 60.0, limits.size(), "dt 2 lc rgb '#d62728'") +
                        "set label '1/60 s' at -0.4,0.025 tc rgb '#d62728'\n" +
                        hline(0.002, limits.size(), "dt 3 lc rgb '#555555'") +
                        "set label '2/ω' at -0.4,0.0028 tc rgb '#555555'\n"
                        "plot 'stability.dat' using 1:3:xtic(2) with boxes lc rgb '#1f77b4' notitle\n");
        }

        // report.json
        nlohmann::json j;
        j["quick"] = options.quick;
        j["dt_values_per_method"] = dt_count;
        j["repetitions"] = repetitions;
        nlohmann::json plist = nlohmann::json::array();
        for (const Problem& p : list)
            plist.push_back({{"name", p.name}, {"title", p.title}, {"error_unit", p.error_unit}, {"end", p.end}});
        j["problems"] = plist;
        j["orders"] = orders;
        j["pareto"] = pareto;
        j["drift"] = drift_json;
        j["stability"] = {{"problem", "stiff spring, k = 1e6 N/m, m = 1 kg"}, {"limits", stab}};
        nlohmann::json scene_json = nlohmann::json::array();
        std::ostringstream cost_csv;
        cost_csv << "scene,frames,physics_ms_per_frame,render_ms_per_frame,encode_ms_per_frame,total_ms_per_frame,"
                    "physics_share,verdict\n";
        auto verdict = [](const SceneCost& c) {
            return c.exploded                 ? "exploded"
                   : c.physics > kPhysicsHigh ? "over"
                   : c.physics > kPhysicsLow  ? "within"
                                              : "under";
        };
        for (const SceneCost& c : costs) {
            nlohmann::json systems = nlohmann::json::object();
            for (const auto& [system, ms] : c.systems) systems[system] = ms;
            scene_json.push_back(
                {{"scene", c.scene},
                 {"frames", c.frames},
                 {"physics_ms_per_frame", c.physics},
                 {"systems_ms_per_frame", systems},
                 {"render_ms_per_frame", c.render},
                 {"encode_ms_per_frame", std::isfinite(c.encode) ? nlohmann::json(c.encode) : nlohmann::json(nullptr)},
                 {"verdict", verdict(c)}});
            const double encode = std::isfinite(c.encode) ? c.encode : 0.0;
            cost_csv << c.scene << ',' << c.frames << ',' << fmt("%.4f", c.physics) << ',' << fmt("%.3f", c.render)
                     << ',' << (std::isfinite(c.encode) ? fmt("%.3f", c.encode) : "") << ','
                     << fmt("%.3f", c.physics + c.render + encode) << ',' << fmt("%.4f", c.physics / kFrameMs) << ','
                     << verdict(c) << '\n';
        }
        j["scenes"] = {{"frame_ms", kFrameMs},
                       {"physics_low_ms", kPhysicsLow},
                       {"physics_high_ms", kPhysicsHigh},
                       {"costs", scene_json}};
        write_file(tmp / "scene_costs.csv", cost_csv.str());
        {
            std::ostringstream data;
            for (std::size_t k = 0; k < costs.size(); ++k) {
                const double encode = std::isfinite(costs[k].encode) ? costs[k].encode : 0.0;
                data << k << " \"" << costs[k].scene << "\" " << fmt("%.5f", costs[k].physics) << ' '
                     << fmt("%.5f", costs[k].physics + costs[k].render) << ' '
                     << fmt("%.5f", costs[k].physics + costs[k].render + encode) << '\n';
            }
            write_file(tmp / "scene_costs.dat", data.str());
            gnuplot(
                tmp, "scene_costs",
                std::string("set terminal pngcairo size 1300,680 enhanced font 'DejaVu Sans,12' linewidth 1.5\n") +
                    "set output 'scene_costs.png'\nset grid y\nset style fill solid 0.85\nset boxwidth 0.7\n"
                    "set logscale y\nset yrange [0.0001:300]\nset xtics rotate by -45 noenhanced\n"
                    "set key outside right top\n"
                    "set title 'Every scene per 30 FPS frame (33 ms): physics, a 1280x720 render, H.264 encoding "
                    "(stacked)'\n"
                    "set ylabel 'ms per frame'\n" +
                    hline(kPhysicsLow, costs.size(), "dt 2 lc rgb '#2ca02c'") +
                    hline(kPhysicsHigh, costs.size(), "dt 2 lc rgb '#d62728'") +
                    hline(kFrameMs, costs.size(), "lc rgb '#000000'") +
                    "plot 'scene_costs.dat' using 1:5:xtic(2) with boxes lc rgb '#f2c48d' title '+ encode (H.264)', "
                    "\\\n"
                    "     '' using 1:4 with boxes lc rgb '#bbbbbb' title 'physics + render', \\\n"
                    "     '' using 1:3 with boxes lc rgb '#1f77b4' title 'physics', \\\n"
                    "     NaN with lines dt 2 lc rgb '#2ca02c' title 'physics 5% (1.67 ms)', \\\n"
                    "     NaN with lines dt 2 lc rgb '#d62728' title 'physics 30% (10 ms)', \\\n"
                    "     NaN with lines lc rgb '#000000' title 'the frame (33 ms)'\n");
        }
        nlohmann::json peer_json = nlohmann::json::array();
        std::ostringstream peer_csv;
        peer_csv << "peer,problem,compared_with,fitted,ratio_ours_over_theirs,ratio_batch,batch_copies,"
                    "ours_ns_per_copy_step,theirs_ns_per_copy_step\n";
        auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
        for (const PeerRow& r : peer_rows) {
            nlohmann::json row{{"peer", r.peer},
                               {"problem", r.problem},
                               {"compared_with", r.ours},
                               {"fitted", number(r.fit.slope)},
                               {"cost_ratio", number(r.ratio)},
                               {"ratio_batch", number(r.ratio_batch)}};
            if (r.batch) {
                const BatchResult& b = *r.batch;
                row["ratio_batch_basis"] = r.batch_basis;
                row["batch"] = {{"copies", b.copies},
                                {"dt", b.dt},
                                {"steps", b.steps},
                                {"ours_seconds_per_copy_step", b.ours_seconds},
                                {"theirs_seconds_per_copy_step", b.theirs_seconds},
                                {"ratio_at_equal_dt", b.ours_seconds / b.theirs_seconds},
                                {"steps_ratio_at_equal_error", number(r.steps_ratio)},
                                {"ours_error", number(b.ours_error)},
                                {"theirs_error", number(b.theirs_error)}};
            }
            peer_json.push_back(row);
            peer_csv << r.peer << ',' << r.problem << ',' << r.ours << ','
                     << (std::isfinite(r.fit.slope) ? fmt("%.3f", r.fit.slope) : "") << ','
                     << (std::isfinite(r.ratio) ? fmt("%.3f", r.ratio) : "") << ','
                     << (std::isfinite(r.ratio_batch) ? fmt("%.3f", r.ratio_batch) : "") << ','
                     << (r.batch ? std::to_string(r.batch->copies) : "") << ','
                     << (r.batch ? fmt("%.3f", 1e9 * r.batch->ours_seconds) : "") << ','
                     << (r.batch ? fmt("%.3f", 1e9 * r.batch->theirs_seconds) : "") << '\n';
        }
        j["peers"] = peer_json;
        write_file(tmp / "peers.csv", peer_csv.str());
        const GrowthFiles growth_out = growth_files(growth);  // how cost grows: CSV, JSON, plot, Markdown
        j["growth"] = growth_out.json;
        write_file(tmp / "growth.csv", growth_out.csv);
        write_file(tmp / "growth.dat", growth_out.plot_data);
        gnuplot(tmp, "growth", std::string(kTerminal) + growth_out.plot_script);
        {
            nlohmann::json map = nlohmann::json::array();
            std::ostringstream csv;
            csv << "case,integrator,largest_stable_dt,largest_stable_stiffness_at_1_60\n";
            for (const MapCell& c : cells) {
                map.push_back({{"case", c.hard_case},
                               {"integrator", c.integrator},
                               {"largest_stable_dt", c.largest_dt},
                               {"largest_stable_stiffness_at_1_60", c.largest_stiffness}});
                csv << c.hard_case << ',' << c.integrator << ',' << fmt("%.6g", c.largest_dt) << ','
                    << fmt("%.6g", c.largest_stiffness) << '\n';
            }
            csv << "ragdoll,ode_quickstep," << fmt("%.6g", ragdoll_dt) << ",\n";
            j["stability_map"] = {{"dt_search", {kDtLo, kDtHi}},
                                  {"stiffness_search", {kKLo, kKHi}},
                                  {"cells", map},
                                  {"ragdoll_ode_largest_dt", ragdoll_dt}};
            write_file(tmp / "stability_map.csv", csv.str());
            nlohmann::json claim = nlohmann::json::array();
            for (const SmallSteps& r : steps_claim) {
                claim.push_back({{"body", r.body},
                                 {"way", r.way},
                                 {"n", r.n},
                                 {"strain", r.strain},
                                 {"ms_per_frame", r.ms_per_frame}});
            }
            j["small_steps"] = claim;

            // The heat map: rows the cases (and the ragdoll), columns the methods (and ODE).
            auto label = [](double dt) {
                if (dt <= 0.0) return std::string("<10 µs");
                if (dt >= kDtHi) return std::string("≥250 ms");
                return dt >= 1e-3 ? fmt("%.3g ms", 1e3 * dt) : fmt("%.3g µs", 1e6 * dt);
            };
            std::ostringstream data, xt, yt;
            for (std::size_t y = 0; y < cases.size(); ++y) {
                for (std::size_t x = 0; x < methods.size(); ++x) {
                    const MapCell& c = cells[y * methods.size() + x];
                    data << x << ' ' << y << ' ' << fmt("%.4f", std::log10(std::max(c.largest_dt, kDtLo / 2))) << " \""
                         << label(c.largest_dt) << "\"\n";
                }
                data << methods.size() << ' ' << y << " NaN \"\"\n\n";
            }
            for (std::size_t x = 0; x < methods.size(); ++x) data << x << ' ' << cases.size() << " NaN \"\"\n";
            data << methods.size() << ' ' << cases.size() << ' ' << fmt("%.4f", std::log10(ragdoll_dt)) << " \""
                 << label(ragdoll_dt) << "\"\n";
            write_file(tmp / "stability_map.dat", data.str());
            for (std::size_t x = 0; x < methods.size(); ++x)
                xt << (x ? ", " : "") << "'" << methods[x].name << "' " << x;
            xt << ", 'ODE quickstep' " << methods.size();
            for (std::size_t y = 0; y < cases.size(); ++y) yt << (y ? ", " : "") << "'" << cases[y].name << "' " << y;
            yt << ", 'ragdoll (ODE)' " << cases.size();
            gnuplot(
                tmp, "stability_map",
                std::string(kTerminal) +
                    "set output 'stability_map.png'\n"
                    "set title 'Largest stable dt per method (white: 1/60 s; blue: a game frame is stable; the "
                    "watchdog decides)'\n"
                    "set xtics (" +
                    xt.str() + ") rotate by -30 noenhanced\nset ytics (" + yt.str() +
                    ") noenhanced\n"
                    "set xrange [-0.5:" +
                    std::to_string(methods.size()) + ".5]\nset yrange [-0.5:" + std::to_string(cases.size()) +
                    ".5]\nset cbrange [-5:-0.6]\nset cblabel 'log_{10} dt (s)'\n"
                    "set palette defined (0 '#b2182b', 0.5 '#f4a582', 0.73 '#f7f7f7', 0.85 '#92c5de', 1 '#2166ac')\n"
                    "set view map\n"
                    "plot 'stability_map.dat' using 1:2:3 with image notitle, '' using 1:2:4 with labels font ',10' "
                    "notitle\n");
        }
        write_file(tmp / "report.json", j.dump(2) + "\n");

        // report.md
        std::ostringstream md;
        md << "# Speed against error\n\n"
           << (options.quick ? "Quick run (`report --quick`): 6 dt values per method; each timing the median of "
                               "runs adding up to 5 ms.\n\n"
                             : "Full run: 8 dt values per method; each timing the median of at least 5 runs adding "
                               "up to 20 ms.\n\n")
           << "Every integrator on problems with exact answers. Error is the distance from the closed form at the "
              "end time (the pendulum: its period's error); cost is measured wall time per simulated second on this "
              "machine, and force evaluations (machine-independent) in `work_precision.csv`.\n\n";
        md << "## Orders of convergence\n\n| problem |";
        for (const IntegratorInfo& info : methods) md << ' ' << info.name << " |";
        md << "\n|---|";
        for (std::size_t k = 0; k < methods.size(); ++k) md << "---|";
        md << '\n';
        int matched = 0, compared = 0;
        for (const Problem& p : list) {
            md << "| " << p.name << " |";
            for (const IntegratorInfo& info : methods) {
                const Fit& f = fits[p.name][std::string(info.name)];
                const int expected = expected_order(p, info);
                if (p.smooth && expected == 0) {
                    md << " exact |";
                } else if (!std::isfinite(f.slope)) {
                    md << " n/a |";
                } else {
                    md << ' ' << fmt("%.2f", f.slope);
                    if (expected > 0) {
                        md << " (" << expected << ")";
                        ++compared;
                        if (std::abs(f.slope - expected) <= 0.15) ++matched;
                    }
                    md << " |";
                }
            }
            md << '\n';
        }
        md << "\nFitted slope of log error on log dt (theory in brackets). **" << matched << " of " << compared
           << " fitted orders are within 0.15 of theory**. Leapfrog (kick-drift-kick) is first order on the damped "
              "oscillator: its second kick evaluates the drag at the half-step velocity (velocity Verlet predicts the "
              "full-step velocity and stays second order). On the pendulum the XPBD rod's projection, which loses "
              "energy "
              "in proportion to dt, makes every method first order in the period, with the same error for all.\n\n";
        md << "## Work-precision\n\n";
        for (const Problem& p : list) {
            md << "### " << p.title << "\n\n![work-precision](work_precision_" << p.name << ".png)\n\n"
               << "![error against dt](error_vs_dt_" << p.name << ".png)\n\n";
            const auto& front = fronts[p.name];
            md << "Pareto front (cheapest first; each point is more accurate than every cheaper one):\n\n"
               << "| integrator | dt (s) | error (" << p.error_unit
               << ") | time per simulated s | force evaluations per simulated s |\n|---|---|---|---|---|\n";
            for (const Sample& s : front) {
                md << "| " << s.integrator << " | " << fmt("%.3g", s.dt) << " | " << fmt("%.2e", s.error) << " | "
                   << fmt("%.2e", s.seconds) << " s | " << fmt("%.3g", s.evaluations) << " |\n";
            }
            std::map<std::string, int> wins;
            for (const Sample& s : front) ++wins[s.integrator];
            std::string winner;
            int most = 0;
            for (const auto& [name, n] : wins)
                if (n > most) most = n, winner = name;
            md << "\n"
               << winner << " holds the most points of the front (" << most << " of " << front.size() << ").\n\n";
        }
        md << "## A game's frame: 1/60 s in substeps\n\n"
           << "Error at the end time with dt = 1/60 s split into n substeps (explosions by the watchdog marked), and "
              "the force evaluations per frame that costs (a method's evaluations per step times n):\n\n";
        for (const Problem& p : list) {
            md << "**" << p.title << "** (error in " << p.error_unit << ")\n\n| integrator |";
            for (const int n : substeps) md << " n = " << n << " |";
            md << " evaluations per frame at n = 1 |\n|---|";
            for (std::size_t k = 0; k <= substeps.size(); ++k) md << "---|";
            md << '\n';
            for (const IntegratorInfo& info : methods) {
                md << "| " << info.name << " |";
                double per_frame = 0.0;
                for (const Sample& s : frame_samples) {
                    if (s.problem != p.name || s.integrator != info.name) continue;
                    md << ' ' << (s.exploded ? std::string("exploded") : fmt("%.1e", s.error)) << " |";
                    if (std::abs(s.dt - 1.0 / 60.0) < 1e-12) per_frame = s.evaluations / 60.0;
                }
                md << ' ' << fmt("%.0f", per_frame) << " |\n";
            }
            md << '\n';
        }
        md << "For an error of 1e-3 (m, or s for the pendulum) at 1/60 s frames, the fewest force evaluations a "
              "frame:\n\n";
        for (const Problem& p : list) {
            const Sample* best = nullptr;
            for (const Sample& s : frame_samples) {
                if (s.problem == p.name && !s.exploded && std::isfinite(s.error) && s.error <= 1e-3 &&
                    (best == nullptr || s.evaluations < best->evaluations ||
                     (s.evaluations == best->evaluations && s.error < best->error))) {  // ties: the more accurate
                    best = &s;
                }
            }
            md << "- " << p.name << ": "
               << (best ? best->integrator + " with " + std::to_string(std::lround(1.0 / 60.0 / best->dt)) +
                              " substep(s), " + fmt("%.0f", best->evaluations / 60.0) + " evaluations a frame"
                        : std::string("none of the measured substeps reaches it"))
               << '\n';
        }
        md << '\n';
        md << "## Which method for which budget\n\n"
           << "The cheapest measured point whose error is within the budget, per problem (error in the problem's "
              "unit):\n\n"
           << "| problem | 1e-2 | 1e-4 | 1e-6 |\n|---|---|---|---|\n";
        for (const Problem& p : list) {
            md << "| " << p.name << " |";
            for (const double budget : {1e-2, 1e-4, 1e-6}) {
                const Sample* best = nullptr;
                for (const Sample& s : fronts[p.name])
                    if (s.error <= budget && (best == nullptr || s.seconds < best->seconds)) best = &s;
                md << ' '
                   << (best ? best->integrator + " at dt " + fmt("%.2g", best->dt) : std::string("none measured"))
                   << " |";
            }
            md << '\n';
        }
        md << "\nOver every point measured (the sweeps and the frame substeps), by wall time on this machine. On "
              "these smooth problems RK4's four evaluations a step buy steps large enough to win almost every "
              "budget; the Verlet methods come next, one evaluation a step and bounded energy; the Euler methods "
              "never pay off.\n\n";
        md << "## Peers: boost::odeint\n\n"
           << "odeint's steppers on the same problems and dt sweeps (dashed in the plots). The ratio is our cost at "
              "the same error over theirs (wall time, median over their points; below 1: ours is cheaper).\n\n"
           << "| peer | compared with | problem | fitted order | our cost / theirs, one particle | batch of 1000 | "
              "ns per copy-step, ours / theirs |\n|---|---|---|---|---|---|---|\n";
        for (const PeerRow& r : peer_rows) {
            md << "| " << r.peer << " | " << r.ours << " | " << r.problem << " | "
               << (std::isfinite(r.fit.slope) ? fmt("%.2f", r.fit.slope) : std::string("exact")) << " | "
               << (std::isfinite(r.ratio) ? fmt("%.2f", r.ratio) : std::string("n/a")) << " | ";
            if (!r.batch) {
                md << "- | - |\n";
                continue;
            }
            md << (std::isfinite(r.ratio_batch) ? fmt("%.2f", r.ratio_batch) : std::string("n/a"))
               << (r.batch_basis == "equal error" || r.batch_basis.empty() ? "" : " (" + r.batch_basis + ")") << " | "
               << fmt("%.2f", 1e9 * r.batch->ours_seconds) << " / " << fmt("%.2f", 1e9 * r.batch->theirs_seconds)
               << " |\n";
        }
        {
            std::map<std::string, std::vector<double>> by, by_batch;
            std::vector<std::string> over;  // batch rows above the target
            bool springs_over = false;
            for (const PeerRow& r : peer_rows) {
                if (std::isfinite(r.ratio)) by[r.peer].push_back(r.ratio);
                if (!std::isfinite(r.ratio_batch)) continue;
                by_batch[r.peer].push_back(r.ratio_batch);
                if (r.ratio_batch > kBatchTarget && r.batch_basis != "equal dt, an upper bound") {
                    over.push_back(r.ours + " on " + r.problem + " (" + fmt("%.2f", r.ratio_batch) + "x)");
                    springs_over = springs_over || r.problem == "oscillator" || r.problem == "damped";
                }
            }
            auto median = [](std::vector<double> v) {
                std::sort(v.begin(), v.end());
                return v[v.size() / 2];
            };
            md << "\nThe fixed cost: each of our steps goes through the whole World (`World::step` checks its settings "
                  "and runs its stages in turn, the force generators are dispatched over the particle arrays, a "
                  "pinned anchor or centre being a second particle, the integrator makes its passes, the watchdog "
                  "checks the result), an overhead the same whatever the number of particles; on one particle it is "
                  "most of the step, against odeint's one inlined 3-vector, and it is mostly what the one-particle "
                  "ratio measures. The batch spreads it over 1000 independent copies of each problem (one World of "
                  "1000 particles against one odeint state of 6000 doubles; the Kepler copies each fall towards a "
                  "fixed attractor, CentralGravity, so that they do not attract each other), so what it shows is the "
                  "integrators' and the forces' own cost per particle. Its ratio is at equal error: our time per "
                  "step per copy over odeint's, times our steps over theirs for the same error, from the single "
                  "copy's sweeps (1.00 for the same method; both sides' errors on the batch are in report.json's "
                  "`batch`). odeint's velocity_verlet is first order on the damped oscillator (its force sees the "
                  "old velocity), ours second (it predicts the new one): there the batch ratio is at equal dt, an "
                  "upper bound.\n";
            for (auto& [peer, v] : by) {
                md << "- Against " << peer << ": our cost at equal error is " << fmt("%.2f", median(v))
                   << "x theirs on one particle";
                if (by_batch.count(peer) != 0) {
                    md << ", " << fmt("%.2f", median(by_batch[peer])) << "x on the batch";
                }
                md << " (median over problems).\n";
            }
            if (!over.empty()) {
                md << "\nAbove " << fmt("%.1f", kBatchTarget) << "x odeint on the batch (the target): ";
                for (std::size_t k = 0; k < over.size(); ++k) md << (k == 0 ? "" : ", ") << over[k];
                md << ". There the cost is in our force and integrator passes, not in the World's overhead (the "
                      "last column: nanoseconds per copy and step).";
                if (springs_over) {
                    md << " A spring is an index record: the spring generator's loop for rest length 0 goes one "
                          "spring at a time, reading both ends through their indices and adding the force back to "
                          "each (the shared anchor's too), where odeint computes -x over contiguous arrays.";
                }
                md << '\n';
            }
            md << '\n';
        }
        md << "## Energy over long runs\n\n![energy](energy.png)\n\n"
           << "| integrator | problem | max error, first half | max error, second half | verdict "
              "|\n|---|---|---|---|---|\n";
        for (const Drift& d : drifts) {
            md << "| " << d.integrator << " | " << d.problem << " | " << fmt("%.2e", d.first_half) << " | "
               << fmt("%.2e", d.second_half) << " | "
               << (d.exploded    ? "exploded"
                   : d.bounded() ? "bounded"
                                 : "drifts")
               << " |\n";
        }
        md << "\nSymplectic methods keep the energy error bounded (it oscillates and does not grow); forward Euler "
              "gains energy, backward Euler and RK4 lose it, steadily.\n\n";
        md << "## Stability on a stiff spring\n\n![stability](stability.png)\n\n"
           << "| integrator | largest stable dt | at 1/60 s |\n|---|---|---|\n";
        for (const Stability& s : limits) {
            md << "| " << s.integrator << " | "
               << (s.always_stable    ? ">= " + fmt("%.3g", s.largest_dt) + " s (always)"
                   : s.largest_dt > 0 ? fmt("%.3g", s.largest_dt) + " s"
                                      : std::string("none (unstable at 1 µs)"))
               << " | "
               << (s.stable_at_frame ? std::string("stable")
                                     : "**unstable**: " + s.quantity + " at frame " + std::to_string(s.exploded_frame))
               << " |\n";
        }
        md << "\nThe watchdog decides: exploded once the mass moves 100 times faster than its own swing within 2 s. "
              "The symplectic and Verlet methods are stable up to 2/ω = 2 ms, RK4 to 2.83/ω; forward Euler's "
              "amplitude grows at every dt (here: within 2 s unless dt is a few µs); backward Euler is stable at "
              "every dt. At a game's 1/60 s only backward Euler survives (or constraints instead of the spring: "
              "`rope-stiff`).\n";
        md << "\n## Stability map\n\n![stability map](stability_map.png)\n\n"
           << "The largest stable dt of each method on each hard case at its own stiffness, and the largest stable "
              "stiffness at a game's 1/60 s, by bisection (the watchdog decides: speed, bounds, NaN). The ragdoll "
              "steps "
              "with ODE's own integrator (quickstep, 40 iterations), whatever the scene's.\n\n"
           << "| case | integrator | largest stable dt | largest stable stiffness at 1/60 s |\n|---|---|---|---|\n";
        for (const MapCell& c : cells) {
            md << "| " << c.hard_case << " | " << c.integrator << " | "
               << (c.largest_dt >= kDtHi ? ">= " + fmt("%.3g", kDtHi) + " s"
                   : c.largest_dt > 0    ? fmt("%.3g", c.largest_dt) + " s"
                                         : "< " + fmt("%.0e", kDtLo) + " s")
               << " | "
               << (c.largest_stiffness >= kKHi ? ">= " + fmt("%.0e", kKHi) + " N/m"
                   : c.largest_stiffness > 0   ? fmt("%.3g", c.largest_stiffness) + " N/m"
                                               : "< " + fmt("%.0f", kKLo) + " N/m")
               << " |\n";
        }
        md << "| ragdoll | ODE quickstep | " << fmt("%.3g", ragdoll_dt) << " s | (joints, not springs) |\n\n"
           << "The explicit methods' limits follow ω h < 2 (symplectic, Verlet) and 2.8 (RK4) of the case's "
              "stiffest mode; the 1000:1 chain's light links set that mode, not the heavy ball. Backward Euler's "
              "limit is the search's end: implicit, it trades accuracy (damping) for stability.\n\n";
        md << "## XPBD: small steps or more iterations?\n\n"
           << "Inextensible links without tethers, 2 s hanging at 1/60 s frames: n substeps of one iteration "
              "against one step of n iterations. Strain is the worst link's stretch at the end.\n\n"
           << "| body | n | strain, n substeps | strain, n iterations | ms per frame, substeps | ms per frame, "
              "iterations |\n"
              "|---|---|---|---|---|---|\n";
        int substeps_win = 0, pairs = 0;
        for (std::size_t i = 0; i + 1 < steps_claim.size(); i += 2) {
            const SmallSteps &a = steps_claim[i], &b = steps_claim[i + 1];
            md << "| " << a.body << " | " << a.n << " | " << fmt("%.2e", a.strain) << " | " << fmt("%.2e", b.strain)
               << " | " << fmt("%.3f", a.ms_per_frame) << " | " << fmt("%.3f", b.ms_per_frame) << " |\n";
            if (a.n > 1) {
                ++pairs;
                if (a.strain < b.strain) ++substeps_win;
            }
        }
        md << "\nWhat we find: n substeps give the lower strain in " << substeps_win << " of " << pairs
           << " comparisons at equal n ("
           << (substeps_win * 2 > pairs ? "the claim holds here" : "the claim does not hold here")
           << "); a substep costs a whole integration and collision pass, an iteration only a constraint sweep, so "
              "compare the times too.\n";
        md << "\n## Every scene against the frame budget\n\n![scene costs](scene_costs.png)\n\n"
           << "Per 30 FPS frame (33 ms): physics is every frame step that 1/30 s of simulated time takes (a scene "
              "at 1/60 s runs two), timed around the whole step; render is one 1280x720 frame with 4x MSAA on OSMesa "
              "(median over the scene's first 30 frames); encode is ffmpeg's libx264 (preset medium, yuv420p) on "
              "those frames, its start-up taken out (`--quick` measures neither the clip nor the encoder). The "
              "lecture's budget for physics is 5% to 30% of the frame, 1.67 to 10 ms.\n\n"
           << "| scene | physics (ms) | by system (ms) | render (ms) | encode (ms) | physics share | verdict "
              "|\n|---|---|---|---|---|---|---|\n";
        int over = 0;
        for (const SceneCost& c : costs) {
            std::string by;
            for (const auto& [system, ms] : c.systems) by += (by.empty() ? "" : ", ") + system + " " + fmt("%.3g", ms);
            md << "| " << c.scene << " | " << fmt("%.3g", c.physics) << " | " << by << " | " << fmt("%.3g", c.render)
               << " | " << (std::isfinite(c.encode) ? fmt("%.3g", c.encode) : std::string("-")) << " | "
               << fmt("%.1f", 100.0 * c.physics / kFrameMs) << "% | " << verdict(c) << " |\n";
            if (c.physics > kPhysicsHigh || c.exploded) ++over;
        }
        double fastest = std::numeric_limits<double>::infinity(), slowest = 0.0;
        for (const SceneCost& c : costs) fastest = std::min(fastest, c.render), slowest = std::max(slowest, c.render);
        md << "\n"
           << (over == 0 ? std::string("No scene is over the 30% physics budget")
                         : std::to_string(over) + " scene(s) over the 30% physics budget (flagged **over**)")
           << ". Rendering 1280x720 with 4x MSAA in software (OSMesa) takes " << fmt("%.0f", fastest) << " to "
           << fmt("%.0f", slowest) << " ms a frame: there, not in the physics, is where a 33 ms frame goes.\n"
           << growth_out.markdown;
        write_file(tmp / "report.md", md.str());
        check_interrupt("report", "the plots");

        fs::remove_all(out, ec);
        fs::rename(tmp, out, ec);
        if (ec) throw sim::InputError("report: cannot write --out " + out.string() + ": " + ec.message());
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
    return out / "report.md";
}

}  // namespace scenes
