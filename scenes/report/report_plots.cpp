// The report's plots: for each, its data file (.dat) and the gnuplot script
// that draws the PNG from it (Debian's gnuplot-nox, run in the report's
// folder). Work-precision and error against dt per problem, energy over
// time, the stiff spring's limits, the stability map, every scene's cost,
// how cost grows. Its own file: the only stage that runs gnuplot.
#include "scenes/report/report_stages.h"

#include "scenes/common/child_process.h"
#include "scenes/common/interrupt.h"

#include "sim/error.h"
#include "sim/integrators.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace scenes::report {
namespace {

namespace fs = std::filesystem;

// Runs gnuplot on a script in `dir`; its errors become an InputError.
void gnuplot(const fs::path& dir, const std::string& name, const std::string& script) {
    const fs::path gp = dir / (name + ".gp"), err = dir / (name + ".gnuplot-errors");
    write_file(gp, script);
    // Run in `dir`, so that the script names its files without the folder's path.
    const int status = ChildProcess({"gnuplot", gp.filename().string()}, {.errors = err, .directory = dir}).wait();
    std::ifstream e(err);
    std::stringstream text;
    text << e.rdbuf();
    fs::remove(err);
    fs::remove(gp);
    // A Ctrl+C in a terminal reaches gnuplot too: a gnuplot ended by it says so.
    if (const int signal = child_interrupt(status); signal != 0) throw_interrupted("report", name + ".png", signal);
    check_interrupt("report", name + ".png");  // the same Ctrl+C reached us: gnuplot's failure is its doing
    if (status != 0) throw sim::InputError("report: gnuplot failed on " + name + ".png: " + text.str());
}

const char* kTerminal = "set terminal pngcairo size 960,680 enhanced font 'DejaVu Sans,12' linewidth 1.5\n";

// A horizontal reference line across a bar chart of `bars` bars, at y.
std::string hline(double y, std::size_t bars, const std::string& look) {
    return "set arrow from -0.5," + fmt("%.6g", y) + " to " + std::to_string(bars) + "-0.5," + fmt("%.6g", y) +
           " nohead " + look + "\n";
}

// One colour per integrator, the same in every plot.
std::string style(std::size_t k) {
    static const char* colors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#ff7f0e", "#17becf"};
    return "lc rgb '" + std::string(colors[k % 7]) + "' pt " + std::to_string(5 + static_cast<int>(k % 7) * 2);
}

// --- work-precision and error against dt, per problem ------------------------------------------

// Every sample in the order the plots read them: the sweeps, the frame substeps, the peers'.
std::vector<const Sample*> every_sample(const Measurements& m) {
    std::vector<const Sample*> out;
    for (const std::vector<Sample>* from : {&m.sweeps, &m.frames})
        for (const Sample& s : *from) out.push_back(&s);
    for (const PeerSweep& peer : m.peers)
        for (const Sample& s : peer.samples) out.push_back(&s);
    return out;
}

// The two plots' lines: ours, then odeint's (dashed, grey), one data block each.
struct SweepLines {
    std::ostringstream data;  // the .dat file: dt, error, seconds, evaluations per block
    std::ostringstream wp;    // the plot command of work-precision (error against seconds)
    std::ostringstream ed;    // the plot command of error against dt
};

void sweep_lines(const Problem& p, const std::vector<const Sample*>& samples, SweepLines& out) {
    std::vector<std::pair<std::string, std::string>> series;  // name, gnuplot style
    for (std::size_t m = 0; m < sim::kIntegrators.size(); ++m) series.emplace_back(sim::kIntegrators[m].name, style(m));
    static const char* greys[] = {"#000000", "#555555", "#999999"};
    for (std::size_t m = 0; m < peers().size(); ++m) {
        series.emplace_back(peers()[m].name, "dt 2 lc rgb '" + std::string(greys[m % 3]) + "' pt " +
                                                 std::to_string(4 + 2 * static_cast<int>(m)));
    }
    std::size_t k = 0;
    for (const auto& [name, look] : series) {
        std::vector<const Sample*> line;  // the sweep and the frame substeps, by dt
        for (const Sample* s : samples) {
            if (s->problem == p.name && s->integrator == name && std::isfinite(s->error) && s->error > 0) {
                line.push_back(s);
            }
        }
        if (line.empty()) continue;
        out.data << "# " << name << "\n";
        std::sort(line.begin(), line.end(), [](const Sample* a, const Sample* b) { return a->dt > b->dt; });
        for (const Sample* s : line) {
            out.data << fmt("%.9g", s->dt) << ' ' << fmt("%.6e", s->error) << ' ' << fmt("%.6e", s->seconds) << ' '
                     << fmt("%.6e", s->evaluations) << '\n';
        }
        out.data << "\n\n";
        const std::string sep = k == 0 ? "plot " : ", \\\n     ";
        out.wp << sep << "'" << p.name << ".dat' index " << k << " using 3:2 with linespoints " << look << " title '"
               << name << "' noenhanced";
        out.ed << sep << "'" << p.name << ".dat' index " << k << " using 1:2 with linespoints " << look << " title '"
               << name << "' noenhanced";
        ++k;
    }
}

void plot_sweeps(const fs::path& dir, const Problem& p, const std::vector<const Sample*>& samples) {
    SweepLines lines;
    sweep_lines(p, samples, lines);
    write_file(dir / (p.name + ".dat"), lines.data.str());
    const std::string axes =
        "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
        "set key outside right top\n";
    gnuplot(dir, "work_precision_" + p.name,
            std::string(kTerminal) + "set output 'work_precision_" + p.name + ".png'\n" + axes +
                "set title \"Work-precision: " + p.title +
                "\" noenhanced\n"
                "set xlabel 'cost: wall time per simulated second (s)'\n"
                "set ylabel 'global error at the end (" +
                p.error_unit + ")'\n" + lines.wp.str() + "\n");
    // Reference slopes through the middle of the dt range.
    const double mid_dt = p.dt2 / 8.0;  // s
    gnuplot(dir, "error_vs_dt_" + p.name,
            std::string(kTerminal) + "set output 'error_vs_dt_" + p.name + ".png'\n" + axes +
                "set title \"Error against dt: " + p.title +
                "\" noenhanced\n"
                "set xlabel 'dt (s)'\nset ylabel 'global error at the end (" +
                p.error_unit + ")'\n" + lines.ed.str() + ", \\\n     1e-3*(x/" + fmt("%.6g", mid_dt) +
                ") dt 2 lc rgb '#999999' title 'slope 1', \\\n     1e-5*(x/" + fmt("%.6g", mid_dt) +
                ")**2 dt 3 lc rgb '#999999' title 'slope 2', \\\n     1e-9*(x/" + fmt("%.6g", mid_dt) +
                ")**4 dt 4 lc rgb '#999999' title 'slope 4'\n");
}

// --- energy, the stiff spring's limits -----------------------------------------------------

// Energy over time on the oscillator (the envelope of |E - E0| / E0).
void plot_energy(const fs::path& dir, const std::vector<Drift>& drifts) {
    std::ostringstream data, plot;
    std::size_t k = 0;
    for (const Drift& d : drifts) {
        if (d.problem != "oscillator") continue;
        data << "# " << d.integrator << "\n";
        for (const auto& [t, e] : d.envelope) data << fmt("%.6g", t) << ' ' << fmt("%.6e", e) << '\n';
        data << "\n\n";
        plot << (k == 0 ? "plot " : ", \\\n     ") << "'energy.dat' index " << k << " using 1:2 with lines " << style(k)
             << " lw 2 title '" << d.integrator << "' noenhanced";
        ++k;
    }
    write_file(dir / "energy.dat", data.str());
    gnuplot(dir, "energy",
            std::string(kTerminal) +
                "set output 'energy.png'\nset logscale y\nset format y '10^{%L}'\nset grid\n"
                "set key outside right top\nset yrange [1e-8:1e3]\n"
                "set title 'Energy error over time: harmonic oscillator, dt = 0.1 s (ω dt = 0.1)'\n"
                "set xlabel 'simulated time (s)'\nset ylabel 'largest |E - E_0| / E_0 so far'\n" +
                plot.str() + "\n");
}

// Stability limits on the stiff spring.
void plot_stiff_spring(const fs::path& dir, const std::vector<Stability>& limits) {
    std::ostringstream data;
    for (std::size_t k = 0; k < limits.size(); ++k) {
        data << k << " \"" << limits[k].integrator << "\" " << fmt("%.6e", std::max(limits[k].largest_dt, 1e-7))
             << '\n';
    }
    write_file(dir / "stability.dat", data.str());
    gnuplot(dir, "stability",
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

// --- the stability map ---------------------------------------------------------------------

// A cell's label: its largest stable dt, in ms or µs.
std::string dt_label(double dt) {
    if (dt <= 0.0) return std::string("<10 µs");
    if (dt >= kDtHi) return std::string("≥250 ms");
    return dt >= 1e-3 ? fmt("%.3g ms", 1e3 * dt) : fmt("%.3g µs", 1e6 * dt);
}

// The heat map's data: rows the cases (and the ragdoll), columns the methods (and ODE).
std::string stability_map_data(const StabilityMap& map) {
    const std::size_t methods = sim::kIntegrators.size(), cases = map.cases.size();
    std::ostringstream data;
    for (std::size_t y = 0; y < cases; ++y) {
        for (std::size_t x = 0; x < methods; ++x) {
            const MapCell& c = map.cells[y * methods + x];
            data << x << ' ' << y << ' ' << fmt("%.4f", std::log10(std::max(c.largest_dt, kDtLo / 2))) << " \""
                 << dt_label(c.largest_dt) << "\"\n";
        }
        data << methods << ' ' << y << " NaN \"\"\n\n";
    }
    for (std::size_t x = 0; x < methods; ++x) data << x << ' ' << cases << " NaN \"\"\n";
    data << methods << ' ' << cases << ' ' << fmt("%.4f", std::log10(map.ragdoll_dt)) << " \""
         << dt_label(map.ragdoll_dt) << "\"\n";
    return data.str();
}

void plot_stability_map(const fs::path& dir, const StabilityMap& map) {
    const std::size_t methods = sim::kIntegrators.size(), cases = map.cases.size();
    write_file(dir / "stability_map.dat", stability_map_data(map));
    std::ostringstream xt, yt;
    for (std::size_t x = 0; x < methods; ++x) xt << (x ? ", " : "") << "'" << sim::kIntegrators[x].name << "' " << x;
    xt << ", 'ODE quickstep' " << methods;
    for (std::size_t y = 0; y < cases; ++y) yt << (y ? ", " : "") << "'" << map.cases[y] << "' " << y;
    yt << ", 'ragdoll (ODE)' " << cases;
    gnuplot(dir, "stability_map",
            std::string(kTerminal) +
                "set output 'stability_map.png'\n"
                "set title 'Largest stable dt per method (white: 1/60 s; blue: a game frame is stable; the "
                "watchdog decides)'\n"
                "set xtics (" +
                xt.str() + ") rotate by -30 noenhanced\nset ytics (" + yt.str() +
                ") noenhanced\n"
                "set xrange [-0.5:" +
                std::to_string(methods) + ".5]\nset yrange [-0.5:" + std::to_string(cases) +
                ".5]\nset cbrange [-5:-0.6]\nset cblabel 'log_{10} dt (s)'\n"
                "set palette defined (0 '#b2182b', 0.5 '#f4a582', 0.73 '#f7f7f7', 0.85 '#92c5de', 1 '#2166ac')\n"
                "set view map\n"
                "plot 'stability_map.dat' using 1:2:3 with image notitle, '' using 1:2:4 with labels font ',10' "
                "notitle\n");
}

// --- every scene's cost, how cost grows ------------------------------------------------------

void plot_scene_costs(const fs::path& dir, const std::vector<SceneCost>& costs) {
    std::ostringstream data;
    for (std::size_t k = 0; k < costs.size(); ++k) {
        const double encode = std::isfinite(costs[k].encode) ? costs[k].encode : 0.0;
        data << k << " \"" << costs[k].scene << "\" " << fmt("%.5f", costs[k].physics) << ' '
             << fmt("%.5f", costs[k].physics + costs[k].render) << ' '
             << fmt("%.5f", costs[k].physics + costs[k].render + encode) << '\n';
    }
    write_file(dir / "scene_costs.dat", data.str());
    gnuplot(dir, "scene_costs",
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

void plot_growth(const fs::path& dir, const std::vector<GrowthSeries>& growth) {
    const GrowthFiles files = growth_files(growth);
    write_file(dir / "growth.dat", files.plot_data);
    gnuplot(dir, "growth", std::string(kTerminal) + files.plot_script);
}

// --- rigid bodies: error against cost per problem -------------------------------------------

// One line per solver and setting over its step sizes: ours in colour,
// Bullet's dashed and grey, as the work-precision plots draw odeint's.
void plot_rigid(const fs::path& dir, const std::string& problem, const std::vector<RigidSample>& rigid) {
    std::ostringstream data, plot;
    std::vector<std::string> labels;
    for (const RigidSample& s : rigid)
        if (s.problem == problem && std::find(labels.begin(), labels.end(), s.label()) == labels.end())
            labels.push_back(s.label());
    static const char* greys[] = {"#000000", "#777777"};
    std::size_t k = 0, colour = 0, grey = 0;
    double coarsest = 0.0, finest = 1.0;  // s
    for (const RigidSample& s : rigid) coarsest = std::max(coarsest, s.h), finest = std::min(finest, s.h);
    for (const std::string& label : labels) {
        std::ostringstream block;
        bool ours = true;
        for (const RigidSample& s : rigid) {
            if (s.problem != problem || s.label() != label) continue;
            ours = s.ours();
            if (s.failed || !std::isfinite(s.error) || s.error <= 0) continue;
            block << fmt("%.6e", s.us_per_frame) << ' ' << fmt("%.6e", s.error) << ' ' << std::lround(1.0 / s.h)
                  << '\n';
        }
        std::string look;
        if (ours) {
            look = style(colour++);
        } else {
            look = "dt 2 lc rgb '" + std::string(greys[grey % 2]) + "' pt " +
                   std::to_string(4 + 2 * static_cast<int>(grey));
            ++grey;
        }
        if (block.str().empty()) continue;  // every run failed: nothing to draw
        data << "# " << label << '\n' << block.str() << "\n\n";
        plot << (k == 0 ? "plot " : ", \\\n     ") << "'rigid_" << problem << ".dat' index " << k
             << " using 1:2 with linespoints " << look << " title '" << label << "' noenhanced";
        ++k;
    }
    write_file(dir / ("rigid_" + problem + ".dat"), data.str());
    if (k == 0) plot << "plot NaN notitle";
    gnuplot(dir, "rigid_" + problem,
            std::string("set terminal pngcairo size 1200,680 enhanced font 'DejaVu Sans,12' linewidth 1.5\n") +
                "set output 'rigid_" + problem +
                ".png'\nset logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
                "set key outside right top\n"
                "set title \"Rigid bodies: the " +
                problem + ", each line h = 1/" + std::to_string(std::lround(1.0 / coarsest)) + " s (left) to 1/" +
                std::to_string(std::lround(1.0 / finest)) +
                " s\" noenhanced\n"
                "set xlabel 'cost: µs of wall time per 1/60 s frame'\n"
                "set ylabel 'largest relative error'\n" +
                plot.str() + "\n");
}

}  // namespace

void draw_plots(const fs::path& dir, const Measurements& m) {
    const std::vector<const Sample*> samples = every_sample(m);
    for (const Problem& p : m.problems) plot_sweeps(dir, p, samples);
    plot_energy(dir, m.drifts);
    plot_stiff_spring(dir, m.limits);
    plot_stability_map(dir, m.map);
    plot_scene_costs(dir, m.costs);
    plot_growth(dir, m.growth);
    for (const std::string& problem : rigid_problems()) plot_rigid(dir, problem, m.rigid);
}

}  // namespace scenes::report
