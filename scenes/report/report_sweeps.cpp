// The report's work-precision measurements: one timed run of a method on a
// problem at one dt (its error against the closed form, its energy error,
// its cost), swept over dt for every method, for odeint's steppers (and
// their batch of copies), and at a game's 1/60 s in substeps. Its own file:
// how error and cost are measured, apart from what is made of them
// (report_analysis.cpp).
#include "scenes/report/report_stages.h"

#include "sim/integrators.h"
#include "sim/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace scenes::report {
namespace {

using sim::IntegratorInfo;
using sim::analytic::PointState;
using Clock = std::chrono::steady_clock;

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

// The errors of a finished run, into `s`: against the closed form, or (the
// pendulum) the period between its first two crossings against the exact one.
void score(const Problem& p, const sim::ParticleModel& model, const sim::World& world, double e0,
           const Crossings& crossings, Sample& s) {
    const double t = world.state().t;
    s.evaluations = world.force_evaluations() / t;
    s.exploded = world.verdict().exploded() || !world.state().x.get(p.particle).allFinite();
    if (s.exploded) return;
    if (p.exact) {
        const PointState exact = p.exact(t);
        s.error = (world.state().x.get(p.particle) - exact.x).norm();
        s.energy_error = std::abs(world.energy() - energy_of(model, p.particle, exact)) / std::abs(e0);
    } else {
        s.error = crossings.times.size() >= 2 ? std::abs(crossings.times[1] - crossings.times[0] - p.period) : kNaN;
        s.energy_error = std::abs(world.energy() - e0) / std::abs(e0);
    }
}

// One side's run times, s, and whether it takes another run: until
// timing.repetitions runs and timing.min_seconds in all (at most 10000
// runs); a run of half a second or more times itself well enough.
struct Runs {
    std::vector<double> times;  // s
    double total = 0.0;         // s
    void add(double seconds) { times.push_back(seconds), total += seconds; }
    bool more(const Timing& timing) const {
        if (times.empty()) return true;
        if (times.back() >= 0.5) return false;
        const auto n = static_cast<int>(times.size());
        return n < timing.repetitions || (total < timing.min_seconds && n < 10000);
    }
};

// One timed run of a method of ours on p at dt, its World kept for score().
struct OurRun {
    std::unique_ptr<sim::World> world;
    double e0 = 0.0;  // J, at the start
    Crossings crossings;
    double seconds = 0.0;
};
OurRun run_ours(const Problem& p, const sim::ParticleModel& model, const IntegratorInfo& info, double dt, long steps) {
    OurRun run{.world = std::make_unique<sim::World>(model)};
    sim::World& world = *run.world;
    run.e0 = world.energy();
    run.crossings.previous_x = world.state().x.get(p.particle).x();
    const auto start = Clock::now();
    for (long i = 0; i < steps && !world.verdict().exploded(); ++i) {
        world.step({info.id, dt, 1});
        if (!p.exact) run.crossings.see(world.state().t, world.state().x.get(p.particle).x());
    }
    run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return run;
}

// The sample of a method of ours from its runs' times and its last run.
Sample our_sample(const Problem& p, const sim::ParticleModel& model, const IntegratorInfo& info, double dt,
                  const Runs& runs, const OurRun& last) {
    Sample s{.problem = p.name, .integrator = std::string(info.name), .dt = dt, .steps = std::lround(p.end / dt)};
    score(p, model, *last.world, last.e0, last.crossings, s);
    s.seconds = median(runs.times) / p.end;
    return s;
}

// The sample of an odeint stepper from its runs' times and its last run.
Sample peer_sample(const Problem& p, const PeerInfo& peer, double dt, const Runs& runs, const PeerRun& last) {
    Sample s{.problem = p.name, .integrator = peer.name, .dt = dt, .steps = std::lround(p.end / dt)};
    const double t = static_cast<double>(s.steps) * dt;
    s.seconds = median(runs.times) / p.end;
    s.evaluations = peer.evaluations * static_cast<double>(s.steps) / t;
    s.exploded = !last.x.allFinite();
    if (!s.exploded) s.error = (last.x - p.exact(t).x).norm();
    return s;
}

// One method on one problem at one dt, timed as `timing` says.
Sample measure(const Problem& p, const IntegratorInfo& info, double dt, Timing timing) {
    const sim::ParticleModel model = p.model();
    const long steps = std::lround(p.end / dt);
    Runs runs;
    OurRun run;
    while (runs.more(timing)) {
        run = run_ours(p, model, info, dt, steps);
        runs.add(run.seconds);
    }
    return our_sample(p, model, info, dt, runs, run);
}

// The method of ours a peer is compared with and the peer, at one dt, timed
// in turn, a block of runs of each (a quarter of timing.min_seconds, at
// least one run), each side's median: what the machine does meanwhile falls
// on both. (Timed one side after the other, the same build's RK4 read 2.6
// and 4.4 times odeint's cost on the oscillator in two reports; taken one
// run each in turn, our short runs started cold after odeint's, 500 steps
// of velocity Verlet at 41 ns a step against 25 warm.)
std::pair<Sample, Sample> measure_pair(const Problem& p, const IntegratorInfo& ours, const PeerInfo& peer, double dt,
                                       Timing timing) {
    const sim::ParticleModel model = p.model();
    const sim::Vec3 x0 = model.particles[p.particle].position, v0 = model.particles[p.particle].velocity;
    const long steps = std::lround(p.end / dt);
    Runs our_runs, their_runs;
    OurRun our_run;
    PeerRun their_run;
    auto block = [&](Runs& runs, auto run_one) {
        double spent = 0.0;  // s
        do {
            const double seconds = run_one();
            runs.add(seconds);
            spent += seconds;
        } while (spent < 0.25 * timing.min_seconds && runs.more(timing));
    };
    while (our_runs.more(timing) || their_runs.more(timing)) {
        block(our_runs, [&] { return (our_run = run_ours(p, model, ours, dt, steps)).seconds; });
        block(their_runs, [&] { return (their_run = run_peer(peer.name, p.name, x0, v0, dt, steps)).seconds; });
    }
    return {our_sample(p, model, ours, dt, our_runs, our_run), peer_sample(p, peer, dt, their_runs, their_run)};
}

// The peer's side of a batch of copies, against the method of ours it is compared with.
BatchResult measure_peer_batch(const Problem& p, const PeerInfo& peer, const BatchTiming& timing) {
    const sim::ParticleModel model = p.model();
    const auto method = sim::integrator_from_name(peer.ours).value();
    return measure_batch(p.name, method, peer.name, model.particles[p.particle].position,
                         model.particles[p.particle].velocity, p.end, peer.order >= 4 ? p.dt4 : p.dt2, timing);
}

}  // namespace

std::vector<Sample> measure_sweeps(const std::vector<Problem>& problems, const Settings& settings, Progress& progress) {
    std::vector<Sample> out;
    for (const Problem& p : problems) {
        for (const IntegratorInfo& info : sim::kIntegrators) {
            double dt = coarsest_dt(p, info);
            for (int k = 0; k < settings.dt_count; ++k, dt /= 2.0) out.push_back(measure(p, info, dt, settings.timing));
            progress.step(p.name + " " + std::string(info.name));
        }
    }
    return out;
}

// odeint's steppers on the same problems and dt sweeps; then the same pairs on
// a batch of 1000 copies of each problem.
std::vector<PeerSweep> measure_peers(const std::vector<Problem>& problems, const Settings& settings,
                                     Progress& progress) {
    std::vector<PeerSweep> out;
    for (const Problem& p : problems) {
        if (!peer_knows(p.name)) continue;
        for (const PeerInfo& peer : peers()) {
            if (p.drag && !peer.velocity_forces) continue;
            PeerSweep sweep{.peer = peer.name, .problem = p.name, .ours = peer.ours};
            const sim::IntegratorInfo& ours = sim::integrator_info(sim::integrator_from_name(peer.ours).value());
            double dt = peer.order >= 4 ? p.dt4 : p.dt2;
            for (int k = 0; k < settings.dt_count; ++k, dt /= 2.0) {
                // Ours again, beside theirs at the same dt, in blocks taken in
                // turn: the ratio then compares timings taken together, not
                // minutes apart (the sweeps above), which the machine's load
                // moves by a fifth.
                auto [mine, theirs] = measure_pair(p, ours, peer, dt, settings.timing);
                sweep.ours_samples.push_back(std::move(mine));
                sweep.samples.push_back(std::move(theirs));
            }
            if (peer.batch) sweep.batch = measure_peer_batch(p, peer, settings.batch);
            out.push_back(sweep);
        }
        progress.step("peers " + p.name);
    }
    return out;
}

// A game's frame: dt = 1/60 s split into 1 to 32 substeps, every method, every problem.
std::vector<Sample> measure_frames(const std::vector<Problem>& problems, const Settings& settings, Progress& progress) {
    std::vector<Sample> out;
    for (const Problem& p : problems) {
        for (const IntegratorInfo& info : sim::kIntegrators) {
            for (const int n : kFrameSubsteps) out.push_back(measure(p, info, 1.0 / 60.0 / n, settings.timing));
        }
        progress.step("frame budget " + p.name);
    }
    return out;
}

}  // namespace scenes::report
