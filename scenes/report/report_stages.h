// The stages of `plausible report`, file by file, in the order write_report
// (report.cpp) runs them: measure → analyse → write the tables → plot → write
// report.md. Each stage reads and returns the records of report_data.h. Its
// own file so that the pipeline reads as one table of contents.
#pragma once

#include "scenes/common/progress.h"
#include "scenes/report/report_data.h"

#include "sim/integrators.h"

#include <filesystem>
#include <string>
#include <vector>

namespace scenes::report {

// --- report_problems.cpp: the problems and the hard cases ----------------------------------

std::vector<Problem> problems();
std::vector<HardCase> hard_cases();
// The watchdog on the stiff spring (kStiffK): what "exploded" means there.
sim::WatchdogLimits stiff_spring_limits();
// The order theory gives the method on the problem; 0: none applies (the
// pendulum's projection), or the method is exact (order >= 2 on the ballistic shot).
int expected_order(const Problem& p, const sim::IntegratorInfo& info);
// The first dt of the method's sweep on the problem, s.
double coarsest_dt(const Problem& p, const sim::IntegratorInfo& info);

// --- report_sweeps.cpp: measuring error and cost over dt -----------------------------------

// Every method on every problem over settings.dt_count halvings of dt.
std::vector<Sample> measure_sweeps(const std::vector<Problem>& problems, const Settings& settings, Progress& progress);
// odeint's steppers on the problems they know, and on the batch of copies.
std::vector<PeerSweep> measure_peers(const std::vector<Problem>& problems, const Settings& settings,
                                     Progress& progress);
// Every method on every problem at 1/60 s in kFrameSubsteps.
std::vector<Sample> measure_frames(const std::vector<Problem>& problems, const Settings& settings, Progress& progress);

// --- report_stability.cpp: long runs and large steps ---------------------------------------

std::vector<Drift> measure_drift(const Settings& settings, Progress& progress);
std::vector<Stability> measure_stiff_spring(const Settings& settings, Progress& progress);
StabilityMap measure_stability_map(const Settings& settings, Progress& progress);
std::vector<SmallSteps> measure_small_steps(Progress& progress);

// --- report_scene_costs.cpp: every shipped scene against the frame budget -------------------

// `scratch`: a folder for ffmpeg's messages.
std::vector<SceneCost> measure_scene_costs(bool quick, const std::filesystem::path& scratch, Progress& progress);
// "exploded", "over", "within" or "under" the physics budget.
const char* budget_verdict(const SceneCost& c);

// --- report_rigid.cpp: rigid bodies against closed forms, ours and Bullet's --------------------

// "pendulum", "top", "chain" (report_rigid.h describes them).
const std::vector<std::string>& rigid_problems();
// The solver-setting series measure_rigid runs, one progress step each.
int rigid_series_count();
// Every solver and setting on every problem at each of span.substeps of a 1/60 s frame.
std::vector<RigidSample> measure_rigid(const RigidSpan& span, Progress& progress);

// --- report_analysis.cpp: fitted orders, Pareto fronts, cost ratios --------------------------

Fit fit_order(const std::vector<Sample>& samples);
// The middle value of `v` (the upper middle of an even count); `v` not empty.
double median(std::vector<double> v);
// `in` by `problem` and `integrator`, in their order.
std::vector<Sample> samples_of(const std::vector<Sample>& in, const std::string& problem,
                               const std::string& integrator);
// Everything the report concludes from the measurements.
Findings analyse(const Measurements& m);
const OrderFit& order_of(const Findings& f, const std::string& problem, const std::string& integrator);

// --- report_tables.cpp: the CSV files and report.json ---------------------------------------

void write_tables(const std::filesystem::path& dir, const Settings& settings, const Measurements& m, const Findings& f);
// printf's `format` of one number.
std::string fmt(const char* format, double v);
// Throws sim::InputError when the file cannot be written.
void write_file(const std::filesystem::path& path, const std::string& text);

// --- report_plots.cpp: the gnuplot scripts and their PNGs -----------------------------------

// Throws sim::InputError when gnuplot fails.
void draw_plots(const std::filesystem::path& dir, const Measurements& m);

// --- report_markdown.cpp: report.md ----------------------------------------------------------

void write_markdown(const std::filesystem::path& dir, const Settings& settings, const Measurements& m,
                    const Findings& f);

}  // namespace scenes::report
