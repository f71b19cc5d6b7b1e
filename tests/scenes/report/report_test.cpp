// `plausible report --quick` (label report): the whole report written by the
// code the command runs, then read back from report.json. It asserts what
// theory says and the report must show: every fitted order within 0.15 of
// the method's order, symplectic methods' energy error bounded over long runs
// (and forward Euler's not), the stiff spring flagged unstable at 1/60 s
// for the explicit methods and stable for backward Euler, odeint's peers
// measured (and, on a batch of 1000 copies of each problem, our cost per copy
// at equal error nearer theirs than on one particle), every shipped scene costed, and cost
// growing with size as the algorithms say: linear for local and spatially
// hashed systems, quadratic for all-pairs gravity; and the rigid bodies'
// section, every problem under every solver, ours and Bullet's, with the
// defaults' pendulum converging to its closed form as h shrinks.
#include "scenes/report/report.h"
#include "sim/error.h"
#include "sim/problems.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// One run of the quick report (the whole of it, about 30 s here), then what it says.
TEST(Report, QuickRunShowsTheOrdersTheDriftAndTheStabilityLimits) {
    const fs::path dir = fs::temp_directory_path() / ("plausible-report-test-" + std::to_string(getpid()));
    fs::remove_all(dir);
    // --out an existing empty folder, given with a trailing slash as a shell's
    // completion writes it: the report fills it.
    fs::create_directories(dir / "report");
    const auto start = std::chrono::steady_clock::now();
    scenes::write_report({.quick = true, .out = (dir / "report").string() + "/"});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ measured ] report --quick took %.1f s\n", seconds);
    std::ifstream f(dir / "report" / "report.json");
    const nlohmann::json json = nlohmann::json::parse(f);

    // The files.
    for (const char* name : {"report.md", "report.json", "work_precision.csv", "orders.csv", "stability.csv",
                             "work_precision_oscillator.png", "error_vs_dt_kepler_e0.9.png", "energy.png",
                             "stability.png", "growth.csv", "growth.png"}) {
        const fs::path p = dir / "report" / name;
        ASSERT_TRUE(fs::exists(p)) << p;
        EXPECT_GT(fs::file_size(p), 100u) << p;
    }
    std::ifstream png(dir / "report" / "energy.png", std::ios::binary);
    char magic[4] = {};
    png.read(magic, 4);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG");
    EXPECT_TRUE(json["quick"].get<bool>());
    EXPECT_GE(json["dt_values_per_method"].get<int>(), 6);

    // Fitted orders within 0.15 of theory.
    int compared = 0;
    std::set<std::string> problems;
    for (const auto& o : json["orders"]) {
        if (o["expected"].is_null()) continue;
        const std::string who = o["integrator"].get<std::string>() + " on " + o["problem"].get<std::string>();
        ASSERT_FALSE(o["fitted"].is_null()) << who << ": no fit (fewer than 3 errors in the fit band)";
        EXPECT_NEAR(o["fitted"].get<double>(), o["expected"].get<int>(), 0.15) << who << ": fitted order";
        problems.insert(o["problem"].get<std::string>());
        ++compared;
    }
    EXPECT_GE(compared, 30) << "orders compared with theory";
    for (const char* p : {"ballistic", "oscillator", "damped", "kepler_e0.5", "kepler_e0.9"}) {
        EXPECT_EQ(problems.count(p), 1u) << p;
    }

    // Symplectic methods do not drift in energy; forward Euler does.
    std::map<std::string, bool> bounded;  // integrator -> bounded on every problem
    for (const auto& d : json["drift"]) {
        const std::string name = d["integrator"].get<std::string>();
        bounded[name] = (bounded.count(name) != 0 ? bounded[name] : true) && d["bounded"].get<bool>();
        if (name != "forward_euler" && name != "backward_euler" && name != "rk4") {
            EXPECT_LE(d["second_half"].get<double>(), 1.2 * d["first_half"].get<double>() + 1e-13)
                << name << " on " << d["problem"].get<std::string>() << ": |E - E0| / E0 grows";
        }
    }
    for (const char* s : {"symplectic_euler", "leapfrog", "velocity_verlet", "position_verlet"}) {
        EXPECT_TRUE(bounded[s]) << s;
    }
    EXPECT_FALSE(bounded["forward_euler"]) << "forward Euler gains energy: the report must say it drifts";

    // The stiff spring (ω h = 16.7 at 1/60 s): explicit methods flagged unstable, limits as theory says.
    const double omega = std::sqrt(sim::problems::kStiffK / 1.0);  // rad/s, on 1 kg
    for (const auto& s : json["stability"]["limits"]) {
        const std::string name = s["integrator"].get<std::string>();
        const double dt = s["largest_stable_dt"].get<double>();  // s
        if (name == "backward_euler") {
            EXPECT_TRUE(s["stable_at_1_60"].get<bool>());
            EXPECT_TRUE(s["always_stable"].get<bool>());
        } else {
            EXPECT_FALSE(s["stable_at_1_60"].get<bool>()) << name << " at ω h = 16.7";
            EXPECT_GT(s["exploded_frame"].get<int>(), 0) << name;
        }
        if (name == "symplectic_euler" || name == "leapfrog" || name == "velocity_verlet" ||
            name == "position_verlet") {
            EXPECT_NEAR(dt, 2.0 / omega, 2e-4) << name << ": s, theory 2/ω";
        }
        if (name == "rk4") {
            EXPECT_NEAR(dt, 2.785 / omega, 2.5e-4) << "s, theory 2.785/ω";
        }
    }
    // Peers: odeint's steppers measured on the same problems, their orders as theory says.
    int peers = 0;
    for (const auto& r : json["peers"]) {
        const std::string who = r["peer"].get<std::string>() + " on " + r["problem"].get<std::string>();
        if (r["problem"] == "oscillator" || r["problem"] == "kepler_e0.5") {
            ASSERT_FALSE(r["fitted"].is_null()) << who;
            const double expected = r["peer"] == "odeint_velocity_verlet" ? 2.0 : 4.0;
            EXPECT_NEAR(r["fitted"].get<double>(), expected, 0.15) << who << ": fitted order";
            EXPECT_FALSE(r["cost_ratio"].is_null()) << who << ": no overlap of errors to compare costs at";
            ++peers;
        }
    }
    EXPECT_EQ(peers, 6) << "three odeint steppers on two problems";

    // The batch: 1000 independent copies of each problem, one World against one
    // odeint state, the same method on both sides. The World's fixed cost is
    // spread over 1000 particles, so our cost per copy over odeint's is below
    // the one-particle ratio. (Issue 17's target, at most 1.2x on the batch, is
    // at its edge with velocity Verlet on the oscillator, 1.20-1.22x: the
    // figures are in the report and the issue, not asserted here: a timing.)
    // Not compared on the damped oscillator with velocity Verlet: odeint's is
    // first order there; at equal error (a full run) ours is far cheaper, and
    // a quick run's ratio is only an upper bound at equal dt.
    int batches = 0;
    for (const auto& r : json["peers"]) {
        if (r["peer"] != "odeint_runge_kutta4" && r["peer"] != "odeint_velocity_verlet") continue;
        const std::string problem = r["problem"].get<std::string>();
        const std::string who =
            r["compared_with"].get<std::string>() + " against " + r["peer"].get<std::string>() + " on " + problem;
        ASSERT_TRUE(r.contains("batch")) << who;
        const auto& b = r["batch"];
        EXPECT_EQ(b["copies"].get<int>(), 1000) << who;
        ++batches;
        if (problem == "damped" && r["peer"] == "odeint_velocity_verlet") continue;
        ASSERT_FALSE(r["ratio_batch"].is_null()) << who << ": no batch ratio";
        const std::string basis = r["ratio_batch_basis"].get<std::string>();
        if (problem == "ballistic") {
            EXPECT_EQ(basis, "equal dt, both exact") << who;
        } else {
            EXPECT_EQ(basis, "equal error") << who;
            ASSERT_FALSE(r["cost_ratio"].is_null()) << who << ": no one-particle ratio at equal error";
            EXPECT_TRUE(std::isfinite(r["cost_ratio"].get<double>())) << who << ": one-particle ratio";
            // Each copy is the problem: both sides' largest error over the copies agree (the same method).
            const double ours = b["ours_error"].get<double>(), theirs = b["theirs_error"].get<double>();
            EXPECT_NEAR(ours / theirs, 1.0, 0.01)
                << who << ": batch errors, m (" << ours << " against " << theirs << "), ratio within 1% of 1";
        }
        const double batch = r["ratio_batch"].get<double>();
        EXPECT_TRUE(std::isfinite(batch) && batch > 0.0) << who << ": batch ratio " << batch;
        if (problem != "ballistic") {
            EXPECT_LT(batch, r["cost_ratio"].get<double>())
                << who << ": our seconds per copy-step at equal error over odeint's, the batch of 1000 ("
                << 1e9 * b["ours_seconds_per_copy_step"].get<double>() << " ns against "
                << 1e9 * b["theirs_seconds_per_copy_step"].get<double>()
                << " ns per copy and step) against one particle: the fixed cost is spread over the batch";
        }
    }
    EXPECT_EQ(batches, 10) << "odeint's runge_kutta4 and velocity_verlet on the batch of each of the five problems";

    // Every shipped scene costed, none exploded.
    const auto& costs = json["scenes"]["costs"];
    EXPECT_GE(costs.size(), 20u);
    for (const auto& c : costs) {
        EXPECT_NE(c["verdict"], "exploded") << c["scene"];
        EXPECT_GT(c["physics_ms_per_frame"].get<double>(), 0.0) << c["scene"];
        EXPECT_GT(c["render_ms_per_frame"].get<double>(), 0.0) << c["scene"];
    }

    // How cost grows: the fitted exponent p of cost ∝ size^p within 0.35 of the
    // algorithm's (1: local or hashed, 2: all pairs). The timings are best of 3
    // on a shared machine; across runs here the exponents stayed within 0.1.
    std::map<std::string, double> expected_growth = {{"free particles", 1.0},
                                                     {"mass-spring cloth", 1.0},
                                                     {"XPBD cloth", 1.0},
                                                     {"fountains (particle collisions)", 1.0},
                                                     {"N-body (Newton gravity)", 2.0},
                                                     {"ragdolls (ODE)", 1.0}};
    for (const auto& g : json["growth"]) {
        const std::string system = g["system"].get<std::string>();
        ASSERT_EQ(expected_growth.count(system), 1u) << system << ": not a system the test knows";
        EXPECT_EQ(g["expected"].get<double>(), expected_growth[system]) << system;
        const auto& sizes = g["sizes"];
        ASSERT_GE(sizes.size(), 4u) << system;
        EXPECT_GE(sizes.back().get<double>() / sizes.front().get<double>(), 8.0) << system << ": sizes span";
        EXPECT_NEAR(g["exponent"].get<double>(), expected_growth[system], 0.35)
            << system << ": fitted exponent of cost per step against size, expected " << expected_growth[system]
            << " ± 0.35";
        expected_growth.erase(system);
    }
    EXPECT_TRUE(expected_growth.empty()) << expected_growth.size() << " system(s) missing from growth";

    // Rigid bodies: every problem under every solver in rigid.csv, the section
    // and its plots, and the closed forms approached as h shrinks.
    const std::vector<std::string> rigid_problems = {"pendulum", "top", "chain"};
    const std::vector<std::string> rigid_solvers = {"plausible", "ode_quickstep", "ode_exact", "bullet_multibody",
                                                    "bullet_sequential_impulse"};
    std::set<std::string> rigid_seen;  // "problem solver"
    std::ifstream rigid_csv(dir / "report" / "rigid.csv");
    std::string line;
    std::getline(rigid_csv, line);
    EXPECT_EQ(line.rfind("problem,solver,setting,h,", 0), 0u) << "rigid.csv's header: " << line;
    while (std::getline(rigid_csv, line)) {
        const std::size_t a = line.find(','), b = line.find(',', a + 1);
        rigid_seen.insert(line.substr(0, a) + " " + line.substr(a + 1, b - a - 1));
    }
    for (const std::string& p : rigid_problems) {
        EXPECT_GT(fs::file_size(dir / "report" / ("rigid_" + p + ".png")), 100u) << p;
        for (const std::string& s : rigid_solvers) EXPECT_EQ(rigid_seen.count(p + " " + s), 1u) << p << " " << s;
    }
    std::ifstream md_file(dir / "report" / "report.md");
    const std::string md((std::istreambuf_iterator<char>(md_file)), std::istreambuf_iterator<char>());
    EXPECT_NE(md.find("\n## Rigid bodies\n"), std::string::npos);
    EXPECT_NE(md.find("](rigid_chain.png)"), std::string::npos);
    EXPECT_NE(md.find("**What to pick.**"), std::string::npos);
    // A series coarsest h first: its relative errors, for the one field.
    auto rigid_series = [&](const std::string& problem, const std::string& label, const char* field) {
        std::vector<double> out;
        for (const auto& r : json["rigid"]["samples"]) {
            if (r["problem"] != problem ||
                r["solver"].get<std::string>() + " " + r["setting"].get<std::string>() != label)
                continue;
            EXPECT_FALSE(r["failed"].get<bool>()) << problem << ", " << label << ", h = " << r["h"];
            EXPECT_GT(r["us_per_frame"].get<double>(), 0.0) << problem << ", " << label;
            out.push_back(r[field].is_null() ? std::nan("") : r[field].get<double>());
        }
        return out;
    };
    // Through RigidWorld, the defaults' pendulum keeps its period and energy
    // better at each smaller h, and within 0.5% at 1/960 s (the accuracy
    // test's target over 10 s; a quick run's span is shorter).
    const std::vector<double> pendulum = rigid_series("pendulum", "plausible defaults", "error");
    ASSERT_GE(pendulum.size(), 3u);
    for (std::size_t k = 1; k < pendulum.size(); ++k) {
        EXPECT_LT(pendulum[k], pendulum[k - 1]) << "the defaults' pendulum error (relative) shrinks with h, step " << k;
    }
    EXPECT_LT(pendulum.back(), 5e-3) << "relative: period and energy against the closed forms at the finest h";
    // Bullet's Featherstone top keeps its 30° tilt (the study's §2: it holds
    // where maximal coordinates do not): a check that the peer is set up right.
    const std::vector<double> tilt = rigid_series("top", "bullet_multibody Featherstone", "tilt_error_deg");
    ASSERT_FALSE(tilt.empty());
    EXPECT_LT(tilt.back(), 1.0) << "deg, Bullet's multibody top's tilt off 30° at the finest h";
    EXPECT_FALSE(json["rigid"]["orders"].empty());
    EXPECT_EQ(json["rigid"]["picks"].size(), 3u * 3u) << "three problems, three frame budgets";
    fs::remove_all(dir);
}

TEST(ReportOut, RefusesADirectoryHoldingSomethingElse) {
    const fs::path dir = fs::temp_directory_path() / ("plausible-report-out-" + std::to_string(getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "thesis.tex") << "mine";
    EXPECT_THROW(scenes::write_report({.quick = true, .out = dir}), sim::InputError);
    EXPECT_TRUE(fs::exists(dir / "thesis.tex")) << "left alone";
    fs::remove_all(dir);
}

}  // namespace
