// report.md: one section per question the report answers, each a table and
// a one-line conclusion drawn from the numbers (orders, work-precision and
// the Pareto fronts, a game's frame, which method for which budget, odeint,
// energy, stability, the XPBD claim, every scene's cost, how cost grows).
// Its own file: the prose, apart from the tables and plots it refers to.
#include "scenes/report/report_rigid.h"
#include "scenes/report/report_stages.h"

#include "sim/integrators.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace scenes::report {
namespace {

using sim::IntegratorInfo;
const auto& kMethods = sim::kIntegrators;

void introduction(std::ostream& md, const Settings& settings) {
    md << "# Speed against error\n\n"
       << (settings.quick ? "Quick run (`report --quick`): 6 dt values per method; each timing the median of "
                            "runs adding up to 5 ms.\n\n"
                          : "Full run: 8 dt values per method; each timing the median of at least 5 runs adding "
                            "up to 20 ms.\n\n")
       << "Every integrator on problems with exact answers. Error is the distance from the closed form at the "
          "end time (the pendulum: its period's error); cost is measured wall time per simulated second on this "
          "machine, and force evaluations (machine-independent) in `work_precision.csv`.\n\n";
}

// --- orders, work-precision, budgets ---------------------------------------------------------

void orders(std::ostream& md, const Measurements& m, const Findings& f) {
    md << "## Orders of convergence\n\n| problem |";
    for (const IntegratorInfo& info : kMethods) md << ' ' << info.name << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < kMethods.size(); ++k) md << "---|";
    md << '\n';
    int matched = 0, compared = 0;
    for (const Problem& p : m.problems) {
        md << "| " << p.name << " |";
        for (const IntegratorInfo& info : kMethods) {
            const std::string method(info.name);  // named: GCC 16 takes a temporary argument for a dangling reference
            const OrderFit& o = order_of(f, p.name, method);
            if (p.smooth && o.expected == 0) {
                md << " exact |";
            } else if (!std::isfinite(o.fit.slope)) {
                md << " n/a |";
            } else {
                md << ' ' << fmt("%.2f", o.fit.slope);
                if (o.expected > 0) {
                    md << " (" << o.expected << ")";
                    ++compared;
                    if (std::abs(o.fit.slope - o.expected) <= 0.15) ++matched;
                }
                md << " |";
            }
        }
        md << '\n';
    }
    md << "\nFitted slope of log error on log dt (theory in brackets). **" << matched << " of " << compared
       << " fitted orders are within 0.15 of theory**. Leapfrog (kick-drift-kick) is first order on the damped "
          "oscillator: its second kick evaluates the drag at the half-step velocity (velocity Verlet predicts the "
          "full-step velocity and stays second order). On the pendulum the XPBD rod's projection, which loses "
          "energy "
          "in proportion to dt, makes every method first order in the period, with the same error for all.\n\n";
}

void pareto_front(std::ostream& md, const Problem& p, const std::vector<Sample>& front) {
    md << "Pareto front (cheapest first; each point is more accurate than every cheaper one):\n\n"
       << "| integrator | dt (s) | error (" << p.error_unit
       << ") | time per simulated s | force evaluations per simulated s |\n|---|---|---|---|---|\n";
    for (const Sample& s : front) {
        md << "| " << s.integrator << " | " << fmt("%.3g", s.dt) << " | " << fmt("%.2e", s.error) << " | "
           << fmt("%.2e", s.seconds) << " s | " << fmt("%.3g", s.evaluations) << " |\n";
    }
    std::map<std::string, int> wins;
    for (const Sample& s : front) ++wins[s.integrator];
    std::string winner;
    int most = 0;
    for (const auto& [name, n] : wins)
        if (n > most) most = n, winner = name;
    md << "\n" << winner << " holds the most points of the front (" << most << " of " << front.size() << ").\n\n";
}

void work_precision(std::ostream& md, const Measurements& m, const Findings& f) {
    md << "## Work-precision\n\n";
    for (const Problem& p : m.problems) {
        md << "### " << p.title << "\n\n![work-precision](work_precision_" << p.name << ".png)\n\n"
           << "![error against dt](error_vs_dt_" << p.name << ".png)\n\n";
        pareto_front(md, p, f.fronts.at(p.name));
    }
}

// The frame substeps' errors, one table per problem.
void frame_substeps(std::ostream& md, const Measurements& m) {
    md << "## A game's frame: 1/60 s in substeps\n\n"
       << "Error at the end time with dt = 1/60 s split into n substeps (explosions by the watchdog marked), and "
          "the force evaluations per frame that costs (a method's evaluations per step times n):\n\n";
    for (const Problem& p : m.problems) {
        md << "**" << p.title << "** (error in " << p.error_unit << ")\n\n| integrator |";
        for (const int n : kFrameSubsteps) md << " n = " << n << " |";
        md << " evaluations per frame at n = 1 |\n|---|";
        for (std::size_t k = 0; k <= kFrameSubsteps.size(); ++k) md << "---|";
        md << '\n';
        for (const IntegratorInfo& info : kMethods) {
            md << "| " << info.name << " |";
            double per_frame = 0.0;
            for (const Sample& s : m.frames) {
                if (s.problem != p.name || s.integrator != info.name) continue;
                md << ' ' << (s.exploded ? std::string("exploded") : fmt("%.1e", s.error)) << " |";
                if (std::abs(s.dt - 1.0 / 60.0) < 1e-12) per_frame = s.evaluations / 60.0;
            }
            md << ' ' << fmt("%.0f", per_frame) << " |\n";
        }
        md << '\n';
    }
}

// The fewest force evaluations a frame for an error of 1e-3.
void frame_cheapest(std::ostream& md, const Measurements& m) {
    md << "For an error of 1e-3 (m, or s for the pendulum) at 1/60 s frames, the fewest force evaluations a "
          "frame:\n\n";
    for (const Problem& p : m.problems) {
        const Sample* best = nullptr;
        for (const Sample& s : m.frames) {
            if (s.problem == p.name && !s.exploded && std::isfinite(s.error) && s.error <= 1e-3 &&
                (best == nullptr || s.evaluations < best->evaluations ||
                 (s.evaluations == best->evaluations && s.error < best->error))) {  // ties: the more accurate
                best = &s;
            }
        }
        md << "- " << p.name << ": "
           << (best ? best->integrator + " with " + std::to_string(std::lround(1.0 / 60.0 / best->dt)) +
                          " substep(s), " + fmt("%.0f", best->evaluations / 60.0) + " evaluations a frame"
                    : std::string("none of the measured substeps reaches it"))
           << '\n';
    }
    md << '\n';
}

void budgets(std::ostream& md, const Measurements& m, const Findings& f) {
    md << "## Which method for which budget\n\n"
       << "The cheapest measured point whose error is within the budget, per problem (error in the problem's "
          "unit):\n\n"
       << "| problem | 1e-2 | 1e-4 | 1e-6 |\n|---|---|---|---|\n";
    for (const Problem& p : m.problems) {
        md << "| " << p.name << " |";
        for (const double budget : {1e-2, 1e-4, 1e-6}) {
            const Sample* best = nullptr;
            for (const Sample& s : f.fronts.at(p.name))
                if (s.error <= budget && (best == nullptr || s.seconds < best->seconds)) best = &s;
            md << ' ' << (best ? best->integrator + " at dt " + fmt("%.2g", best->dt) : std::string("none measured"))
               << " |";
        }
        md << '\n';
    }
    md << "\nOver every point measured (the sweeps and the frame substeps), by wall time on this machine. On "
          "these smooth problems RK4's four evaluations a step buy steps large enough to win almost every "
          "budget; the Verlet methods come next, one evaluation a step and bounded energy; the Euler methods "
          "never pay off.\n\n";
}

// --- peers -------------------------------------------------------------------------------------

void peer_table(std::ostream& md, const Findings& f) {
    md << "## Peers: boost::odeint\n\n"
       << "odeint's steppers on the same problems and dt sweeps (dashed in the plots). The ratio is our cost at "
          "the same error over theirs (wall time, median over their points; below 1: ours is cheaper), each "
          "point of ours timed again beside theirs at the same dt, in blocks of runs taken in turn (a few "
          "milliseconds of ours, then of theirs, each side's median), so that both see the same load.\n\n"
       << "| peer | compared with | problem | fitted order | our cost / theirs, one particle | batch of 1000 | "
          "ns per copy-step, ours / theirs |\n|---|---|---|---|---|---|---|\n";
    for (const PeerRow& r : f.peers) {
        md << "| " << r.peer << " | " << r.ours << " | " << r.problem << " | "
           << (std::isfinite(r.fit.slope) ? fmt("%.2f", r.fit.slope) : std::string("exact")) << " | "
           << (std::isfinite(r.ratio) ? fmt("%.2f", r.ratio) : std::string("n/a")) << " | ";
        if (!r.batch) {
            md << "- | - |\n";
            continue;
        }
        md << (std::isfinite(r.ratio_batch) ? fmt("%.2f", r.ratio_batch) : std::string("n/a"))
           << (r.batch_basis == "equal error" || r.batch_basis.empty() ? "" : " (" + r.batch_basis + ")") << " | "
           << fmt("%.2f", 1e9 * r.batch->ours_seconds) << " / " << fmt("%.2f", 1e9 * r.batch->theirs_seconds) << " |\n";
    }
}

const char* kFixedCost =
    "\nThe fixed cost: each of our steps goes through the whole World (`World::step` checks its settings "
    "and runs its stages in turn, the force generators are dispatched over the particle arrays, a "
    "pinned anchor or centre being a second particle (RK4 leaves an anchor at rest out of its "
    "arithmetic, not of the step), the integrator makes its passes, the watchdog "
    "checks the result), an overhead the same whatever the number of particles; on one particle it is "
    "most of the step, against odeint's one inlined 3-vector, and it is mostly what the one-particle "
    "ratio measures. On a shared machine that ratio moves from run to run by up to 1.6x on the "
    "oscillators (our step is some 270 to 600 instructions of straight-line code, odeint's a short loop; "
    "where the CPU shares its core with another busy hardware thread, ours runs up to 1.7x slower and "
    "odeint's hardly at all; docs/fixed-cost-study.md): read it as a range. The batch spreads it over "
    "1000 independent copies of each problem (one World of 1000 particles against one odeint state of "
    "6000 doubles; the Kepler copies each fall towards a "
    "fixed attractor, CentralGravity, so that they do not attract each other), so what it shows is the "
    "integrators' and the forces' own cost per particle (both sides built at the same width: AVX2 where "
    "the CPU has it, as our World runs; both sides' arrays start on a cache line). Its ratio is at equal "
    "error: our time per step per copy over odeint's, times our steps over theirs for the same error, "
    "from the single copy's sweeps (1.00 for the same method; both sides' errors on the batch are in report.json's "
    "`batch`).";

// The batch rows at equal dt because the single copy's sweeps do not reach
// a common error (a quick run's few dt values), where ours is the more
// accurate: a sentence each (the table marks them too).
std::string upper_bound_notes(const Findings& f) {
    std::string notes;
    for (const PeerRow& r : f.peers) {
        if (!std::isfinite(r.ratio_batch) || r.batch_basis != "equal dt, an upper bound") continue;
        notes += " Against " + r.peer + " on " + r.problem +
                 " the sweeps' errors do not overlap: the batch ratio is at equal dt, where ours is the more "
                 "accurate, an upper bound of the ratio at equal error.";
    }
    return notes;
}

// The medians per peer, and the batch rows above the target.
void peer_summary(std::ostream& md, const Findings& f) {
    std::map<std::string, std::vector<double>> by, by_batch;
    std::vector<std::string> over;  // batch rows above the target
    bool springs_over = false;
    for (const PeerRow& r : f.peers) {
        if (std::isfinite(r.ratio)) by[r.peer].push_back(r.ratio);
        if (!std::isfinite(r.ratio_batch)) continue;
        by_batch[r.peer].push_back(r.ratio_batch);
        if (r.ratio_batch > kBatchTarget && r.batch_basis != "equal dt, an upper bound") {
            over.push_back(r.ours + " on " + r.problem + " (" + fmt("%.2f", r.ratio_batch) + "x)");
            springs_over = springs_over || r.problem == "oscillator" || r.problem == "damped";
        }
    }
    md << kFixedCost
       << " odeint's velocity_verlet is first order on the damped oscillator (its force sees the old velocity), "
          "ours second (it predicts the new one), so at equal error ours needs far fewer steps there."
       << upper_bound_notes(f) << '\n';
    for (auto& [peer, v] : by) {
        md << "- Against " << peer << ": our cost at equal error is " << fmt("%.2f", median(v))
           << "x theirs on one particle";
        if (by_batch.count(peer) != 0) {
            md << ", " << fmt("%.2f", median(by_batch[peer])) << "x on the batch";
        }
        md << " (median over problems).\n";
    }
    if (!over.empty()) {
        md << "\nAbove " << fmt("%.1f", kBatchTarget) << "x odeint on the batch (the target): ";
        for (std::size_t k = 0; k < over.size(); ++k) md << (k == 0 ? "" : ", ") << over[k];
        md << ". There the cost is in our force and integrator passes, not in the World's overhead (the "
              "last column: nanoseconds per copy and step).";
        if (springs_over) {
            md << " Our oscillators are beads on springs to one pinned anchor: one pass computes each spring's "
                  "force and its bead's acceleration (the anchor's own sum is left out) where odeint computes -x, "
                  "and it also reads each spring's stiffness and each bead's inverse mass.";
        }
        md << '\n';
    }
    md << '\n';
}

// --- energy and stability ----------------------------------------------------------------------

void energy(std::ostream& md, const Measurements& m) {
    md << "## Energy over long runs\n\n![energy](energy.png)\n\n"
       << "| integrator | problem | max error, first half | max error, second half | verdict "
          "|\n|---|---|---|---|---|\n";
    for (const Drift& d : m.drifts) {
        md << "| " << d.integrator << " | " << d.problem << " | " << fmt("%.2e", d.first_half) << " | "
           << fmt("%.2e", d.second_half) << " | "
           << (d.exploded    ? "exploded"
               : d.bounded() ? "bounded"
                             : "drifts")
           << " |\n";
    }
    md << "\nSymplectic methods keep the energy error bounded (it oscillates and does not grow); forward Euler "
          "gains energy, backward Euler and RK4 lose it, steadily.\n\n";
}

void stiff_spring(std::ostream& md, const Measurements& m) {
    md << "## Stability on a stiff spring\n\n![stability](stability.png)\n\n"
       << "| integrator | largest stable dt | at 1/60 s |\n|---|---|---|\n";
    for (const Stability& s : m.limits) {
        md << "| " << s.integrator << " | "
           << (s.always_stable    ? ">= " + fmt("%.3g", s.largest_dt) + " s (always)"
               : s.largest_dt > 0 ? fmt("%.3g", s.largest_dt) + " s"
                                  : std::string("none (unstable at 1 µs)"))
           << " | "
           << (s.stable_at_frame ? std::string("stable")
                                 : "**unstable**: " + s.quantity + " at frame " + std::to_string(s.exploded_frame))
           << " |\n";
    }
    md << "\nThe watchdog decides: exploded once the mass moves 100 times faster than its own swing within 2 s. "
          "The symplectic and Verlet methods are stable up to 2/ω = 2 ms, RK4 to 2.83/ω; forward Euler's "
          "amplitude grows at every dt (here: within 2 s unless dt is a few µs); backward Euler is stable at "
          "every dt. At a game's 1/60 s only backward Euler survives (or constraints instead of the spring: "
          "`rope-stiff`).\n";
}

void stability_map(std::ostream& md, const StabilityMap& map) {
    md << "\n## Stability map\n\n![stability map](stability_map.png)\n\n"
       << "The largest stable dt of each method on each hard case at its own stiffness, and the largest stable "
          "stiffness at a game's 1/60 s, by bisection (the watchdog decides: speed, bounds, NaN). The ragdoll "
          "steps "
          "with ODE's own integrator (quickstep, 40 iterations), whatever the scene's.\n\n"
       << "| case | integrator | largest stable dt | largest stable stiffness at 1/60 s |\n|---|---|---|---|\n";
    for (const MapCell& c : map.cells) {
        md << "| " << c.hard_case << " | " << c.integrator << " | "
           << (c.largest_dt >= kDtHi ? ">= " + fmt("%.3g", kDtHi) + " s"
               : c.largest_dt > 0    ? fmt("%.3g", c.largest_dt) + " s"
                                     : "< " + fmt("%.0e", kDtLo) + " s")
           << " | "
           << (c.largest_stiffness >= kKHi ? ">= " + fmt("%.0e", kKHi) + " N/m"
               : c.largest_stiffness > 0   ? fmt("%.3g", c.largest_stiffness) + " N/m"
                                           : "< " + fmt("%.0f", kKLo) + " N/m")
           << " |\n";
    }
    md << "| ragdoll | ODE quickstep | " << fmt("%.3g", map.ragdoll_dt) << " s | (joints, not springs) |\n\n"
       << "The explicit methods' limits follow ω h < 2 (symplectic, Verlet) and 2.8 (RK4) of the case's "
          "stiffest mode; the 1000:1 chain's light links set that mode, not the heavy ball. Backward Euler's "
          "limit is the search's end: implicit, it trades accuracy (damping) for stability.\n\n";
}

void small_steps(std::ostream& md, const std::vector<SmallSteps>& claim) {
    md << "## XPBD: small steps or more iterations?\n\n"
       << "Inextensible links without tethers, 2 s hanging at 1/60 s frames: n substeps of one iteration "
          "against one step of n iterations. Strain is the worst link's stretch at the end.\n\n"
       << "| body | n | strain, n substeps | strain, n iterations | ms per frame, substeps | ms per frame, "
          "iterations |\n"
          "|---|---|---|---|---|---|\n";
    int substeps_win = 0, pairs = 0;
    for (std::size_t i = 0; i + 1 < claim.size(); i += 2) {
        const SmallSteps &a = claim[i], &b = claim[i + 1];
        md << "| " << a.body << " | " << a.n << " | " << fmt("%.2e", a.strain) << " | " << fmt("%.2e", b.strain)
           << " | " << fmt("%.3f", a.ms_per_frame) << " | " << fmt("%.3f", b.ms_per_frame) << " |\n";
        if (a.n > 1) {
            ++pairs;
            if (a.strain < b.strain) ++substeps_win;
        }
    }
    md << "\nWhat we find: n substeps give the lower strain in " << substeps_win << " of " << pairs
       << " comparisons at equal n ("
       << (substeps_win * 2 > pairs ? "the claim holds here" : "the claim does not hold here")
       << "); a substep costs a whole integration and collision pass, an iteration only a constraint sweep, so "
          "compare the times too.\n";
}

// --- every scene's cost --------------------------------------------------------------------------

void scene_costs(std::ostream& md, const std::vector<SceneCost>& costs) {
    md << "\n## Every scene against the frame budget\n\n![scene costs](scene_costs.png)\n\n"
       << "Per 30 FPS frame (33 ms): physics is every frame step that 1/30 s of simulated time takes (a scene "
          "at 1/60 s runs two), timed around the whole step; render is one 1280x720 frame with 4x MSAA on OSMesa "
          "(median over the scene's first 30 frames); encode is ffmpeg's libx264 (preset medium, yuv420p) on "
          "those frames, its start-up taken out (`--quick` measures neither the clip nor the encoder). The "
          "lecture's budget for physics is 5% to 30% of the frame, 1.67 to 10 ms.\n\n"
       << "| scene | physics (ms) | by system (ms) | render (ms) | encode (ms) | physics share | verdict "
          "|\n|---|---|---|---|---|---|---|\n";
    int over = 0;
    for (const SceneCost& c : costs) {
        std::string by;
        for (const auto& [system, ms] : c.systems) by += (by.empty() ? "" : ", ") + system + " " + fmt("%.3g", ms);
        md << "| " << c.scene << " | " << fmt("%.3g", c.physics) << " | " << by << " | " << fmt("%.3g", c.render)
           << " | " << (std::isfinite(c.encode) ? fmt("%.3g", c.encode) : std::string("-")) << " | "
           << fmt("%.1f", 100.0 * c.physics / kFrameMs) << "% | " << budget_verdict(c) << " |\n";
        if (c.physics > kPhysicsHigh || c.exploded) ++over;
    }
    double fastest = std::numeric_limits<double>::infinity(), slowest = 0.0;
    for (const SceneCost& c : costs) fastest = std::min(fastest, c.render), slowest = std::max(slowest, c.render);
    md << "\n"
       << (over == 0 ? std::string("No scene is over the 30% physics budget")
                     : std::to_string(over) + " scene(s) over the 30% physics budget (flagged **over**)")
       << ". Rendering 1280x720 with 4x MSAA in software (OSMesa) takes " << fmt("%.0f", fastest) << " to "
       << fmt("%.0f", slowest) << " ms a frame: there, not in the physics, is where a 33 ms frame goes.\n";
}

// --- rigid bodies ----------------------------------------------------------------------------

std::string percent(double e) { return (100.0 * e >= 100.0 ? fmt("%.0f", 100.0 * e) : fmt("%.2g", 100.0 * e)) + "%"; }

// A step as the tables name it: "1/240 s".
std::string step_name(double h) { return "1/" + std::to_string(std::lround(1.0 / h)) + " s"; }

std::string rigid_title(const std::string& problem, double seconds) {
    if (problem == "pendulum") {
        return "Hinged rod released at 90°: period against 4 √(I / m g d) K(sin 45°) = " +
               fmt("%.6f", RigidPendulum::period()) + " s, energy change over " + fmt("%g", seconds) +
               " s over the swing's m g d";
    }
    if (problem == "top") {
        return "Heavy symmetric top in steady precession (tilt 30°, spin 50 rad/s): precession rate over 2 s "
               "against Ω = " +
               fmt("%.6f", RigidTop::precession()) + " rad/s, tilt after " + fmt("%g", seconds) + " s";
    }
    return "Chain of 8 hinged links released horizontal: energy change over " + fmt("%g", seconds) + " s over the " +
           fmt("%.2f", RigidChain::released()) + " J its fall releases";
}

// A run's errors in words: "T 0.04%, E 1.6%", "Ω 1.2%, tilt 74°", "E 4.9%".
std::string rigid_errors(const RigidSample& s) {
    if (s.failed || !std::isfinite(s.error)) return "failed";
    if (s.problem == "pendulum") return "T " + percent(s.period_error) + ", E " + percent(s.energy_error);
    if (s.problem == "top") return "Ω " + percent(s.precession_error) + ", tilt " + fmt("%.3g", s.tilt_error) + "°";
    return "E " + percent(s.energy_error);
}

std::string rigid_point(const RigidSample& s) {
    return s.label() + " at " + step_name(s.h) + " (error " + percent(s.error) + ", " + fmt("%.3g", s.us_per_frame) +
           " µs)";
}

// The samples of one problem and series, coarsest h first.
std::vector<const RigidSample*> rigid_series(const Measurements& m, const std::string& problem,
                                             const std::string& label) {
    std::vector<const RigidSample*> out;
    for (const RigidSample& s : m.rigid)
        if (s.problem == problem && s.label() == label) out.push_back(&s);
    return out;
}

// The median over problems and steps of b's error and cost over a's, where both ran.
struct RigidRatio {
    double error = kNaN, cost = kNaN;
    double error_lo = kNaN, error_hi = kNaN;  // the smallest and largest error ratio
};
RigidRatio rigid_ratio(const Measurements& m, const std::string& a, const std::string& b) {
    std::vector<double> errors, costs;
    for (const std::string& problem : rigid_problems()) {
        const auto sa = rigid_series(m, problem, a), sb = rigid_series(m, problem, b);
        for (std::size_t i = 0; i < std::min(sa.size(), sb.size()); ++i) {
            if (sa[i]->failed || sb[i]->failed || !(sa[i]->error > 0) || !(sb[i]->error > 0)) continue;
            errors.push_back(sb[i]->error / sa[i]->error);
            costs.push_back(sb[i]->us_per_frame / sa[i]->us_per_frame);
        }
    }
    RigidRatio r;
    if (errors.empty()) return r;
    r.error = median(errors), r.cost = median(costs);
    r.error_lo = *std::min_element(errors.begin(), errors.end());
    r.error_hi = *std::max_element(errors.begin(), errors.end());
    return r;
}

// A ratio as the prose gives it: "2.3", "960".
std::string times(double ratio) {
    return ratio < 1.0 ? fmt("%.2f", ratio) : ratio < 10.0 ? fmt("%.1f", ratio) : fmt("%.0f", ratio);
}

// "3.2x smaller", "1.5x larger", or "about the same" within 10%.
std::string factor(double ratio) {
    if (!std::isfinite(ratio)) return "n/a";
    if (ratio >= 1.0 / 1.1 && ratio <= 1.1) return "about the same";
    return ratio < 1.0 ? times(1.0 / ratio) + "x smaller" : times(ratio) + "x larger";
}

void rigid_problem_table(std::ostream& md, const Settings& settings, const Measurements& m, const Findings& f,
                         const std::string& problem) {
    md << "### " << rigid_title(problem, settings.rigid.seconds) << "\n\n![" << problem << "](rigid_" << problem
       << ".png)\n\n| solver | setting |";
    for (const int n : settings.rigid.substeps) md << " h = " << step_name(1.0 / 60.0 / n) << " |";
    md << " fitted order |\n|---|---|";
    for (std::size_t k = 0; k <= settings.rigid.substeps.size(); ++k) md << "---|";
    md << '\n';
    for (const RigidOrder& o : f.rigid_orders) {
        if (o.problem != problem) continue;
        md << "| " << o.solver << " | " << o.setting << " |";
        for (const RigidSample* s : rigid_series(m, problem, o.solver + " " + o.setting)) {
            md << ' ' << rigid_errors(*s);
            if (!s->failed) md << " · " << fmt("%.3g", s->us_per_frame) << " µs";
            md << " |";
        }
        md << ' ' << (std::isfinite(o.fit.slope) ? fmt("%.2f", o.fit.slope) : std::string("n/a")) << " |\n";
    }
    md << '\n';
}

// Which setting for a frame budget, in words, from the picks and the ratios.
void rigid_advice(std::ostream& md, const Measurements& m, const Findings& f) {
    md << "### Which setting for a frame budget\n\n| problem | budget (µs per frame) | most accurate measured | "
          "most accurate through RigidWorld |\n|---|---|---|---|\n";
    std::map<std::string, int> ours_wins;
    int pairs = 0;
    for (const RigidPick& p : f.rigid_picks) {
        md << "| " << p.problem << " | " << fmt("%g", p.budget) << " | "
           << (p.best ? rigid_point(*p.best) : std::string("nothing that cheap")) << " | "
           << (p.ours ? rigid_point(*p.ours) : std::string("nothing that cheap")) << " |\n";
        if (p.ours) ++ours_wins[p.ours->label()], ++pairs;
    }
    md << "\n**What to pick.** ";
    std::string favourite;
    int most = 0;
    for (const auto& [label, n] : ours_wins)
        if (n > most) most = n, favourite = label;
    if (!favourite.empty()) {
        md << "Through RigidWorld, " << favourite << " is the most accurate within the budget in " << most << " of "
           << pairs << " problem-budget pairs: pick it, and spend the budget on substeps";
    }
    // The favourite's error and cost per halving of h, the median over the problems' series.
    std::vector<double> error_step, cost_step;
    for (const std::string& problem : rigid_problems()) {
        const auto s = rigid_series(m, problem, favourite);
        for (std::size_t i = 0; i + 1 < s.size(); ++i) {
            if (s[i]->failed || s[i + 1]->failed || !(s[i]->error > 0) || !(s[i + 1]->error > 0)) continue;
            const double halvings = std::log2(s[i]->h / s[i + 1]->h);
            error_step.push_back(std::pow(s[i]->error / s[i + 1]->error, 1.0 / halvings));
            cost_step.push_back(std::pow(s[i + 1]->us_per_frame / s[i]->us_per_frame, 1.0 / halvings));
        }
    }
    if (!error_step.empty()) {
        md << ": each halving of h divides its error by " << times(median(error_step)) << " and multiplies its cost by "
           << times(median(cost_step)) << " (medians over the problems)";
    }
    md << ".";
    // The cheapest point of ours under 1% per problem.
    md << " For 1% error through RigidWorld:";
    for (std::size_t k = 0; k < rigid_problems().size(); ++k) {
        const std::string& problem = rigid_problems()[k];
        const RigidSample* cheapest = nullptr;
        for (const RigidSample& s : m.rigid) {
            if (s.problem == problem && s.ours() && !s.failed && s.error <= 0.01 &&
                (!cheapest || s.us_per_frame < cheapest->us_per_frame)) {
                cheapest = &s;
            }
        }
        md << (k == 0 ? " " : "; ") << "the " << problem << ", "
           << (cheapest ? cheapest->label() + " at " + step_name(cheapest->h) + ", " +
                              fmt("%.3g", cheapest->us_per_frame) + " µs a frame"
                        : std::string("no step measured reaches it"));
        if (!cheapest || cheapest->label() == favourite) continue;
        for (const RigidSample* s : rigid_series(m, problem, favourite)) {
            if (!s->failed && s->error <= 0.01) {
                md << " (" << favourite << ": " << step_name(s->h) << ", " << fmt("%.3g", s->us_per_frame) << " µs)";
                break;
            }
        }
    }
    md << ".\n\n";
    const RigidRatio ode = rigid_ratio(m, "ode_quickstep 20 iterations", "plausible defaults");
    const RigidRatio iterations = rigid_ratio(m, "ode_quickstep 10 iterations", "ode_quickstep 50 iterations");
    const RigidRatio exact = rigid_ratio(m, "ode_quickstep 20 iterations", "ode_exact dWorldStep");
    md << "Against ODE as it comes (quickstep, 20 iterations) at the same h, the defaults' error is "
       << factor(ode.error) << " (median over problems and steps; from " << factor(ode.error_lo) << " to "
       << factor(ode.error_hi) << ") at " << times(ode.cost) << "x the cost. Quickstep's iterations, 50 against "
       << "10, leave the error " << factor(iterations.error) << " (median) at " << times(iterations.cost)
       << "x the cost, and ODE's exact solver leaves it " << factor(exact.error) << " at " << times(exact.cost)
       << "x quickstep's cost: on one body or one chain the iterative solver is not what limits the error";
    // Where a peer is markedly more accurate within the largest budget.
    std::vector<std::string> better;
    for (const RigidPick& p : f.rigid_picks) {
        if (p.budget != kRigidBudgets.back() || !p.best || p.best->ours() || !p.ours) continue;
        if (p.best->error < 0.5 * p.ours->error) {
            better.push_back("the " + p.problem + " (" + p.best->label() + ", " + percent(p.best->error) + " against " +
                             percent(p.ours->error) + ")");
        }
    }
    if (!better.empty()) {
        md << " Within " << fmt("%g", kRigidBudgets.back()) << " µs a frame Bullet is markedly more accurate on ";
        for (std::size_t k = 0; k < better.size(); ++k) md << (k == 0 ? "" : " and ") << better[k];
    }
    md << ".\n\n";
}

void rigid_bodies(std::ostream& md, const Settings& settings, const Measurements& m, const Findings& f) {
    md << "\n## Rigid bodies\n\n"
       << "Three problems with closed forms (`tests/sim/rigid_accuracy_test.cpp`, "
          "`docs/studies/rigid-closed-forms.md`), each run through `sim::RigidWorld` under Plausible's defaults "
          "(sleep off; a tree hung from the world and touching nothing steps in reduced coordinates), with that "
          "turned off (`articulated off`: ODE's maximal coordinates under Plausible's joint settings) and under ODE "
          "as it comes (its own joint ERP 0.2 and CFM 1e-10, its implicit gyroscopic "
          "term, no position pass: quickstep at 10, 20 and 50 iterations, and the exact dWorldStep), and through "
          "Bullet's Featherstone `btMultiBody` and its `btSequentialImpulseConstraintSolver` (single precision, "
          "no sleeping, the multibody undamped and its joint rates clamped at 1e4 rad/s as ours are, one "
          "stepSimulation(h, 0) a step), at a 1/60 s frame in ";
    for (std::size_t k = 0; k < settings.rigid.substeps.size(); ++k)
        md << (k == 0 ? "" : ", ") << settings.rigid.substeps[k];
    md << " substeps, " << fmt("%g", settings.rigid.seconds) << " s simulated a run. Cost is wall time per 1/60 s "
       << "frame, µs, timed around the steps alone"
       << (settings.rigid.repetitions > 1 ? " (median of " + std::to_string(settings.rigid.repetitions) + " runs)"
                                          : std::string(" (one run)"))
       << "; the error in the plots and the fitted orders is the largest of a problem's relative errors (the "
          "top's tilt over its 30°). A fitted order needs three errors between 1e-11 and 5e-2 (n/a: fewer). "
          "Every run is in `rigid.csv`.\n\n";
    for (const std::string& problem : rigid_problems()) rigid_problem_table(md, settings, m, f, problem);
    rigid_advice(md, m, f);
}

}  // namespace

void write_markdown(const std::filesystem::path& dir, const Settings& settings, const Measurements& m,
                    const Findings& f) {
    std::ostringstream md;
    introduction(md, settings);
    orders(md, m, f);
    work_precision(md, m, f);
    frame_substeps(md, m);
    frame_cheapest(md, m);
    budgets(md, m, f);
    peer_table(md, f);
    peer_summary(md, f);
    energy(md, m);
    stiff_spring(md, m);
    stability_map(md, m.map);
    small_steps(md, m.small_steps);
    scene_costs(md, m.costs);
    md << growth_files(m.growth).markdown;
    rigid_bodies(md, settings, m, f);
    write_file(dir / "report.md", md.str());
}

}  // namespace scenes::report
