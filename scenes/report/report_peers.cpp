#include "scenes/report/report_peers.h"

#include "sim/analytic.h"
#include "sim/cpu.h"
#include "sim/error.h"
#include "sim/problems.h"
#include "sim/world.h"

#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace scenes {
namespace {

namespace odeint = boost::numeric::odeint;
using S3 = std::array<double, 3>;
using S6 = std::array<double, 6>;

namespace pr = sim::problems;

// The accelerations of the report's problems (unit-mass test particle).
struct Ballistic {
    void operator()(const S3&, const S3&, S3& a) const { a = {0.0, -pr::kGravity, 0.0}; }
};
struct Oscillator {  // k = m = 1
    void operator()(const S3& x, const S3&, S3& a) const {
        for (int k = 0; k < 3; ++k) a[k] = -x[k];
    }
};
struct Damped {  // k = m = 1, c = 0.2 (sim::problems::kDamped)
    void operator()(const S3& x, const S3& v, S3& a) const {
        for (int k = 0; k < 3; ++k) a[k] = -x[k] - pr::kDamped.damping * v[k];
    }
};
struct Kepler {  // μ = 1
    void operator()(const S3& x, const S3&, S3& a) const {
        const double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        const double s = -1.0 / (r2 * std::sqrt(r2));
        for (int k = 0; k < 3; ++k) a[k] = s * x[k];
    }
};

template <class Accel>
PeerRun integrate(std::string_view peer, Accel accel, const sim::Vec3& x0, const sim::Vec3& v0, double dt, long steps) {
    S3 x{x0.x(), x0.y(), x0.z()}, v{v0.x(), v0.y(), v0.z()};
    double t = 0.0;
    const auto start = std::chrono::steady_clock::now();
    if (peer == "odeint_runge_kutta4") {
        S6 s{x[0], x[1], x[2], v[0], v[1], v[2]};
        odeint::runge_kutta4<S6> stepper;
        auto f = [&](const S6& y, S6& d, double) {
            S3 a;
            accel(S3{y[0], y[1], y[2]}, S3{y[3], y[4], y[5]}, a);
            d = {y[3], y[4], y[5], a[0], a[1], a[2]};
        };
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, s, t, dt);
        x = {s[0], s[1], s[2]};
    } else if (peer == "odeint_velocity_verlet") {
        odeint::velocity_verlet<S3> stepper;
        auto f = [&](const S3& q, const S3& w, S3& a, double) { accel(q, w, a); };
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, std::make_pair(std::ref(x), std::ref(v)), t, dt);
    } else if (peer == "odeint_rkn_mclachlan4") {
        odeint::symplectic_rkn_sb3a_mclachlan<S3> stepper;
        auto f = [&](const S3& q, S3& dpdt) { accel(q, S3{}, dpdt); };  // position forces only
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, std::make_pair(std::ref(x), std::ref(v)), t, dt);
    } else {
        throw sim::InputError("report: no peer '" + std::string(peer) + "'");
    }
    PeerRun r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.x = sim::Vec3(x[0], x[1], x[2]);
    return r;
}

}  // namespace

const std::vector<PeerInfo>& peers() {
    static const std::vector<PeerInfo> list = {
        {.name = "odeint_runge_kutta4",
         .ours = "rk4",
         .order = 4,
         .evaluations = 4,
         .velocity_forces = true,
         .batch = true},
        {.name = "odeint_velocity_verlet",
         .ours = "velocity_verlet",
         .order = 2,
         .evaluations = 1,
         .velocity_forces = true,
         .batch = true},
        // McLachlan's 4th-order symplectic Runge-Kutta-Nyström, 6 stages (5 new force evaluations per step).
        {.name = "odeint_rkn_mclachlan4", .ours = "rk4", .order = 4, .evaluations = 5, .velocity_forces = false},
    };
    return list;
}

bool peer_knows(std::string_view problem) {
    return problem == "ballistic" || problem == "oscillator" || problem == "damped" || problem == "kepler_e0.5" ||
           problem == "kepler_e0.9";
}

PeerRun run_peer(std::string_view peer, std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double dt,
                 long steps) {
    if (problem == "ballistic") return integrate(peer, Ballistic{}, x0, v0, dt, steps);
    if (problem == "oscillator") return integrate(peer, Oscillator{}, x0, v0, dt, steps);
    if (problem == "damped") return integrate(peer, Damped{}, x0, v0, dt, steps);
    if (problem == "kepler_e0.5" || problem == "kepler_e0.9") return integrate(peer, Kepler{}, x0, v0, dt, steps);
    throw sim::InputError("report: the peers do not know the problem '" + std::string(problem) + "'");
}

// --- the batch -------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kBallisticSpan = 30.0;  // s: a shot falls 4.3 km, to 290 m/s: inside the watchdog's 10 km and 500 m/s

// Our World of the copies, one particle each (after `first` pinned ones).
// Ballistic: free particles in the uniform field (the fused fast path).
// Oscillators: each bead on its own zero-rest-length spring to one shared
// pinned anchor at the origin (a pinned particle's force moves nothing, so
// the beads are independent), the damper as linear drag. Kepler: each
// particle about a fixed attractor through CentralGravity (NewtonGravity
// would make the copies attract each other, and cost O(n²)).
sim::ParticleModel batch_model(std::string_view problem, const Copies& copies, std::size_t& first) {
    sim::ParticleModel model;
    const std::size_t n = copies.x0.size();
    first = 0;
    if (problem == "ballistic") {
        for (std::size_t c = 0; c < n; ++c) model.particles.push_back({copies.x0[c], copies.v0[c], 1.0, false});
        model.forces.push_back(sim::UniformGravity{pr::kShotGravity});
    } else if (problem == "oscillator" || problem == "damped") {
        first = 1;
        model.particles.push_back({sim::Vec3::Zero(), sim::Vec3::Zero(), 1.0, true});
        sim::Springs springs;
        for (std::size_t c = 0; c < n; ++c) {
            model.particles.push_back({copies.x0[c], copies.v0[c], pr::kOscillator.mass, false});
            springs.list.push_back({0, static_cast<std::uint32_t>(c + 1), 0.0, pr::kOscillator.stiffness, 0.0});
        }
        model.forces.push_back(std::move(springs));
        if (problem == "damped") model.forces.push_back(sim::LinearDrag{pr::kDamped.damping});
    } else if (problem == "kepler_e0.5" || problem == "kepler_e0.9") {
        for (std::size_t c = 0; c < n; ++c)
            model.particles.push_back({copies.x0[c], copies.v0[c], pr::kKeplerMass, false});
        model.forces.push_back(sim::CentralGravity{sim::Vec3::Zero(), pr::kKeplerMu});
    } else {
        throw sim::InputError("report: no batch of the problem '" + std::string(problem) + "'");
    }
    return model;
}

// odeint's side of the batch: the accelerations of n copies at once over
// component arrays (x: 3n values, all x, then all y, then all z; v and a
// alike), loops a user would write and the compiler vectorises.
struct BallisticBatch {
    void operator()(const double*, const double*, double* a, std::size_t n) const {
        std::fill(a, a + n, 0.0);
        std::fill(a + n, a + 2 * n, -pr::kGravity);
        std::fill(a + 2 * n, a + 3 * n, 0.0);
    }
};
struct OscillatorBatch {  // k = m = 1
    void operator()(const double* x, const double*, double* a, std::size_t n) const {
        for (std::size_t i = 0; i < 3 * n; ++i) a[i] = -x[i];
    }
};
struct DampedBatch {  // k = m = 1, c = 0.2 (sim::problems::kDamped)
    void operator()(const double* x, const double* v, double* a, std::size_t n) const {
        for (std::size_t i = 0; i < 3 * n; ++i) a[i] = -x[i] - pr::kDamped.damping * v[i];
    }
};
// (__restrict parameters of a function of its own, as our force loops have
// them: written inline, GCC leaves the loop scalar, its square root and
// division one at a time.)
void kepler_batch(const double* __restrict x, const double* __restrict y, const double* __restrict z,
                  double* __restrict ax, double* __restrict ay, double* __restrict az, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const double r2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i];
        const double s = -1.0 / (r2 * std::sqrt(r2));
        ax[i] = s * x[i], ay[i] = s * y[i], az[i] = s * z[i];
    }
}
struct KeplerBatch {  // μ = 1
    void operator()(const double* x, const double*, double* a, std::size_t n) const {
        kepler_batch(x, x + n, x + 2 * n, a, a + n, a + 2 * n, n);
    }
};

struct PeerBatchRun {
    std::vector<double> x;  // m, at the end: all x, all y, all z
    double seconds = 0.0;   // wall time of the steps
};

// odeint's state on the batch: std::vector starting on a cache line, as
// our World's arrays do (sim::Vec3Array). With malloc's 16-byte alignment
// it started at 16, 32 or 48 bytes into a line in some of a report's
// batches, and its 32-byte loads then straddled lines: odeint's velocity
// Verlet read 1.28-1.48 ns a copy-step in the report against 1.07-1.15 in
// a process of its own, which flattered our ratio.
using BatchState = std::vector<double, sim::CacheLineAllocator<double>>;

// One run of `peer` on the copies: BatchState states, odeint's default range
// algebra (its temporaries are sized at the first step, then nothing is
// allocated). Its steps are built at our World's width (AVX2 where the CPU
// has it, sim/cpu.h), so that the ratio compares the integrators, not the
// instruction sets.
template <class Accel>
PeerBatchRun integrate_batch(std::string_view peer, Accel accel, const Copies& copies, double dt, long steps) {
    const std::size_t n = copies.x0.size();
    BatchState q(3 * n), p(3 * n);
    for (std::size_t c = 0; c < n; ++c) {
        for (std::size_t k = 0; k < 3; ++k) {
            q[k * n + c] = copies.x0[c][static_cast<int>(k)];
            p[k * n + c] = copies.v0[c][static_cast<int>(k)];
        }
    }
    PeerBatchRun run;
    double t = 0.0;
    if (peer == "odeint_runge_kutta4") {
        BatchState y(q);
        y.insert(y.end(), p.begin(), p.end());
        odeint::runge_kutta4<BatchState> stepper;
        auto f = [&](const BatchState& s, BatchState& d, double) {
            std::copy(s.begin() + static_cast<std::ptrdiff_t>(3 * n), s.end(), d.begin());
            accel(s.data(), s.data() + 3 * n, d.data() + 3 * n, n);
        };
        const auto start = Clock::now();
        sim::run_at_width(sim::avx2_available(), [&] {
            for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, y, t, dt);
        });
        run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        run.x.assign(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(3 * n));
    } else if (peer == "odeint_velocity_verlet") {
        odeint::velocity_verlet<BatchState> stepper;
        auto f = [&](const BatchState& qq, const BatchState& pp, BatchState& a, double) {
            accel(qq.data(), pp.data(), a.data(), n);
        };
        const auto start = Clock::now();
        sim::run_at_width(sim::avx2_available(), [&] {
            for (long i = 0; i < steps; ++i, t += dt) {
                stepper.do_step(f, std::make_pair(std::ref(q), std::ref(p)), t, dt);
            }
        });
        run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        run.x.assign(q.begin(), q.end());
    } else {
        throw sim::InputError("report: no batch of the peer '" + std::string(peer) + "'");
    }
    return run;
}

PeerBatchRun run_peer_batch(std::string_view peer, std::string_view problem, const Copies& copies, double dt,
                            long steps) {
    if (problem == "ballistic") return integrate_batch(peer, BallisticBatch{}, copies, dt, steps);
    if (problem == "oscillator") return integrate_batch(peer, OscillatorBatch{}, copies, dt, steps);
    if (problem == "damped") return integrate_batch(peer, DampedBatch{}, copies, dt, steps);
    if (problem == "kepler_e0.5" || problem == "kepler_e0.9") {
        return integrate_batch(peer, KeplerBatch{}, copies, dt, steps);
    }
    throw sim::InputError("report: no batch of the problem '" + std::string(problem) + "'");
}

}  // namespace

Copies batch_copies(const sim::Vec3& x0, const sim::Vec3& v0, int count) {
    constexpr double kSpread = 1e-3;  // δ, relative
    Copies copies;
    for (int c = 0; c < count; ++c) {
        const double s = kSpread * ((c + 0.5) / count - 0.5);
        copies.x0.push_back((1.0 + s) * x0);
        copies.v0.push_back((1.0 - s) * v0 + s * v0.norm() * sim::Vec3::UnitZ());
    }
    return copies;
}

sim::Vec3 batch_exact(std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double t) {
    if (problem == "ballistic") return sim::analytic::ballistic(x0, v0, pr::kShotGravity, t).x;
    if (problem == "oscillator") return sim::analytic::oscillator(pr::kOscillator, x0, v0, t).x;
    if (problem == "damped") return sim::analytic::oscillator(pr::kDamped, x0, v0, t).x;
    if (problem == "kepler_e0.5" || problem == "kepler_e0.9") return sim::analytic::kepler(pr::kKeplerMu, x0, v0, t).x;
    throw sim::InputError("report: no closed form of the problem '" + std::string(problem) + "'");
}

BatchResult measure_batch(std::string_view problem, sim::Integrator ours, std::string_view peer, const sim::Vec3& x0,
                          const sim::Vec3& v0, double end, double dt, const BatchTiming& timing) {
    const Copies copies = batch_copies(x0, v0, timing.copies);
    const auto n = static_cast<std::size_t>(timing.copies);
    std::size_t first = 0;
    const sim::ParticleModel model = batch_model(problem, copies, first);
    const sim::StepSettings step{ours, dt, 1};
    const std::string what = "the batch of " + std::to_string(n) + " copies of " + std::string(problem) + " (" +
                             std::string(sim::integrator_info(ours).name) + ", dt " + sim::format_value(dt) + " s)";

    // `runs` runs of `steps` steps, each on a World built before the clock
    // starts; the last World is kept for its error.
    std::unique_ptr<sim::World> last;
    auto time_ours = [&](long steps, int runs) {
        std::vector<std::unique_ptr<sim::World>> worlds;
        for (int r = 0; r < runs; ++r) worlds.push_back(std::make_unique<sim::World>(model));
        const auto start = Clock::now();
        for (const auto& w : worlds) {
            for (long i = 0; i < steps; ++i) w->step(step);
        }
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        for (const auto& w : worlds) {
            if (w->verdict().exploded()) {
                throw std::runtime_error("report: the World stopped, so its time is no measure: " +
                                         w->verdict().message(what));
            }
            if (w->steps() != static_cast<std::uint64_t>(steps)) {
                throw std::runtime_error("report: " + what + " made " + std::to_string(w->steps()) + " steps of the " +
                                         std::to_string(steps) + " asked");
            }
        }
        last = std::move(worlds.back());
        return seconds;
    };
    PeerBatchRun theirs;
    auto time_theirs = [&](long steps, int runs) {
        double seconds = 0.0;
        for (int r = 0; r < runs; ++r) {
            theirs = run_peer_batch(peer, problem, copies, dt, steps);
            seconds += theirs.seconds;
        }
        return seconds;
    };

    // A run covers the problem's span, or as many more steps as make it last
    // min_seconds (the ballistic shot's at most kBallisticSpan; the damped
    // oscillator's at most its span: longer, its copies decay to nothing and
    // the batch's errors with them); then as many runs to a repetition as
    // make it last min_seconds, from the time of a run of each side once warm.
    long steps = std::max(1L, std::lround(end / dt));
    const long most = problem == "ballistic" ? std::lround(kBallisticSpan / dt)
                      : problem == "damped"  ? steps
                                             : std::numeric_limits<long>::max() / 4;
    time_ours(steps, 1);  // warm-up: the first run's caches and allocations
    double run_ours = time_ours(steps, 1);
    while (run_ours < timing.min_seconds && steps < most) {
        const double scale = 1.2 * timing.min_seconds / std::max(run_ours, 1e-7);
        steps = std::min(most, std::max(2 * steps, std::lround(std::ceil(static_cast<double>(steps) * scale))));
        run_ours = time_ours(steps, 1);
    }
    time_theirs(steps, 1);
    const double run_theirs = time_theirs(steps, 1);
    auto runs_for = [&](double run) {
        return std::max(1, static_cast<int>(std::ceil(1.1 * timing.min_seconds / std::max(run, 1e-7))));
    };
    const int runs_ours = runs_for(run_ours), runs_theirs = runs_for(run_theirs);

    BatchResult r;
    r.copies = timing.copies;
    r.dt = dt;
    r.steps = steps;
    r.ours_seconds = r.theirs_seconds = std::numeric_limits<double>::infinity();
    const double per = static_cast<double>(steps) * static_cast<double>(n);  // copy-steps per run
    for (int k = 0; k < timing.repetitions; ++k) {
        r.ours_seconds = std::min(r.ours_seconds, time_ours(steps, runs_ours) / (runs_ours * per));
        r.theirs_seconds = std::min(r.theirs_seconds, time_theirs(steps, runs_theirs) / (runs_theirs * per));
    }

    const double t = last->state().t;
    for (std::size_t c = 0; c < n; ++c) {
        const sim::Vec3 exact = batch_exact(problem, copies.x0[c], copies.v0[c], t);
        const sim::Vec3 x(theirs.x[c], theirs.x[n + c], theirs.x[2 * n + c]);
        const double ours_error = (last->state().x.get(first + c) - exact).norm(), theirs_error = (x - exact).norm();
        // (std::max would drop a NaN)
        r.ours_error = std::isfinite(ours_error) ? std::max(r.ours_error, ours_error) : ours_error;
        r.theirs_error = std::isfinite(theirs_error) ? std::max(r.theirs_error, theirs_error) : theirs_error;
        if (!std::isfinite(r.ours_error) || !std::isfinite(r.theirs_error)) break;
    }
    return r;
}

}  // namespace scenes
