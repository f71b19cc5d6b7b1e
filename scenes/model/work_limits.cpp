// Work that grows faster than the scene file: refused at load, with the
// estimate. Every other cost of a scene is linear in what the file lists
// (particles, links, bodies) times frames and substeps, and the readers'
// limits bound each of those. Some keys multiply instead:
//  - Newton gravity pairs every particle with every other: one key on a
//    group of a million particles asks for 5e11 pair evaluations a pass,
//    more than an hour a frame. Backward Euler makes it worse: its Jacobian
//    is dense, so each substep factors a dense 3n x 3n system.
//  - [view] trail_frames keeps that many positions of every moving
//    particle: 1e5 frames behind 1e6 particles is a terabyte.
//  - Backward Euler factors the springs' sparse system every substep, which
//    grows faster than the springs (a cloth of n nodes: about n^1.5 flops).
//  - [step] substeps, [constraints] and [rigid] iterations multiply all the
//    rest: a million particles at 10,000 substeps is a minute a frame.
// (The links of a body, memory rather than time, are refused as the body is
// built: particle_body.cpp.)
// The estimates come from counts and fixed costs per unit, so the verdict
// is the same on every machine; the costs are this machine's, to say what
// the counts mean in seconds and bytes.
#include "scenes/model/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace scenes::loader {
namespace {

// One pair of sim::NewtonGravity's force or potential pass, s: 12 frames of
// a group of 4000 (8.0e6 pairs, a force pass and an energy pass a frame)
// take 1.6 s more than 2 frames, on the development machine shared with
// other work (issue 19 measured 6 ns on an idle one).
constexpr double kPairSeconds = 10e-9;
// One flop of backward Euler's sparse LDLᵀ on Newton gravity's dense
// system, with its assembly, s: a step of 400 particles (a 1200 x 1200
// system, (3n)³/3 = 5.8e8 flops) takes 2.25 s, 200 particles 0.42 s.
constexpr double kDenseFlopSeconds = 4e-9;
// The most a frame may cost. A scene of 600 frames then runs at most ten
// minutes; beyond it a run takes hours and looks hung.
constexpr double kMaxSecondsPerFrame = 1.0;

// What Newton gravity costs a frame with n particles.
struct Cost {
    double pairs = 0.0;   // pairs a pass, n (n - 1) / 2
    double passes = 0.0;  // pair passes a frame
    double flops = 0.0;   // backward Euler's dense factorization a substep, (3n)³ / 3
    double seconds = 0.0;
};

// The pair passes a frame: the integrator's force evaluations in each
// substep, one potential pass for the energy each frame (run, check and the
// HUD report it), and one more each substep when the watchdog's energy rule
// is on (it measures the energy after every substep).
Cost newton_cost(const SceneDef& scene, double n) {
    const sim::IntegratorInfo& info = sim::integrator_info(scene.step.integrator);
    const double substeps = scene.step.substeps;
    Cost c;
    c.pairs = 0.5 * n * (n - 1.0);
    c.passes = substeps * info.force_evaluations + 1.0 + (scene.watchdog.energy_growth > 0.0 ? substeps : 0.0);
    if (info.needs_jacobians) c.flops = std::pow(3.0 * n, 3.0) / 3.0;
    c.seconds = c.pairs * c.passes * kPairSeconds + substeps * c.flops * kDenseFlopSeconds;
    return c;
}

// The most particles whose frame costs at most kMaxSecondsPerFrame (the
// cost grows with n: bisection over whole numbers).
double most_particles(const SceneDef& scene) {
    double lo = 1.0, hi = static_cast<double>(kMaxParticles);
    while (hi - lo > 1.0) {
        const double mid = std::floor(0.5 * (lo + hi));
        (newton_cost(scene, mid).seconds <= kMaxSecondsPerFrame ? lo : hi) = mid;
    }
    return lo;
}

// One point of a particle's trail, bytes: SceneRun keeps the last
// trail_frames + 1 positions of each moving particle as three floats, in a
// std::deque whose 512-byte nodes hold 42 of them.
constexpr double kTrailPointBytes = 512.0 / 42.0;
// At most this many trail points by the last frame, about 610 MB: a trail
// of 120 frames behind 400,000 particles. More runs a machine out of memory
// before the run ends.
constexpr double kMaxTrailPoints = 5e7;

void refuse_newton_gravity(const SceneBuilder& b, const Section& top) {
    const SceneDef& scene = b.scene;
    if (b.find_force<sim::NewtonGravity>() == nullptr) return;
    const Cost c = newton_cost(scene, static_cast<double>(scene.model.particles.size()));
    if (c.seconds <= kMaxSecondsPerFrame) return;
    const sim::IntegratorInfo& info = sim::integrator_info(scene.step.integrator);
    const std::string passes = std::to_string(info.force_evaluations) + " a step x " +
                               std::to_string(scene.step.substeps) +
                               (scene.step.substeps == 1 ? " substep" : " substeps") + ", 1 for the energy" +
                               (scene.watchdog.energy_growth > 0.0 ? ", 1 a substep for the watchdog's energy" : "");
    const std::string side = std::to_string(3 * scene.model.particles.size());  // the dense system's rows
    const std::string dense = c.flops == 0.0 ? ""
                                             : ", and " + std::string(info.name) + " factors a dense " + side + " x " +
                                                   side + " system each substep (" + sim::format_value(c.flops) +
                                                   " flops at " + sim::format_value(kDenseFlopSeconds * 1e9) + " ns)";
    const toml::table* forces = top.subtable("forces");
    b.r.fail(forces != nullptr ? forces->get("newton_gravity") : nullptr,
             "forces.newton_gravity on " + std::to_string(scene.model.particles.size()) +
                 " particles is O(n²): n (n - 1) / 2 = " + sim::format_value(c.pairs) + " pairs, evaluated " +
                 sim::format_value(c.passes) + " times a frame (" + std::string(info.name) + ": " + passes + ") at " +
                 sim::format_value(kPairSeconds * 1e9) + " ns a pair" + dense + ": about " +
                 sim::format_value(std::round(c.seconds)) + " s a frame; at most " +
                 sim::format_value(kMaxSecondsPerFrame) +
                 " s a frame, so that no run hangs for hours (Newton gravity is meant for a few bodies): these "
                 "settings allow at most " +
                 sim::format_value(most_particles(scene)) + " particles");
}

// Backward Euler's sparse solve on springs, measured on cloths of 20² to 60²
// nodes with shear and bend (a step of 400 nodes, 9.1e6 flops by the
// symbolic count, takes 72 ms; of 3600 nodes, 4.6e8 flops, 600 ms): a cost
// per particle (the assembly and the fallback paths) and one per flop of the
// factorization, s. The two together stay above every measured step.
constexpr double kSolveParticleSeconds = 150e-6;
constexpr double kSparseFlopSeconds = 1e-9;

// Backward Euler factors the springs' sparse system every substep; its cost
// grows faster than the springs do (a cloth of n nodes: about n^1.5 flops; a
// soft body: about n²).
void refuse_sparse_solve(const SceneBuilder& b, const Section& top) {
    const SceneDef& scene = b.scene;
    const sim::IntegratorInfo& info = sim::integrator_info(scene.step.integrator);
    if (!info.needs_jacobians) return;
    std::vector<std::array<std::uint32_t, 2>> links;
    for (const sim::ForceDef& f : scene.model.forces) {
        if (const auto* springs = std::get_if<sim::Springs>(&f)) {
            for (const sim::Spring& spring : springs->list) links.push_back({spring.i, spring.j});
        }
    }
    if (links.empty()) return;
    const double n = static_cast<double>(scene.model.particles.size());
    const double flops = sim::backward_euler_factor_flops(scene.model.particles.size(), links);
    const double seconds = scene.step.substeps * (n * kSolveParticleSeconds + flops * kSparseFlopSeconds);
    if (seconds <= kMaxSecondsPerFrame) return;
    const toml::table* step = top.subtable("step");
    b.r.fail(
        step != nullptr ? step->get("integrator") : nullptr,
        "step.integrator = \"" + std::string(info.name) + "\" factors the springs' sparse system every substep: " +
            std::to_string(links.size()) + " springs on " + std::to_string(scene.model.particles.size()) +
            " particles make a factorization of " + sim::format_value(flops) + " flops (Eigen's symbolic count), x " +
            std::to_string(scene.step.substeps) + (scene.step.substeps == 1 ? " substep" : " substeps") + " at " +
            sim::format_value(kSparseFlopSeconds * 1e9) + " ns a flop and " +
            sim::format_value(kSolveParticleSeconds * 1e6) + " µs a particle: about " +
            sim::format_value(std::round(seconds)) + " s a frame; at most " + sim::format_value(kMaxSecondsPerFrame) +
            " s a frame, so that no run hangs for hours: an explicit integrator with substeps, link = "
            "\"constraints\", or fewer nodes");
}

// What the rest of a substep costs, per unit, s, measured with `run --json`
// (ms_per_step) on this machine: 10⁵ free particles 0.37 ms; a 300² cloth's
// 537,000 springs 5.7 ms, or as constraints with its tethers at 4 iterations
// 74 ms; 10⁵ colliding particles 8.3 ms; a chain of 1000 links on quickstep's
// 20 iterations 15 ms. Rounded up. Linear in what the scene holds, but
// multiplied by the substeps and the solvers' iterations, which the file sets
// with one number each: a million particles at 10,000 substeps is about a
// minute a frame.
constexpr double kParticleSeconds = 5e-9;     // a particle's force evaluation and update
constexpr double kSpringSeconds = 12e-9;      // a spring's force evaluation
constexpr double kConstraintSeconds = 30e-9;  // a distance constraint or tether, one iteration
constexpr double kCollisionSeconds = 100e-9;  // a particle in the pair grid, with its candidates
constexpr double kBodySeconds = 5e-6;         // a rigid body in ODE's step, with its contacts
constexpr double kJointRowSeconds = 500e-9;   // a joint in one of quickstep's iterations

// ODE's exact step (quickstep = false) solves each island of jointed bodies
// as one dense LCP, about rows³: a chain of 100 ball-jointed links (300 rows)
// took 15 ms a step, of 400 links 426 ms, of 2000 more than a minute for 3
// frames. s per row³, the larger of the two.
constexpr double kLcpRowCubedSeconds = 6e-10;

// The constraint rows of a joint: a ball holds 3; the others 5 or 6, with a limit's.
double joint_rows(sim::JointType type) { return type == sim::JointType::ball ? 3.0 : 6.0; }

// A resting box's contacts: four points of three rows (the normal, two of friction).
constexpr double kContactRows = 12.0;

// Σ rows³ over the islands the joints make (bodies joined directly or
// through others), and one island of the bodies no joint holds, kContactRows
// each: touching, they join through their contacts (wrecking-ball's twelve
// bricks at 400 substeps: 1.43 ms a substep measured, 1.9 estimated).
double lcp_rows_cubed(const sim::RigidModel& rigid) {
    std::vector<int> parent(rigid.bodies.size());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = static_cast<int>(k);
    auto root = [&](int k) {
        while (parent[static_cast<std::size_t>(k)] != k) {
            auto& up = parent[static_cast<std::size_t>(k)];
            up = parent[static_cast<std::size_t>(up)];  // path halving: long chains stay near-linear
            k = up;
        }
        return k;
    };
    for (const sim::RigidJoint& j : rigid.joints) {
        if (j.b >= 0) parent[static_cast<std::size_t>(root(j.a))] = root(j.b);
    }
    std::vector<double> rows(rigid.bodies.size(), 0.0);
    std::vector<bool> jointed(rigid.bodies.size(), false);
    for (const sim::RigidJoint& j : rigid.joints) {
        rows[static_cast<std::size_t>(root(j.a))] += joint_rows(j.joint.type);
        jointed[static_cast<std::size_t>(j.a)] = true;
        if (j.b >= 0) jointed[static_cast<std::size_t>(j.b)] = true;
    }
    const double free_rows = kContactRows * static_cast<double>(std::count(jointed.begin(), jointed.end(), false));
    double sum = free_rows * free_rows * free_rows;
    for (const double r : rows) sum += r * r * r;
    return sum;
}

// The linear work of a frame, s, and what it is made of (for the message).
struct FrameWork {
    double seconds = 0.0;
    std::string parts;
};

FrameWork frame_work(const SceneDef& scene) {
    const sim::ParticleModel& m = scene.model;
    const double evals = sim::integrator_info(scene.step.integrator).force_evaluations;
    double springs = 0.0;
    for (const sim::ForceDef& f : m.forces) {
        if (const auto* s = std::get_if<sim::Springs>(&f)) springs += static_cast<double>(s->list.size());
    }
    const double n = static_cast<double>(m.particles.size());
    const double constraints = static_cast<double>(m.constraints.distance.size() + m.constraints.tethers.size());
    const double bodies = static_cast<double>(m.rigid.bodies.size());
    const double joints = static_cast<double>(m.rigid.joints.size());
    const double sweeps = m.rigid.settings.quickstep ? m.rigid.settings.iterations : 1.0;
    FrameWork w;
    auto add = [&](double count, double per, double seconds, const std::string& what) {
        if (count == 0.0) return;
        w.seconds += count * per * seconds;
        w.parts += (w.parts.empty() ? "" : ", ") + std::to_string(static_cast<long long>(count)) + " " + what;
    };
    add(n, evals, kParticleSeconds, "particles");
    add(springs, evals, kSpringSeconds, "springs");
    add(constraints, m.constraints.iterations, kConstraintSeconds,
        "constraints x " + std::to_string(m.constraints.iterations) + " iterations");
    add(m.collisions.particle_particle ? n : 0.0, 1.0, kCollisionSeconds, "colliding particles");
    add(bodies, 1.0, kBodySeconds, "rigid bodies");
    add(joints, sweeps, kJointRowSeconds, "joints x " + sim::format_value(sweeps) + " iterations");
    if (!m.rigid.settings.quickstep)
        add(lcp_rows_cubed(m.rigid), 1.0, kLcpRowCubedSeconds, "rows³ of ODE's exact step");
    w.seconds *= scene.step.substeps;
    return w;
}

void refuse_slow_frames(const SceneBuilder& b, const Section& top) {
    const SceneDef& scene = b.scene;
    const FrameWork w = frame_work(scene);
    if (w.seconds <= kMaxSecondsPerFrame) return;
    const toml::table* step = top.subtable("step");
    const toml::node* substeps = step != nullptr ? step->get("substeps") : nullptr;
    b.r.fail(substeps, "a frame of " + std::to_string(scene.step.substeps) +
                           (scene.step.substeps == 1 ? " substep" : " substeps") + " over " + w.parts +
                           " would take about " + sim::format_value(std::round(w.seconds * 10.0) / 10.0) +
                           " s; at most " + sim::format_value(kMaxSecondsPerFrame) +
                           " s a frame, so that no run hangs for hours: fewer substeps, or a smaller scene");
}

void refuse_trails(const SceneBuilder& b, const Section& top) {
    const SceneDef& scene = b.scene;
    if (scene.view.trail_frames <= 0) return;
    // The particles that can move: the free ones and every emitter's (parked,
    // pinned, until born). Pinned ones keep no trail.
    std::size_t moving = 0;
    for (const sim::ParticleDef& p : scene.model.particles) moving += p.pinned ? 0 : 1;
    for (const sim::Emitter& e : scene.model.emitters) moving += e.count;
    const double kept = std::min(scene.view.trail_frames, scene.frames) + 1.0;  // positions a trail holds at the end
    const double points = static_cast<double>(moving) * kept;
    if (points <= kMaxTrailPoints) return;
    const toml::table* view = top.subtable("view");
    b.r.fail(view != nullptr ? view->get("trail_frames") : nullptr,
             "view.trail_frames = " + std::to_string(scene.view.trail_frames) + " behind " + std::to_string(moving) +
                 " moving particles keeps " + sim::format_value(points) + " trail points by frame " +
                 std::to_string(scene.frames) + " (the last " + sim::format_value(kept) + " positions of each, " +
                 sim::format_value(std::round(kTrailPointBytes * 10.0) / 10.0) + " bytes a point): about " +
                 sim::format_value(std::round(points * kTrailPointBytes / 1e8) / 10.0) + " GB; at most " +
                 sim::format_value(kMaxTrailPoints) + " points (about " +
                 sim::format_value(std::round(kMaxTrailPoints * kTrailPointBytes / 1e6)) +
                 " MB), so that a run cannot run out of memory: a shorter trail, or fewer particles");
}

}  // namespace

void refuse_work_too_large(SceneBuilder& b, const Section& top) {
    refuse_newton_gravity(b, top);
    refuse_sparse_solve(b, top);
    refuse_slow_frames(b, top);
    refuse_trails(b, top);
}

}  // namespace scenes::loader
