// How cost grows with size, for `plausible report`: the wall time of one step
// against the size of six kinds of system, each built directly as a
// sim::ParticleModel at sizes on a geometric ladder, and the exponent p of
// cost ∝ size^p fitted log-log. Free particles, a mass-spring cloth, an XPBD
// cloth, a fountain's colliding droplets (a spatial hash) and ragdolls
// through ODE touch each particle, link or body a bounded number of times a
// step: p = 1. Newton gravity sums over every pair: p = 2.
//
// The report calls measure_growth() as one of its stages and writes what
// growth_files() makes: growth.csv, growth.dat and the gnuplot script of
// growth.png, report.json's "growth" and the Markdown section.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace scenes {

// One system measured at every size.
struct GrowthSeries {
    std::string system;                    // "N-body (Newton gravity)"
    std::string size_unit;                 // what size counts: "particles", "ragdolls"
    std::vector<int> sizes;                // ascending
    std::vector<double> seconds_per_step;  // s, wall time of one step at each size (best of the repetitions)
    double exponent = 0.0;                 // fitted p of cost ∝ size^p
    double expected = 1.0;                 // p that theory gives
};

struct GrowthTiming {
    double min_seconds = 0.1;  // s, each timed repetition runs at least this long
    int repetitions = 3;       // of which the fastest counts (noise only ever adds time)
};

// The timing of `report` (min_seconds 0.1 s) or `report --quick` (0.02 s).
GrowthTiming growth_timing(bool quick);

// The number of systems measure_growth() measures (for a progress bar).
std::size_t growth_system_count();

// Measures every system at every size; `done(system)` after each system.
// Throws std::runtime_error naming the system and size when a World stopped
// (the watchdog's verdict, or fewer steps than asked): a stopped World
// costs nothing a step, so its time would be a lie.
std::vector<GrowthSeries> measure_growth(const GrowthTiming& timing,
                                         const std::function<void(const std::string&)>& done);

// Least-squares slope of log(seconds) against log(size): the exponent p.
double fit_exponent(const std::vector<int>& sizes, const std::vector<double>& seconds);

// What the report writes of the measurement.
struct GrowthFiles {
    std::string csv;          // growth.csv: system,size,seconds_per_step
    std::string plot_data;    // growth.dat: one gnuplot data block per system
    std::string plot_script;  // draws growth.png from growth.dat (the terminal comes first, from the report)
    nlohmann::json json;      // report.json's "growth": [{system, sizes, seconds_per_step, exponent, expected}]
    std::string markdown;     // the section "How cost grows with size"
};
GrowthFiles growth_files(const std::vector<GrowthSeries>& series);

}  // namespace scenes
