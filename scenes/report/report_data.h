// The records `plausible report`'s stages pass along: the settings --quick
// chooses, the problems, what the measuring stages find (Measurements),
// what the analysis makes of it (Findings). Units in the comments.
// Its own file so that every stage (report_*.cpp) reads the same records;
// private to scenes/report (report.h is the public face).
#pragma once

#include "scenes/report/report_growth.h"
#include "scenes/report/report_peers.h"

#include "sim/analytic.h"
#include "sim/world.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace scenes::report {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The fit of an order uses errors in this band: below it rounding dominates,
// above it the method is not yet in its asymptotic regime.
inline constexpr double kFitFloor = 1e-11;
inline constexpr double kFitCeiling = 5e-2;

// A game's frame, dt = 1/60 s, split into this many substeps.
inline const std::vector<int> kFrameSubsteps = {1, 2, 4, 8, 16, 32};

// s simulated per trial on the stiff spring (sim::problems::stiff_spring_model).
inline constexpr double kStiffEnd = 2.0;

// The stability map's searches, by bisection in log.
inline constexpr double kDtLo = 1e-5, kDtHi = 0.25;  // s, the dt search
inline constexpr double kKLo = 1.0, kKHi = 1e10;     // N/m, the stiffness search at 1/60 s

// The target for the batch: our cost per copy at equal error at most
// this many times odeint's (the World's fixed cost spread over 1000 copies).
inline constexpr double kBatchTarget = 1.2;

// The rigid section's frame budgets, µs of one problem's physics per 1/60 s
// frame: what the recommendation is made for.
inline const std::vector<double> kRigidBudgets = {20.0, 100.0, 500.0};

// The lecture's budget: physics takes 5% to 30% of a 33 ms frame (30 FPS).
inline constexpr double kFrameMs = 1000.0 / 30.0;
inline constexpr double kPhysicsLow = 0.05 * kFrameMs, kPhysicsHigh = 0.30 * kFrameMs;  // ms

// --- the settings ------------------------------------------------------------------------

// Timing: at least `repetitions` runs, and more while they add up to under
// min_seconds (short runs are at the mercy of the clock); the median of all.
struct Timing {
    int repetitions = 1;
    double min_seconds = 0.005;  // s
};

// The rigid problems' step sizes: a 1/60 s frame in 1, 2, 4, 8, 16 substeps
// (--quick: 1, 4, 16), and how long each run is simulated.
struct RigidSpan {
    std::vector<int> substeps = {1, 2, 4, 8, 16};
    double seconds = 10.0;  // s simulated per run: the energy's and the tilt's span
    int repetitions = 3;    // runs timed, the median counts
};

// Everything --quick changes, in one place (settings_for in report.cpp).
struct Settings {
    bool quick = false;
    int dt_count = 8;               // dt values per method in a sweep, each half the one before
    Timing timing;                  // of every run in the sweeps
    BatchTiming batch;              // of the peers' batch of copies
    double drift_oscillator = 0.0;  // s simulated: 100 or 200 periods of 2π s
    double drift_kepler = 0.0;      // s simulated: 10 or 20 orbits of 2π s
    int stiff_bisections = 30;      // of the stiff spring's largest stable dt
    int map_bisections = 16;        // of each search of the stability map
    GrowthTiming growth;            // of how cost grows with size
    RigidSpan rigid;                // of the rigid problems
};

// --- the problems ------------------------------------------------------------------------

// A problem with an exact answer, swept over dt by every method.
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
    std::size_t particle = 0;                                  // the particle compared with the closed form
    std::function<sim::analytic::PointState(double t)> exact;  // its closed form; empty: the pendulum's period
    double period = 0.0;                                       // s, the pendulum's exact period
};

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

// --- what the measuring stages find -------------------------------------------------------

// One run of one method on one problem at one dt.
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

// One of odeint's steppers swept on one problem, and on the batch of copies.
struct PeerSweep {
    std::string peer;                  // "odeint_runge_kutta4"
    std::string problem;               // "oscillator"
    std::string ours;                  // the integrator of ours it is compared with
    std::vector<Sample> samples;       // the dt sweep, coarsest first
    std::vector<Sample> ours_samples;  // ours at the same dt values, each timed just before theirs
    std::optional<BatchResult> batch;  // measured when the peer is timed on the batch
};

struct Drift {
    std::string integrator;
    std::string problem;
    double first_half = 0.0;   // max |E - E0| / |E0| over the first half of the run
    double second_half = 0.0;  // ... over the second half
    bool exploded = false;
    std::vector<std::pair<double, double>> envelope;  // (t, running max of |E - E0| / |E0|), for the plot
    bool bounded() const { return !exploded && second_half <= 1.2 * first_half + 1e-13; }
};

// One method on the stiff spring.
struct Stability {
    std::string integrator;
    double largest_dt = 0.0;       // s, the largest stable dt found (upper end of the search if never unstable)
    bool always_stable = false;    // stable up to the search's upper end
    bool stable_at_frame = false;  // at 1/60 s
    std::uint64_t exploded_frame = 0;
    std::string quantity;  // what the watchdog saw at 1/60 s
};

struct MapCell {
    std::string hard_case, integrator;
    double largest_dt = 0.0;         // s; the search's upper end if always stable, 0 if unstable at its lower end
    double largest_stiffness = 0.0;  // N/m at 1/60 s (0: none; NaN: not a spring case)
};

struct StabilityMap {
    std::vector<std::string> cases;  // the hard cases' names, the map's rows
    std::vector<MapCell> cells;      // case by case, each every method in sim::kIntegrators' order
    double ragdoll_dt = 0.0;         // s, the largest stable dt of the thrown ragdoll through ODE
};

// Macklin et al. (2019)'s claim, one way at one n.
struct SmallSteps {
    std::string body;  // rope, cloth
    std::string way;   // substeps, iterations
    int n = 1;
    double strain = 0.0;  // max |length / rest - 1| over the links at the end
    double ms_per_frame = 0.0;
};

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

// --- rigid bodies (report_rigid.cpp, report_rigid_peers.cpp) --------------------------------

// One solver and setting of one problem at one step h: its errors against
// the closed forms (relative unless said; NaN: not applicable, or the run
// failed) and its cost.
struct RigidSample {
    std::string problem;  // "pendulum", "top", "chain"
    std::string solver;   // "plausible", "ode_quickstep", "ode_exact", "bullet_multibody", "bullet_sequential_impulse"
    std::string setting;  // "defaults", "20 iterations", ...
    double h = 0.0;       // s
    // The largest of the problem's errors below, each relative (the tilt's
    // over the tilt): the one number the plots and the fitted orders use.
    double error = kNaN;
    double period_error = kNaN;      // pendulum: |T / T_exact - 1| over its first full swing
    double energy_error = kNaN;      // pendulum: |ΔE| / m g d (1 - cos θ0); chain: |ΔE| / 78.48 J; over the run
    double precession_error = kNaN;  // top: |rate over the first 2 s / Ω - 1|
    double tilt_error = kNaN;        // top: |θ - 30°| at the run's end, deg
    double us_per_frame = kNaN;      // µs of wall time per 1/60 s of simulated time (median of the runs)
    bool failed = false;             // non-finite state, or a spin past sim::kMaxBodySpin
    std::string label() const { return solver + " " + setting; }
    bool ours() const { return solver.rfind("bullet", 0) != 0; }  // through sim::RigidWorld
};

struct Measurements {
    std::vector<Problem> problems;
    std::vector<Sample> sweeps;           // problem by problem, method by method, coarsest dt first
    std::vector<PeerSweep> peers;         // problem by problem, peer by peer
    std::vector<Sample> frames;           // 1/60 s in kFrameSubsteps: problem by problem, method by method
    std::vector<Drift> drifts;            // method by method: the oscillator, then the e = 0.5 orbit
    std::vector<Stability> limits;        // the stiff spring, method by method
    StabilityMap map;                     // the hard cases and the ragdoll
    std::vector<SmallSteps> small_steps;  // body, n, then substeps before iterations
    std::vector<SceneCost> costs;         // every shipped scene, in catalog order
    std::vector<GrowthSeries> growth;     // how cost grows with size
    std::vector<RigidSample> rigid;       // problem by problem, solver by solver, coarsest h first
};

// --- what the analysis makes of them --------------------------------------------------------

// Least-squares slope of log(error) on log(dt) over the errors in the fit band.
struct Fit {
    double slope = kNaN;
    int points = 0;
};

struct OrderFit {
    std::string problem, integrator;
    Fit fit;
    int expected = 0;  // the order theory gives; 0: none applies, or the method is exact
};

struct PeerRow {
    std::string peer, problem, ours;
    Fit fit;
    double ratio = kNaN;  // our seconds / theirs at equal error, one particle
    std::optional<BatchResult> batch;
    double steps_ratio = kNaN;  // our steps / theirs at equal error (the single copy's sweeps)
    double ratio_batch = kNaN;  // our seconds / theirs at equal error, per copy of the batch
    std::string batch_basis;    // what "equal error" rests on (see batch_ratio)
};

// A rigid solver and setting's fitted order on one problem (of its headline error in h).
struct RigidOrder {
    std::string problem, solver, setting;
    Fit fit;
};

// The most accurate measured point of a rigid problem within a cost budget.
struct RigidPick {
    std::string problem;
    double budget = 0.0;              // µs per 1/60 s frame
    std::optional<RigidSample> best;  // any solver; empty: nothing that cheap
    std::optional<RigidSample> ours;  // through sim::RigidWorld (plausible, ode_*)
};

struct Findings {
    std::vector<OrderFit> orders;                       // problem by problem, method by method
    std::map<std::string, std::vector<Sample>> fronts;  // per problem, its Pareto front, cheapest first
    std::vector<PeerRow> peers;                         // as Measurements::peers
    std::vector<RigidOrder> rigid_orders;               // as the series of Measurements::rigid
    std::vector<RigidPick> rigid_picks;                 // problem by problem, budget by budget
};

}  // namespace scenes::report
