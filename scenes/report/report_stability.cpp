// How the methods hold up over long runs and at large steps: energy drift
// over many periods, the largest stable dt on the stiff spring, the stability
// map of the hard cases (and a ragdoll through ODE), and the XPBD "small
// steps" claim. Its own file: these run until something breaks, where the
// sweeps (report_sweeps.cpp) measure what works.
#include "scenes/report/report_stages.h"

#include "scenes/model/scene.h"

#include "sim/integrators.h"
#include "sim/mass_spring.h"
#include "sim/problems.h"
#include "sim/ragdoll.h"
#include "sim/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace scenes::report {
namespace {

namespace pr = sim::problems;
using sim::Integrator;
using sim::IntegratorInfo;
using sim::Vec3;
using Clock = std::chrono::steady_clock;

// --- energy drift over long runs ----------------------------------------------------------

Drift drift(const std::string& name, const sim::ParticleModel& model, const IntegratorInfo& info, double dt,
            double end) {
    Drift d{.integrator = std::string(info.name), .problem = name};
    sim::World world(model);
    const double e0 = world.energy();
    const long steps = std::lround(end / dt);
    double running = 0.0;
    for (long i = 1; i <= steps; ++i) {
        world.step({info.id, dt, 1});
        if (world.verdict().exploded()) {
            d.exploded = true;
            break;
        }
        const double e = std::abs(world.energy() - e0) / std::abs(e0);
        running = std::max(running, e);
        (2 * i <= steps ? d.first_half : d.second_half) = std::max(2 * i <= steps ? d.first_half : d.second_half, e);
        if (i % std::max(1L, steps / 400) == 0) d.envelope.emplace_back(world.state().t, std::max(running, 1e-17));
    }
    return d;
}

// --- stability on the stiff spring ---------------------------------------------------------

sim::Verdict stiff_run(const IntegratorInfo& info, double dt) {
    sim::World world(pr::stiff_spring_model(pr::kStiffK));
    world.set_watchdog(stiff_spring_limits());
    const long steps = std::max(1L, std::lround(kStiffEnd / dt));
    for (long i = 0; i < steps && !world.verdict().exploded(); ++i) world.step({info.id, dt, 1});
    return world.verdict();
}

Stability stability(const IntegratorInfo& info, int bisections) {
    Stability s{.integrator = std::string(info.name)};
    const sim::Verdict at_frame = stiff_run(info, 1.0 / 60.0);
    s.stable_at_frame = !at_frame.exploded();
    s.exploded_frame = at_frame.frame;
    s.quantity = at_frame.quantity;
    double lo = 1e-6, hi = 0.25;  // s
    if (!stiff_run(info, hi).exploded()) {
        s.always_stable = true;
        s.largest_dt = hi;
        return s;
    }
    if (stiff_run(info, lo).exploded()) return s;  // unstable down to 1 µs
    for (int i = 0; i < bisections; ++i) {
        const double mid = std::sqrt(lo * hi);
        (stiff_run(info, mid).exploded() ? hi : lo) = mid;
    }
    s.largest_dt = lo;
    return s;
}

// --- stability maps: hard cases, per method --------------------------------------------------

bool explodes(const HardCase& c, const IntegratorInfo& info, double dt, double k) {
    sim::World world(c.model(k));
    world.set_watchdog(c.limits);
    const long steps = std::max(1L, std::lround(c.end / dt));
    for (long i = 0; i < steps && !world.verdict().exploded(); ++i) world.step({info.id, dt, 1});
    return world.verdict().exploded();
}

// The largest value in [lo, hi] at which `stable` holds, by bisection in log
// (stable below a threshold, unstable above it). `hi` when stable there;
// 0 when unstable at lo.
double largest_stable(double lo, double hi, int bisections, const std::function<bool(double)>& stable) {
    if (stable(hi)) return hi;
    if (!stable(lo)) return 0.0;
    for (int i = 0; i < bisections; ++i) {
        const double mid = std::sqrt(lo * hi);
        (stable(mid) ? lo : hi) = mid;
    }
    return lo;
}

MapCell map_cell(const HardCase& c, const IntegratorInfo& info, int bisections) {
    return {.hard_case = c.name,
            .integrator = std::string(info.name),
            .largest_dt = largest_stable(kDtLo, kDtHi, bisections,
                                         [&](double dt) { return !explodes(c, info, dt, c.stiffness); }),
            .largest_stiffness =
                largest_stable(kKLo, kKHi, bisections, [&](double k) { return !explodes(c, info, 1.0 / 60.0, k); })};
}

// A ragdoll thrown at 10 m/s steps with ODE whatever the integrator: the
// largest dt of ODE's quickstep (the ragdoll scene's 40 iterations) at which
// it stays finite, under 100 m/s and with its joints within 10 cm after 2 s.
double ragdoll_largest_dt(int bisections) {
    const SceneDef scene = load_scene(resolve_scene("ragdoll"));
    auto stable = [&](double dt) {
        sim::RigidSettings settings = scene.model.rigid.settings;
        settings.sleep = false;
        sim::RigidWorld world(settings);
        sim::RagdollDef def;
        def.position = Vec3(0, 1.5, 0);
        def.velocity = Vec3(6, 8, 0);
        def.angular_velocity = Vec3(1, 0, -3);
        const sim::Ragdoll doll = sim::create_ragdoll(world, def);
        const long steps = std::max(1L, std::lround(2.0 / dt));
        for (long i = 0; i < steps; ++i) {
            world.step(dt);
            for (const sim::BodyId b : doll.bodies) {
                const sim::BodyState st = world.state(b);
                if (!st.position.allFinite() || st.velocity.norm() > 100.0) return false;
            }
        }
        for (const sim::JointId j : doll.joints)
            if (world.joint_separation(j) > 0.1) return false;
        return true;
    };
    return largest_stable(1e-3, kDtHi, bisections, stable);
}

// --- the XPBD "small steps" claim -----------------------------------------------------------

// Macklin et al. (2019): n substeps of one iteration beat one step of n
// iterations. A hanging rope and a cloth held by one edge, inextensible XPBD
// links without tethers, 2 s at 1/60 s frames: the largest strain at the end
// and the time per frame, either way.
sim::ParticleModel hanging(const std::string& body) {
    sim::ParticleModel m;
    sim::LinkSettings links;
    links.kind = sim::LinkSettings::Kind::constraints;
    links.compliance = 0.0;
    links.tethers = false;
    if (body == "rope") {
        sim::RopeDef rope;
        rope.segments = 20;
        rope.links = links;
        sim::add_rope(m, rope);
    } else {
        sim::ClothDef cloth;
        cloth.nx = cloth.ny = 16;
        cloth.pins = sim::ClothDef::Pins::edge;
        cloth.links = links;
        sim::add_cloth(m, cloth);
    }
    m.forces.push_back(sim::UniformGravity{Vec3(0, -pr::kGravity, 0)});
    return m;
}

SmallSteps small_steps(const std::string& body, bool substeps, int n) {
    sim::ParticleModel m = hanging(body);
    m.constraints.iterations = substeps ? 1 : n;
    sim::World world(m);
    const sim::StepSettings step{Integrator::symplectic_euler, 1.0 / 60.0, substeps ? n : 1};
    const auto start = Clock::now();
    for (int f = 0; f < 120; ++f) world.step(step);
    SmallSteps r{.body = body, .way = substeps ? "substeps" : "iterations", .n = n};
    r.ms_per_frame = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / 120.0;
    for (const sim::DistanceConstraint& c : m.constraints.distance) {
        const double length = (world.state().x.get(c.i) - world.state().x.get(c.j)).norm();
        r.strain = std::max(r.strain, std::abs(length / c.rest - 1.0));
    }
    return r;
}

}  // namespace

// Energy drift over long runs: the oscillator for 100 periods, the e = 0.5 orbit for 20.
std::vector<Drift> measure_drift(const Settings& settings, Progress& progress) {
    std::vector<Drift> out;
    for (const IntegratorInfo& info : sim::kIntegrators) {
        out.push_back(drift("oscillator", pr::oscillator_model(pr::kOscillator, pr::kOscX0, pr::kOscV0), info, 0.1,
                            settings.drift_oscillator));
        progress.step("drift oscillator " + std::string(info.name));
        out.push_back(drift("kepler_e0.5", pr::kepler_model(0.5), info, 0.005, settings.drift_kepler));
        progress.step("drift kepler " + std::string(info.name));
    }
    return out;
}

std::vector<Stability> measure_stiff_spring(const Settings& settings, Progress& progress) {
    std::vector<Stability> out;
    for (const IntegratorInfo& info : sim::kIntegrators) {
        out.push_back(stability(info, settings.stiff_bisections));
        progress.step("stability " + std::string(info.name));
    }
    return out;
}

// Each hard case per method, and the ragdoll through ODE.
StabilityMap measure_stability_map(const Settings& settings, Progress& progress) {
    StabilityMap map;
    for (const HardCase& c : hard_cases()) {
        map.cases.push_back(c.name);
        for (const IntegratorInfo& info : sim::kIntegrators)
            map.cells.push_back(map_cell(c, info, settings.map_bisections));
        progress.step("stability map " + c.name);
    }
    map.ragdoll_dt = ragdoll_largest_dt(settings.map_bisections);
    progress.step("stability map ragdoll");
    return map;
}

std::vector<SmallSteps> measure_small_steps(Progress& progress) {
    std::vector<SmallSteps> out;
    for (const std::string body : {"rope", "cloth"}) {
        for (const int n : {1, 2, 4, 8, 16}) {
            out.push_back(small_steps(body, true, n));
            out.push_back(small_steps(body, false, n));
        }
    }
    progress.step("XPBD small steps");
    return out;
}

}  // namespace scenes::report
