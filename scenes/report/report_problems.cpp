// The report's problems (sim/problems.h's models, named, titled, with the
// dt each method's sweep starts at and the closed form to compare with) and
// its hard cases (what the stability map scales). Its own file: what is
// measured, apart from how.
#include "scenes/report/report_stages.h"

#include "sim/integrators.h"
#include "sim/mass_spring.h"
#include "sim/problems.h"

#include <cmath>

namespace scenes::report {

namespace pr = sim::problems;
using sim::Vec3;

namespace {

Problem kepler(double e) {
    const bool half = e == 0.5;
    return {
        .name = half ? "kepler_e0.5" : "kepler_e0.9",
        .title = "Kepler orbit, e = " + std::string(half ? "0.5" : "0.9") + ", 5 s of its 2π s period",
        .error_unit = "m",
        .end = pr::kKeplerEnd,
        .dt1 = half ? 0.00125 : 6.25e-5,
        .dt2 = half ? 0.005 : 0.001,
        .dt4 = half ? 0.01 : 0.002,
        .model = [e] { return pr::kepler_model(e); },
        .particle = 1,
        .exact = [e](double t) { return sim::analytic::kepler(pr::kKeplerMu, pr::kepler_r0(e), pr::kepler_v0(e), t); }};
}

Problem pendulum() {
    const double period = sim::analytic::pendulum_period(pr::kPendulumLength, pr::kGravity, pr::kPendulumAmplitude);
    return {.name = "pendulum",
            .title = "pendulum on an XPBD rod, released 120° out: its period against the elliptic integral",
            .error_unit = "s",
            .end = 2.0 * period,
            .dt1 = 0.00125,
            .dt2 = 0.00125,
            .dt4 = 0.00125,
            .smooth = false,
            .model = pr::pendulum_model,
            .particle = 1,
            .exact = {},
            .period = period};
}

}  // namespace

std::vector<Problem> problems() {
    std::vector<Problem> out;
    out.push_back(
        {.name = "ballistic",
         .title = "ballistic shot, 1 s (exact for every method of order 2 or more)",
         .error_unit = "m",
         .end = 1.0,
         .dt1 = 0.0125,
         .dt2 = 0.05,
         .dt4 = 0.1,
         .model = [] { return pr::ballistic_model(); },
         .particle = 0,
         .exact =
             [](double t) { return sim::analytic::ballistic(Vec3::Zero(), pr::kShotVelocity, pr::kShotGravity, t); }});
    out.push_back(
        {.name = "oscillator",
         .title = "harmonic oscillator, ω = 1 rad/s, 10 s",
         .error_unit = "m",
         .end = pr::kOscEnd,
         .dt1 = 0.005,
         .dt2 = 0.02,
         .dt4 = 0.04,
         .model = [] { return pr::oscillator_model(pr::kOscillator, pr::kOscX0, pr::kOscV0); },
         .particle = 1,
         .exact = [](double t) { return sim::analytic::oscillator(pr::kOscillator, pr::kOscX0, pr::kOscV0, t); }});
    out.push_back(
        {.name = "damped",
         .title = "damped oscillator, ζ = 0.1, 10 s",
         .error_unit = "m",
         .end = pr::kOscEnd,
         .dt1 = 0.005,
         .dt2 = 0.02,
         .dt4 = 0.04,
         .drag = true,
         .model = pr::damped_model,
         .particle = 1,
         .exact = [](double t) { return sim::analytic::oscillator(pr::kDamped, pr::kOscX0, pr::kOscV0, t); }});
    out.push_back(kepler(0.5));
    out.push_back(kepler(0.9));
    out.push_back(pendulum());
    return out;
}

int expected_order(const Problem& p, const sim::IntegratorInfo& info) {
    if (!p.smooth || (p.name == "ballistic" && info.order >= 2)) return 0;
    // Kick-drift-kick leapfrog's second kick sees the half-step velocity: with
    // a velocity-dependent force its velocity, and so its orbit, is first order.
    if (p.drag && info.id == sim::Integrator::leapfrog) return 1;
    return info.order;
}

double coarsest_dt(const Problem& p, const sim::IntegratorInfo& info) {
    return info.order <= 1 ? p.dt1 : info.order >= 4 ? p.dt4 : p.dt2;
}

// --- the hard cases --------------------------------------------------------------------------

sim::WatchdogLimits stiff_spring_limits() {
    // Exploded once it moves 100 times faster than its own swing (ω A = 10 m/s):
    // an unstable method's amplitude grows without bound, a stable one's
    // energy may wobble (symplectic Euler's by a factor near 2/(1 - (ω h / 2)²)) but stays bounded.
    sim::WatchdogLimits limits;
    limits.max_speed = 100.0 * std::sqrt(pr::kStiffK) * pr::kStiffX0;  // m/s
    return limits;
}

namespace {

HardCase stiff_spring() {
    return {.name = "stiff_spring",
            .title = "stiff spring, 1 kg",
            .stiffness = pr::kStiffK,
            .end = kStiffEnd,
            .model = pr::stiff_spring_model,
            .limits = stiff_spring_limits()};
}

HardCase cloth() {
    HardCase c{.name = "cloth",
               .title = "cloth 12x12, 0.5 kg, hung by one edge",
               .stiffness = 2000.0,
               .end = 1.0,
               .model = [](double k) {
                   sim::ParticleModel m;
                   sim::ClothDef cloth;
                   cloth.nx = cloth.ny = 12;
                   cloth.mass = 0.5;
                   cloth.pins = sim::ClothDef::Pins::edge;
                   cloth.links.stiffness = k;
                   sim::add_cloth(m, cloth);
                   m.forces.push_back(sim::UniformGravity{Vec3(0, -pr::kGravity, 0)});
                   return m;
               }};
    c.limits.max_speed = 50.0;  // m/s: a 2 m cloth falling 2 m reaches 6
    c.limits.world_half_extent = 100.0;
    return c;
}

HardCase heavy_chain() {
    HardCase c{
        .name = "chain_1000_1",
        .title = "chain of 8 links of 1 g and a 1 kg ball (1000:1)",
        .stiffness = 2000.0,
        .end = 1.0,
        .model = [](double k) {
            sim::ParticleModel m;
            sim::RopeDef rope;
            rope.segments = 8;
            rope.mass = 0.009;  // kg: 1 g a node
            rope.start = Vec3(0, 2, 0);
            rope.end = Vec3(1.6, 2, 0);
            rope.links.stiffness = k;
            const sim::BodyRange r = sim::add_rope(m, rope);
            const auto last = static_cast<std::uint32_t>(r.first + r.count - 1);
            m.particles.push_back({Vec3(1.8, 2, 0), Vec3::Zero(), 1.0, false});
            m.forces.push_back(sim::Springs{{{last, static_cast<std::uint32_t>(m.particles.size() - 1), 0.2, k, 0.0}}});
            m.forces.push_back(sim::UniformGravity{Vec3(0, -pr::kGravity, 0)});
            return m;
        }};
    c.limits.max_speed = 50.0;
    c.limits.world_half_extent = 100.0;
    return c;
}

}  // namespace

std::vector<HardCase> hard_cases() { return {stiff_spring(), cloth(), heavy_chain()}; }

}  // namespace scenes::report
