// `plausible report`: speed against error. Every integrator on problems with
// exact answers (ballistic shot, harmonic and damped oscillators, Kepler
// orbits of eccentricity 0.5 and 0.9, a large-amplitude pendulum on an XPBD
// rod), over a sweep of dt: global error at the end time, energy error, cost
// in force evaluations and in measured time per simulated second; the fitted
// order of convergence; the Pareto front (at each error level, the cheapest
// method); energy drift over long runs; and the largest stable dt of each
// method on a stiff spring, found by bisection with the watchdog deciding;
// how the cost of a step grows with the size of six kinds of system
// (scenes/report/report_growth.h), with the fitted exponent; and boost::odeint's
// steppers as peers (scenes/report/report_peers.h), our cost at equal error over
// theirs on the single particle (where the World's fixed cost per step
// dominates) and on a batch of 1000 independent copies of each problem
// (where it is spread over 1000 particles, and the integrators' own speed
// shows); and rigid bodies (scenes/report/report_rigid.h): a hinged rod, a
// heavy top and a chain of 8 links through sim::RigidWorld and Bullet, error
// against cost per 1/60 s frame over substeps.
//
// Output (into --out, written whole or not at all): report.md (tables, each
// with a one-line conclusion), work_precision.csv, orders.csv, stability.csv,
// growth.csv (system, size, seconds_per_step), rigid.csv (problem, solver,
// setting, h, errors, us_per_frame), report.json (`orders`: a list
// of {integrator, problem, fitted, expected}; `pareto`; `drift`; `stability`;
// `growth`: a list of {system, size_unit, sizes, seconds_per_step, exponent,
// expected}; `rigid`: {cost_unit, seconds_simulated, substeps, samples,
// orders, picks}; `peers`: a list of {peer, problem, compared_with, fitted,
// cost_ratio (one particle), ratio_batch (the batch of 1000),
// ratio_batch_basis, batch: {copies, dt, steps, ours_ and
// theirs_seconds_per_copy_step, ratio_at_equal_dt,
// steps_ratio_at_equal_error, ours_ and theirs_error}}), peers.csv and PNG
// plots drawn by gnuplot (Debian's gnuplot-nox):
// work-precision and error-against-dt with reference slopes per problem,
// energy over time, the stability limits, cost per step against size
// (growth.png, log-log), each rigid problem's error against cost
// (rigid_<problem>.png, log-log).
#pragma once

#include <filesystem>
#include <string>

namespace scenes {

struct ReportOptions {
    bool quick = false;                        // fewer dt values and repetitions: CI's run, under 60 s
    std::filesystem::path out = "out/report";  // the directory written
    bool progress = false;                     // a progress bar with ETA on stderr
};

// Writes the report; returns the path of report.md. Throws sim::InputError
// when --out cannot be written or gnuplot is missing or fails (nothing is
// left behind then).
std::filesystem::path write_report(const ReportOptions& options);

}  // namespace scenes
