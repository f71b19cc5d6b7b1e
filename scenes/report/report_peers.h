// Peers for `plausible report`: boost::odeint's steppers (Debian's
// libboost-dev, header-only) on the report's closed-form problems, so that
// our integrators' cost at equal error can be given as a ratio. Built into
// the command's library only, never into the physics core.
//
// Two measurements: the single copy (one particle, run_peer; the report
// times our World itself) and the batch (measure_batch): 1000 independent
// copies of the problem as one World of ours and one odeint state, so that
// the World's fixed cost per step is spread over 1000 particles and what is
// left is the integrators' and the forces' own speed.
#pragma once

#include "sim/integrators.h"
#include "sim/vec3_array.h"

#include <string>
#include <string_view>
#include <vector>

namespace scenes {

struct PeerInfo {
    std::string name;  // "odeint_runge_kutta4"
    std::string ours;  // the integrator of ours it is compared with (of the same order)
    int order = 0;
    int evaluations = 0;   // force evaluations per step
    bool velocity_forces;  // can it take a velocity-dependent force (drag)?
    bool batch = false;    // also timed on the batch of copies (measure_batch)
};
const std::vector<PeerInfo>& peers();

// The problems the peers know: "ballistic", "oscillator", "damped",
// "kepler_e0.5", "kepler_e0.9" (the same accelerations as the report's
// particle models).
bool peer_knows(std::string_view problem);

struct PeerRun {
    sim::Vec3 x = sim::Vec3::Zero();  // m, at the end
    double seconds = 0.0;             // wall time of the run
};

// One run of `peer` on `problem` from (x0, v0) for `steps` steps of dt.
PeerRun run_peer(std::string_view peer, std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double dt,
                 long steps);

// --- the batch -------------------------------------------------------------------------

// The initial conditions of `count` independent copies of the problem that
// starts at (x0, v0): copy c at s = (c + 0.5) / count - 1/2 starts at
//   x0 (1 + δ s),   v0 (1 - δ s) + δ s |v0| ẑ,   δ = 1e-3,
// a spread small enough that every copy is the same problem (the same error
// at the same dt, to a fraction of a percent) and large enough that no two
// copies compute the same numbers.
struct Copies {
    std::vector<sim::Vec3> x0;  // m
    std::vector<sim::Vec3> v0;  // m/s
};
Copies batch_copies(const sim::Vec3& x0, const sim::Vec3& v0, int count);

// Where copy c is at time t, m: the problem's closed form from the copy's start.
sim::Vec3 batch_exact(std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double t);

struct BatchTiming {
    int copies = 1000;
    double min_seconds = 0.02;  // s, each timed repetition of each side lasts at least this long
    int repetitions = 3;        // the fastest counts (noise only ever adds time)
};

// One method pair on the batch at one dt.
struct BatchResult {
    int copies = 0;
    double dt = 0.0;              // s
    long steps = 0;               // per run (a repetition may hold several runs)
    double ours_seconds = 0.0;    // s per step per copy, our World (best of the repetitions)
    double theirs_seconds = 0.0;  // s per step per copy, odeint
    double ours_error = 0.0;      // m, the largest over the copies against each one's closed form at the end
    double theirs_error = 0.0;    // m, the same for odeint
};

// Times `ours` and `peer` on `timing.copies` copies of `problem` (started
// from the copies of (x0, v0)) at dt, each run `end` / dt steps or more (as
// many as make a run last min_seconds; the ballistic shot's at most 30 s, to
// stay inside the watchdog's box), the two sides in turn, and measures each
// side's error at the end. Throws std::runtime_error naming the problem when
// our World stopped (the watchdog's verdict, or fewer steps than asked): a
// stopped World costs nothing a step, so its time would be a lie.
BatchResult measure_batch(std::string_view problem, sim::Integrator ours, std::string_view peer, const sim::Vec3& x0,
                          const sim::Vec3& v0, double end, double dt, const BatchTiming& timing);

}  // namespace scenes
