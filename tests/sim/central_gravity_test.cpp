// sim::CentralGravity: the inverse-square law towards a fixed point, a
// particle's orbit against the closed-form Kepler solution (and against the
// same orbit about a pinned particle through NewtonGravity), and copies that
// do not attract each other: each particle of a swarm moves bit for bit as
// it would alone. Potential, Jacobians and block-by-block evaluation are
// checked with the other generators in forces_test.cpp.
#include "sim/central_gravity.h"
#include "sim/cpu.h"
#include "sim/error.h"
#include "sim/problems.h"
#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace sim {
namespace {

ForceInput input_of(const Vec3Array& x, const Vec3Array& v, const std::vector<double>& mass,
                    const std::vector<double>& inv_mass) {
    return {0.0, 0, x.span(), v.span(), mass.data(), inv_mass.data()};
}

TEST(CentralGravity, InverseSquareLawTowardsTheCenter) {
    const CentralGravity gravity{Vec3(1.0, -2.0, 0.5), 5.0};  // μ = 5 m³/s²
    Vec3Array x(3), v(3), f(3);
    x.set(0, gravity.center + Vec3(2.0, 0.0, 0.0));   // 2 m out along +x
    x.set(1, gravity.center + Vec3(0.0, -3.0, 4.0));  // 5 m out
    x.set(2, gravity.center);                         // at the centre: no direction to fall in
    const std::vector<double> mass = {3.0, 0.5, 1.0}, inv_mass = {1.0 / 3.0, 2.0, 1.0};
    accumulate(gravity, input_of(x, v, mass, inv_mass), f.span());
    EXPECT_NEAR((f.get(0) - Vec3(-3.0 * 5.0 / 4.0, 0.0, 0.0)).norm(), 0.0, 1e-12) << "N, -m μ / r² along d̂";
    EXPECT_NEAR((f.get(1) - (-0.5 * 5.0 / 25.0) * Vec3(0.0, -0.6, 0.8)).norm(), 0.0, 1e-12) << "N";
    EXPECT_EQ(f.get(2), Vec3::Zero()) << "N, a particle at the centre";
    EXPECT_TRUE(is_local(gravity));
    EXPECT_NEAR(potential_energy(gravity, input_of(x, v, mass, inv_mass)), -3.0 * 5.0 / 2.0 - 0.5 * 5.0 / 5.0, 1e-12)
        << "J, -m μ / r (the particle at the centre left out)";
}

TEST(CentralGravity, OrbitMatchesTheKeplerClosedForm) {
    // e = 0.5 about a centre off the origin, RK4 at 1 ms for 5 s: the closed
    // form is in coordinates relative to the centre.
    const double e = 0.5;
    const Vec3 center(0.3, -1.0, 2.0);  // m
    ParticleModel model;
    model.particles.push_back({center + problems::kepler_r0(e), problems::kepler_v0(e), 1e-3, false});
    model.forces.push_back(CentralGravity{center, problems::kKeplerMu});
    World world(model);
    problems::run_to(world, Integrator::rk4, 5.0, 1e-3);
    ASSERT_FALSE(world.verdict().exploded());
    const analytic::PointState exact =
        analytic::kepler(problems::kKeplerMu, problems::kepler_r0(e), problems::kepler_v0(e), world.state().t);
    // RK4's error at h = 1 ms: 1.2e-11 m and 9.6e-12 m/s here.
    EXPECT_LT((world.state().x.get(0) - center - exact.x).norm(), 1e-10) << "m, position against the closed form";
    EXPECT_LT((world.state().v.get(0) - exact.v).norm(), 1e-10) << "m/s, velocity against the closed form";

    // The same orbit about a pinned particle of mass μ/G through the all-pairs law.
    World pinned(problems::kepler_model(e));
    problems::run_to(pinned, Integrator::rk4, 5.0, 1e-3);
    EXPECT_LT((world.state().x.get(0) - center - pinned.state().x.get(1)).norm(), 1e-12)
        << "m, against NewtonGravity about a pinned central particle (round-off apart: 8e-14 m here)";

    // Energy is conserved to the method's error (6e-16 J here, of -5e-4 J):
    // the potential is -m μ / r.
    EXPECT_LT(std::abs(world.energy() - World(model).energy()), 1e-13) << "J";
}

TEST(CentralGravity, CopiesDoNotAttractEachOther) {
    // Three particles on different orbits about one centre move exactly as
    // each moves alone (the same bits): no particle feels another.
    const Vec3 r0[3] = {Vec3(1.0, 0.0, 0.0), Vec3(0.0, 0.5, 0.0), Vec3(-0.2, 0.0, 0.9)};
    const Vec3 v0[3] = {Vec3(0.0, 1.1, 0.0), Vec3(-1.3, 0.0, 0.2), Vec3(0.0, 0.9, 0.1)};
    ParticleModel swarm;
    swarm.forces.push_back(CentralGravity{Vec3::Zero(), 1.0});
    for (int k = 0; k < 3; ++k) swarm.particles.push_back({r0[k], v0[k], 1.0 + k, false});
    World all(swarm);
    problems::run_to(all, Integrator::velocity_verlet, 2.0, 1e-3);
    for (int k = 0; k < 3; ++k) {
        ParticleModel lone;
        lone.forces = swarm.forces;
        lone.particles.push_back(swarm.particles[k]);
        World alone(lone);
        problems::run_to(alone, Integrator::velocity_verlet, 2.0, 1e-3);
        const Vec3 a = all.state().x.get(k), b = alone.state().x.get(0);
        EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * 3), 0)
            << "particle " << k << " in the swarm at " << a.transpose() << " m, alone at " << b.transpose() << " m";
    }
}

// The same doubles to the last bit (the sign of zero included).
bool same_bits(const Vec3Array& a, const Vec3Array& b) {
    const std::vector<double> fa = a.flat(), fb = b.flat();
    return fa.size() == fb.size() && std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(double)) == 0;
}

// 37 particles (vector bodies and a remainder at either width), particle 5
// at `centre` (a force of -0 there: +0 + -0 is +0, an addition the fused
// pass must keep) and particle 7 pinned; a field's force on each.
struct Swarm {
    static constexpr std::size_t n = 37;
    Vec3Array x{n}, v{n}, field{n};
    std::vector<double> mass = std::vector<double>(n), inv_mass = std::vector<double>(n);
    ForceInput input() const { return input_of(x, v, mass, inv_mass); }
};
Swarm swarm_about(const Vec3& centre) {
    Swarm w;
    for (std::size_t i = 0; i < Swarm::n; ++i) {
        const double s = static_cast<double>(i);
        w.x.set(i, Vec3(std::sin(1.3 * s + 0.2), std::cos(0.7 * s) * 1.5, 0.4 * s - 0.9));
        w.field.set(i, Vec3(0.01 * s, -9.81 * (0.5 + 0.125 * s), -0.003 * s));  // N, gravity and drag, say
        w.mass[i] = 0.5 + 0.125 * s;
        w.inv_mass[i] = 1.0 / w.mass[i];
    }
    w.x.set(5, centre);
    w.inv_mass[7] = 0.0;
    return w;
}

TEST(CentralGravity, WideAndFusedPassesGiveTheSameBits) {
    const CentralGravity gravity{Vec3(0.2, -0.1, 0.3), 1.7};  // μ, m³/s²
    const Swarm w = swarm_about(gravity.center);
    const std::size_t n = Swarm::n;
    const Vec3Array& field = w.field;
    const std::vector<double>& inv_mass = w.inv_mass;
    const ForceInput in = w.input();
    // The reference: zero (or the field), accumulate in the pinned build, a *= 1/m.
    auto reference = [&](const Vec3Array& start) {
        Vec3Array a = start;
        accumulate(gravity, in, a.span(), false);
        for (std::size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) a.span().c[k][i] *= inv_mass[i];
        }
        return a;
    };
    const Vec3Array from_zero = reference(Vec3Array(n)), from_field = reference(field);
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        Vec3Array f = field, f_base = field;
        accumulate(gravity, in, f.span(), wide);
        accumulate(gravity, in, f_base.span(), false);
        EXPECT_TRUE(same_bits(f, f_base)) << "accumulate";
        Vec3Array a(n);
        to_acceleration(gravity, in, a.span(), true, wide);
        EXPECT_TRUE(same_bits(a, from_zero)) << "from zero";
        Vec3Array b = field;
        to_acceleration(gravity, in, b.span(), false, wide);
        EXPECT_TRUE(same_bits(b, from_field)) << "after a field";
    }
}

// A centre at the origin, (+0, +0, +0), has a build of its own that takes d
// as x itself. Against a centre at (-0, -0, -0), which the general build
// takes (d = x - -0 = x + 0: x again, except where x is -0), the same bits,
// at both widths, from zero or after a field; with a particle at the centre
// and one pinned. A -0 in x is where the two differ (the general build turns
// it into +0), so the origin's build is taken only at +0.
TEST(CentralGravity, TheOriginsBuildGivesTheGeneralBuildsBits) {
    const CentralGravity origin{Vec3(0.0, 0.0, 0.0), 2.3}, minus{Vec3(-0.0, -0.0, -0.0), 2.3};  // μ, m³/s²
    const Swarm w = swarm_about(Vec3::Zero());
    const std::size_t n = Swarm::n;
    const Vec3Array& field = w.field;
    const ForceInput in = w.input();
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        Vec3Array f0 = field, f1 = field, a0(n), a1(n), b0 = field, b1 = field;
        accumulate(origin, in, f0.span(), wide);
        accumulate(minus, in, f1.span(), wide);
        EXPECT_TRUE(same_bits(f0, f1)) << "accumulate";
        to_acceleration(origin, in, a0.span(), true, wide);
        to_acceleration(minus, in, a1.span(), true, wide);
        EXPECT_TRUE(same_bits(a0, a1)) << "from zero";
        to_acceleration(origin, in, b0.span(), false, wide);
        to_acceleration(minus, in, b1.span(), false, wide);
        EXPECT_TRUE(same_bits(b0, b1)) << "after a field";
        EXPECT_NE(a0.get(0), Vec3::Zero()) << "m/s², it pulls";
    }
    // x = (-0, y, z), added to a sum of -0: the general build's d.x is +0,
    // its force's x -0, and -0 + -0 stays -0; the origin build's d.x is -0,
    // its force's x +0, and the sum +0.
    Vec3Array xm(1), vm(1), fm0(1), fm1(1);
    xm.set(0, Vec3(-0.0, 1.0, 0.5));
    fm0.set(0, Vec3(-0.0, 0.0, 0.0)), fm1.set(0, Vec3(-0.0, 0.0, 0.0));
    const std::vector<double> m1 = {1.0}, inv1 = {1.0};
    accumulate(origin, input_of(xm, vm, m1, inv1), fm0.span(), false);
    accumulate(minus, input_of(xm, vm, m1, inv1), fm1.span(), false);
    EXPECT_FALSE(std::signbit(fm0.get(0).x())) << "the origin's build";
    EXPECT_TRUE(std::signbit(fm1.get(0).x())) << "a centre at -0 is not the origin's build";
}

TEST(CentralGravity, RefusesBadParameters) {
    auto message_of = [](const CentralGravity& g) -> std::string {
        try {
            validate(g, 1);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(message_of({Vec3::Zero(), 0.0}), "central_gravity.mu must be > 0 and finite, in m³/s² (got 0)");
    EXPECT_EQ(message_of({Vec3::Zero(), NAN}), "central_gravity.mu must be > 0 and finite, in m³/s² (got nan)");
    EXPECT_EQ(message_of({Vec3(0.0, INFINITY, 0.0), 1.0}), "central_gravity.center must be finite, in m (got inf)");
    EXPECT_EQ(message_of({Vec3(1.0, 2.0, 3.0), 1.0}), "");
}

}  // namespace
}  // namespace sim
