// The report's tables: each CSV file and its part of report.json, made from
// the same rows side by side so that the two never disagree. Its own file:
// the machine-readable output, apart from the plots and the prose.
#include "scenes/report/report_stages.h"

#include "sim/error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace scenes::report {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A finite number, or JSON's null.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
// A finite number in `format`, or an empty CSV field.
std::string field(const char* format, double v) { return std::isfinite(v) ? fmt(format, v) : ""; }

// One table: its CSV text and its part of report.json.
struct Table {
    std::string csv;
    json rows = json::array();
};

// The sweeps, then the frame substeps: one row per run.
std::string work_precision_csv(const Measurements& m) {
    std::ostringstream csv;
    csv << "problem,integrator,dt,steps,error,error_unit,energy_error,force_evaluations_per_simulated_second,"
           "seconds_per_simulated_second,exploded\n";
    for (const std::vector<Sample>* from : {&m.sweeps, &m.frames}) {
        for (const Sample& s : *from) {
            const Problem& p = *std::find_if(m.problems.begin(), m.problems.end(),
                                             [&](const Problem& q) { return q.name == s.problem; });
            csv << s.problem << ',' << s.integrator << ',' << fmt("%.9g", s.dt) << ',' << s.steps << ','
                << fmt("%.6e", s.error) << ',' << p.error_unit << ',' << fmt("%.6e", s.energy_error) << ','
                << fmt("%.6g", s.evaluations) << ',' << fmt("%.6e", s.seconds) << ',' << s.exploded << '\n';
        }
    }
    return csv.str();
}

Table orders(const Findings& f) {
    Table t{.csv = "integrator,problem,fitted,expected,points\n"};
    for (const OrderFit& o : f.orders) {
        json row{{"integrator", o.integrator}, {"problem", o.problem}, {"points", o.fit.points}};
        row["fitted"] = number(o.fit.slope);
        row["expected"] = o.expected > 0 ? json(o.expected) : json(nullptr);
        t.rows.push_back(row);
        t.csv += o.integrator + ',' + o.problem + ',' + field("%.3f", o.fit.slope) + ',' +
                 (o.expected > 0 ? std::to_string(o.expected) : "") + ',' + std::to_string(o.fit.points) + '\n';
    }
    return t;
}

json pareto(const Findings& f) {
    json out = json::object();
    for (const auto& [problem, front] : f.fronts) {
        json points = json::array();
        for (const Sample& s : front) {
            points.push_back({{"integrator", s.integrator},
                              {"dt", s.dt},
                              {"error", s.error},
                              {"seconds_per_simulated_second", s.seconds},
                              {"force_evaluations_per_simulated_second", s.evaluations}});
        }
        out[problem] = points;
    }
    return out;
}

json drift(const Measurements& m) {
    json out = json::array();
    for (const Drift& d : m.drifts) {
        out.push_back({{"integrator", d.integrator},
                       {"problem", d.problem},
                       {"first_half", d.first_half},
                       {"second_half", d.second_half},
                       {"exploded", d.exploded},
                       {"bounded", d.bounded()}});
    }
    return out;
}

Table stiff_spring(const Measurements& m) {
    std::ostringstream csv;
    csv << "integrator,largest_stable_dt,always_stable,stable_at_1_60,exploded_frame,quantity\n";
    Table t;
    for (const Stability& s : m.limits) {
        csv << s.integrator << ',' << fmt("%.6g", s.largest_dt) << ',' << s.always_stable << ',' << s.stable_at_frame
            << ',' << s.exploded_frame << ',' << s.quantity << '\n';
        t.rows.push_back({{"integrator", s.integrator},
                          {"largest_stable_dt", s.largest_dt},
                          {"always_stable", s.always_stable},
                          {"stable_at_1_60", s.stable_at_frame},
                          {"exploded_frame", s.exploded_frame},
                          {"quantity", s.quantity}});
    }
    t.csv = csv.str();
    return t;
}

Table scene_costs(const Measurements& m) {
    std::ostringstream csv;
    csv << "scene,frames,physics_ms_per_frame,render_ms_per_frame,encode_ms_per_frame,total_ms_per_frame,"
           "physics_share,verdict\n";
    Table t;
    for (const SceneCost& c : m.costs) {
        json systems = json::object();
        for (const auto& [system, ms] : c.systems) systems[system] = ms;
        t.rows.push_back({{"scene", c.scene},
                          {"frames", c.frames},
                          {"physics_ms_per_frame", c.physics},
                          {"systems_ms_per_frame", systems},
                          {"render_ms_per_frame", c.render},
                          {"encode_ms_per_frame", number(c.encode)},
                          {"verdict", budget_verdict(c)}});
        const double encode = std::isfinite(c.encode) ? c.encode : 0.0;
        csv << c.scene << ',' << c.frames << ',' << fmt("%.4f", c.physics) << ',' << fmt("%.3f", c.render) << ','
            << field("%.3f", c.encode) << ',' << fmt("%.3f", c.physics + c.render + encode) << ','
            << fmt("%.4f", c.physics / kFrameMs) << ',' << budget_verdict(c) << '\n';
    }
    t.csv = csv.str();
    return t;
}

json peer_row(const PeerRow& r) {
    json row{{"peer", r.peer},
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
    return row;
}

Table peers_table(const Findings& f) {
    std::ostringstream csv;
    csv << "peer,problem,compared_with,fitted,ratio_ours_over_theirs,ratio_batch,batch_copies,"
           "ours_ns_per_copy_step,theirs_ns_per_copy_step\n";
    Table t;
    for (const PeerRow& r : f.peers) {
        t.rows.push_back(peer_row(r));
        csv << r.peer << ',' << r.problem << ',' << r.ours << ',' << field("%.3f", r.fit.slope) << ','
            << field("%.3f", r.ratio) << ',' << field("%.3f", r.ratio_batch) << ','
            << (r.batch ? std::to_string(r.batch->copies) : "") << ','
            << (r.batch ? fmt("%.3f", 1e9 * r.batch->ours_seconds) : "") << ','
            << (r.batch ? fmt("%.3f", 1e9 * r.batch->theirs_seconds) : "") << '\n';
    }
    t.csv = csv.str();
    return t;
}

Table stability_map(const StabilityMap& map) {
    std::ostringstream csv;
    csv << "case,integrator,largest_stable_dt,largest_stable_stiffness_at_1_60\n";
    json cells = json::array();
    for (const MapCell& c : map.cells) {
        cells.push_back({{"case", c.hard_case},
                         {"integrator", c.integrator},
                         {"largest_stable_dt", c.largest_dt},
                         {"largest_stable_stiffness_at_1_60", c.largest_stiffness}});
        csv << c.hard_case << ',' << c.integrator << ',' << fmt("%.6g", c.largest_dt) << ','
            << fmt("%.6g", c.largest_stiffness) << '\n';
    }
    csv << "ragdoll,ode_quickstep," << fmt("%.6g", map.ragdoll_dt) << ",\n";
    return {.csv = csv.str(),
            .rows = {{"dt_search", {kDtLo, kDtHi}},
                     {"stiffness_search", {kKLo, kKHi}},
                     {"cells", cells},
                     {"ragdoll_ode_largest_dt", map.ragdoll_dt}}};
}

json small_steps(const Measurements& m) {
    json out = json::array();
    for (const SmallSteps& r : m.small_steps) {
        out.push_back(
            {{"body", r.body}, {"way", r.way}, {"n", r.n}, {"strain", r.strain}, {"ms_per_frame", r.ms_per_frame}});
    }
    return out;
}

// The rigid problems: every run, the fitted orders, the picks for a frame budget.
Table rigid(const Settings& settings, const Measurements& m, const Findings& f) {
    std::ostringstream csv;
    csv << "problem,solver,setting,h,substeps,error,period_error,energy_error,precession_error,tilt_error_deg,"
           "us_per_frame,failed\n";
    json samples = json::array();
    for (const RigidSample& s : m.rigid) {
        csv << s.problem << ',' << s.solver << ',' << s.setting << ',' << fmt("%.9g", s.h) << ','
            << std::lround(1.0 / 60.0 / s.h) << ',' << field("%.6e", s.error) << ',' << field("%.6e", s.period_error)
            << ',' << field("%.6e", s.energy_error) << ',' << field("%.6e", s.precession_error) << ','
            << field("%.6g", s.tilt_error) << ',' << field("%.6g", s.us_per_frame) << ',' << s.failed << '\n';
        samples.push_back({{"problem", s.problem},
                           {"solver", s.solver},
                           {"setting", s.setting},
                           {"h", s.h},
                           {"error", number(s.error)},
                           {"period_error", number(s.period_error)},
                           {"energy_error", number(s.energy_error)},
                           {"precession_error", number(s.precession_error)},
                           {"tilt_error_deg", number(s.tilt_error)},
                           {"us_per_frame", number(s.us_per_frame)},
                           {"failed", s.failed}});
    }
    json orders = json::array();
    for (const RigidOrder& o : f.rigid_orders) {
        orders.push_back({{"problem", o.problem},
                          {"solver", o.solver},
                          {"setting", o.setting},
                          {"fitted", number(o.fit.slope)},
                          {"points", o.fit.points}});
    }
    auto point = [](const std::optional<RigidSample>& s) {
        return s ? json{{"solver", s->solver},
                        {"setting", s->setting},
                        {"h", s->h},
                        {"error", s->error},
                        {"us_per_frame", s->us_per_frame}}
                 : json(nullptr);
    };
    json picks = json::array();
    for (const RigidPick& p : f.rigid_picks) {
        picks.push_back({{"problem", p.problem},
                         {"budget_us_per_frame", p.budget},
                         {"best", point(p.best)},
                         {"ours", point(p.ours)}});
    }
    return {.csv = csv.str(),
            .rows = {{"cost_unit", "µs of wall time per 1/60 s frame"},
                     {"seconds_simulated", settings.rigid.seconds},
                     {"substeps", settings.rigid.substeps},
                     {"samples", samples},
                     {"orders", orders},
                     {"picks", picks}}};
}

json problem_list(const Measurements& m) {
    json out = json::array();
    for (const Problem& p : m.problems)
        out.push_back({{"name", p.name}, {"title", p.title}, {"error_unit", p.error_unit}, {"end", p.end}});
    return out;
}

}  // namespace

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    f.close();  // the last bytes are written here: a full disk shows here
    if (!f) throw sim::InputError("report: cannot write " + path.string());
}

void write_tables(const fs::path& dir, const Settings& settings, const Measurements& m, const Findings& f) {
    const Table orders_table = orders(f), limits = stiff_spring(m), costs = scene_costs(m), peer_table = peers_table(f),
                map = stability_map(m.map), rigid_table = rigid(settings, m, f);
    const GrowthFiles growth = growth_files(m.growth);
    write_file(dir / "orders.csv", orders_table.csv);
    write_file(dir / "work_precision.csv", work_precision_csv(m));
    write_file(dir / "stability.csv", limits.csv);
    write_file(dir / "scene_costs.csv", costs.csv);
    write_file(dir / "peers.csv", peer_table.csv);
    write_file(dir / "growth.csv", growth.csv);
    write_file(dir / "stability_map.csv", map.csv);
    write_file(dir / "rigid.csv", rigid_table.csv);

    json j;
    j["quick"] = settings.quick;
    j["dt_values_per_method"] = settings.dt_count;
    j["repetitions"] = settings.timing.repetitions;
    j["problems"] = problem_list(m);
    j["orders"] = orders_table.rows;
    j["pareto"] = pareto(f);
    j["drift"] = drift(m);
    j["stability"] = {{"problem", "stiff spring, k = 1e6 N/m, m = 1 kg"}, {"limits", limits.rows}};
    j["scenes"] = {{"frame_ms", kFrameMs},
                   {"physics_low_ms", kPhysicsLow},
                   {"physics_high_ms", kPhysicsHigh},
                   {"costs", costs.rows}};
    j["peers"] = peer_table.rows;
    j["growth"] = growth.json;
    j["stability_map"] = map.rows;
    j["small_steps"] = small_steps(m);
    j["rigid"] = rigid_table.rows;
    write_file(dir / "report.json", j.dump(2) + "\n");
}

}  // namespace scenes::report
