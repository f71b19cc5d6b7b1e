// Force generators: the lecture's spring formula, Newton's third law, safety
// at zero length, the fast spring pass against the reference loop (bit for
// bit), potentials and Jacobians (checked by central differences), and the
// refusal of bad parameters.
#include "sim/forces.h"
#include "sim/cpu.h"
#include "sim/error.h"
#include "sim/mass_spring.h"
#include "sim/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace sim {
namespace {

// A small system of n particles at scattered positions and velocities.
struct Fixture {
    Vec3Array x, v;
    std::vector<double> mass, inv_mass;
    explicit Fixture(std::size_t n) : x(n), v(n), mass(n), inv_mass(n) {
        for (std::size_t i = 0; i < n; ++i) {
            const double s = static_cast<double>(i);
            x.set(i, Vec3(std::sin(1.3 * s + 0.2), std::cos(0.7 * s) * 1.5, 0.4 * s - 0.9));
            v.set(i, Vec3(0.3 * std::cos(s), -0.2 * s, 0.5 * std::sin(2.0 * s)));
            mass[i] = 0.5 + 0.25 * s;
            inv_mass[i] = 1.0 / mass[i];
        }
    }
    ForceInput input() const { return {0.0, 0, x.span(), v.span(), mass.data(), inv_mass.data()}; }
};

Vec3Array force_of(const ForceDef& def, const Fixture& fx) {
    Vec3Array f(fx.x.size());
    std::visit([&](const auto& g) { accumulate(g, fx.input(), f.span()); }, def);
    return f;
}

TEST(Spring, ForceIsTheLectureFormula) {
    // f_a = k (|p_b - p_a| - ℓ) (p_b - p_a) / |p_b - p_a|, f_b = -f_a
    const Spring s{0, 1, 0.8, 250.0, 0.0};
    const Vec3 pa(0.1, -0.3, 0.2), pb(1.2, 0.4, -0.5);
    const Vec3 d = pb - pa;
    const Vec3 expected = s.k * (d.norm() - s.rest) * d / d.norm();
    const Vec3 f = spring_force(s, pa, pb, Vec3::Zero(), Vec3::Zero());
    EXPECT_LT((f - expected).norm(), 1e-12) << "N";
}

TEST(Spring, DamperActsAlongTheSpring) {
    const Spring s{0, 1, 1.0, 0.0, 3.0};  // pure damper, c = 3 N·s/m
    const Vec3 pa(0, 0, 0), pb(2, 0, 0);
    // b moves away along the spring at 0.5 m/s and sideways at 7 m/s:
    // only the 0.5 m/s separation is damped, f_a = c · 0.5 along +x.
    const Vec3 f = spring_force(s, pa, pb, Vec3::Zero(), Vec3(0.5, 7.0, 0.0));
    EXPECT_LT((f - Vec3(1.5, 0.0, 0.0)).norm(), 1e-12) << "N";
}

TEST(Spring, NewtonsThirdLaw) {
    Fixture fx(6);
    Springs springs{
        {{0, 1, 0.5, 100, 2}, {1, 2, 1.0, 40, 0}, {2, 5, 0.2, 10, 1}, {3, 4, 2.0, 7, 0.5}, {0, 5, 0, 3, 0}}};
    const Vec3Array f = force_of(springs, fx);
    Vec3 total = Vec3::Zero();
    for (std::size_t i = 0; i < 6; ++i) {
        total += f.get(i);
    }
    EXPECT_LT(total.norm(), 1e-12) << "net internal force, N";
    // and pair by pair
    for (const Spring& s : springs.list) {
        const Vec3 fa = spring_force(s, fx.x.get(s.i), fx.x.get(s.j), fx.v.get(s.i), fx.v.get(s.j));
        const Vec3 fb = spring_force(s, fx.x.get(s.j), fx.x.get(s.i), fx.v.get(s.j), fx.v.get(s.i));
        EXPECT_LT((fa + fb).norm(), 1e-12) << "N";
    }
}

TEST(Spring, ZeroLengthGivesNoNaN) {
    const Vec3 p(0.3, 0.3, 0.3);
    for (double rest : {0.0, 1.0}) {
        const Spring s{0, 1, rest, 100.0, 5.0};
        const Vec3 f = spring_force(s, p, p, Vec3(1, 0, 0), Vec3(0, 2, 0));
        EXPECT_TRUE(f.allFinite()) << "rest " << rest;
        EXPECT_EQ(f, Vec3::Zero()) << "N, no direction to push along (rest " << rest << " m)";
    }
    // The Jacobian and energy at zero length are finite too.
    Fixture fx(2);
    fx.x.set(1, fx.x.get(0));
    Springs springs{{{0, 1, 1.0, 100.0, 5.0}}};
    Jacobians jac;
    accumulate_jacobians(springs, fx.input(), jac);
    for (const auto& e : jac.dfdx) {
        EXPECT_TRUE(std::isfinite(e.value()));
    }
    EXPECT_DOUBLE_EQ(potential_energy(springs, fx.input()), 0.5 * 100.0 * 1.0);
}

// The same doubles to the last bit (NaN payloads and the sign of zero included).
bool same_bits(const Vec3Array& a, const Vec3Array& b) {
    const std::vector<double> fa = a.flat(), fb = b.flat();
    return fa.size() == fb.size() && std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(double)) == 0;
}

TEST(Spring, FastPassGivesTheReferenceLoopsBits) {
    // A 16 x 16 cloth (structural, shear and bend springs), crumpled and moving:
    // its springs fall into runs, its inner particles into blocks and its
    // edges into single particles.
    ParticleModel model;
    ClothDef cloth;
    cloth.nx = cloth.ny = 16;
    cloth.links.damping = 0.3;  // N·s/m
    add_cloth(model, cloth);
    const Springs built = std::get<Springs>(model.forces.at(0));
    const std::size_t n = model.particles.size();
    Random random(11);
    Fixture crumpled(n);
    for (std::size_t i = 0; i < n; ++i) {
        crumpled.x.set(i, model.particles[i].position + 0.02 * random.unit_vector());
        crumpled.v.set(i, random.normal(0.0, 1.0) * random.unit_vector());
    }
    // The pinned build (SSE) and, where the CPU has it, the AVX2 build.
    std::vector<bool> widths{false};
    if (avx2_available()) widths.push_back(true);
    for (const bool wide : widths) {
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        Springs springs = built;
        Fixture fx = crumpled;
        SpringPlan plan = plan_springs(springs, n);
        plan.wide = wide;
        EXPECT_FALSE(plan.runs.empty());
        EXPECT_FALSE(plan.blocks.empty());
        EXPECT_FALSE(plan.singles.empty());
        // Both start from the same forces (gravity, say): the order of the
        // additions shows in the bits.
        Vec3Array reference(n);
        for (std::size_t i = 0; i < n; ++i) reference.set(i, Vec3(0.0, -9.81 * fx.mass[i], 0.0));
        Vec3Array fast = reference;
        accumulate(springs, fx.input(), reference.span());
        EXPECT_TRUE(accumulate(springs, plan, fx.input(), fast.span())) << "the fast pass ran";
        EXPECT_TRUE(same_bits(reference, fast));

        // Plastic springs change rest lengths; the pass re-reads them.
        springs.plasticity.yield_strain = 0.1;
        springs.plasticity.creep = 1.0;  // 1/s
        for (Spring& s : springs.list) s.rest *= 1.1;
        Vec3Array reference2(n), fast2(n);
        accumulate(springs, fx.input(), reference2.span());
        EXPECT_TRUE(accumulate(springs, plan, fx.input(), fast2.span())) << "the fast pass ran";
        EXPECT_TRUE(same_bits(reference2, fast2)) << "after rest lengths changed";

        // Two particles on top of each other (no direction: the reference loop
        // leaves the spring out): the fast pass hands it to the reference loop.
        fx.x.set(1, fx.x.get(0));
        Vec3Array reference3(n), fast3(n);
        accumulate(springs, fx.input(), reference3.span());
        EXPECT_FALSE(accumulate(springs, plan, fx.input(), fast3.span())) << "the reference loop ran";
        EXPECT_TRUE(same_bits(reference3, fast3)) << "a spring of length 0";
        // A plastic list with a spring of rest length 0 (force k d): the
        // stretch kernels give way to the mixed ones.
        fx.x.set(1, crumpled.x.get(1));
        springs.list.push_back({2, 40, 0.0, 50.0, 0.1});
        SpringPlan zero_rest = plan_springs(springs, n);
        zero_rest.wide = wide;
        EXPECT_EQ(zero_rest.loose_kind, SpringPlan::Kind::mixed);
        Vec3Array reference4(n), fast4(n);
        accumulate(springs, fx.input(), reference4.span());
        EXPECT_TRUE(accumulate(springs, zero_rest, fx.input(), fast4.span())) << "the fast pass ran";
        EXPECT_TRUE(same_bits(reference4, fast4)) << "a spring of rest length 0";
    }
}

TEST(Spring, FastPassGivesTheReferenceLoopsBitsOnAnyTopology) {
    // Springs in no order at all (random pairs, both directions, repeated
    // pairs) next to a rope (one long run): every spring and particle path.
    const std::size_t n = 320;  // the last 20 without springs
    Random random(5);
    Springs springs;
    for (std::uint32_t i = 0; i + 1 < 100; ++i) springs.list.push_back({i, i + 1, 0.05, 400.0, 0.2});
    for (int s = 0; s < 700; ++s) {
        const auto i = static_cast<std::uint32_t>(random.uniform(0.0, 300.0));
        auto j = static_cast<std::uint32_t>(random.uniform(0.0, 300.0));
        if (j == i) j = (i + 1) % 300;
        springs.list.push_back({i, j, random.uniform(0.0, 0.5) + 0.01, random.uniform(1.0, 500.0), 0.05});
    }
    Fixture fx(n);
    for (std::size_t i = 0; i < n; ++i) {
        fx.x.set(i, random.uniform(0.0, 1.0) * random.unit_vector());
        fx.v.set(i, random.normal(0.0, 1.0) * random.unit_vector());
    }
    Vec3Array reference(n);
    accumulate(springs, fx.input(), reference.span());
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SpringPlan plan = plan_springs(springs, n);
        plan.wide = wide;
        EXPECT_FALSE(plan.runs.empty()) << "the rope";
        EXPECT_LT(plan.loose, springs.list.size()) << "the random springs";
        for (const std::uint32_t p : plan.singles) EXPECT_GT(plan.first[p + 1], plan.first[p]) << "particle " << p;
        Vec3Array fast(n);
        EXPECT_TRUE(accumulate(springs, plan, fx.input(), fast.span())) << "the fast pass ran";
        EXPECT_TRUE(same_bits(reference, fast)) << (wide ? "AVX2 build" : "pinned build");
    }
}

TEST(Spring, FastPassGivesTheReferenceLoopsBitsWithZeroRestSprings) {
    // Beads on springs to one shared pinned anchor (particle 0), as the
    // report's batch of oscillators: a fan of rest-0 springs without damper
    // (k d only), a fan where rest-0 springs with and without damper and
    // springs of rest length > 0 alternate (each spring its own formula), a
    // rope of rest length > 0, and random loose springs of every kind, one
    // rest-0 damped spring of length 0 among them (no direction: k d alone,
    // no fallback).
    const std::size_t n = 200;
    Springs springs;
    for (std::uint32_t b = 1; b <= 40; ++b) springs.list.push_back({0, b, 0.0, 1.0 + 0.1 * b, 0.0});
    for (std::uint32_t b = 42; b <= 81; ++b) {  // (41 left out: two fans, not one)
        const double rest = b % 3 == 0 ? 0.3 : 0.0, c = b % 2 == 0 ? 0.37 + 0.01 * b : 0.0;
        springs.list.push_back({0, b, rest, 2.0 + 0.1 * b, c});
    }
    for (std::uint32_t i = 82; i < 120; ++i) springs.list.push_back({i, i + 1, 0.05, 300.0, 0.2});
    Random random(17);
    for (int s = 0; s < 200; ++s) {
        const auto i = static_cast<std::uint32_t>(random.uniform(1.0, 199.0));
        auto j = static_cast<std::uint32_t>(random.uniform(1.0, 199.0));
        if (j == i) j = i + 1;
        const double rest = s % 4 == 0 ? 0.0 : random.uniform(0.01, 0.5);
        springs.list.push_back({i, j, rest, random.uniform(1.0, 500.0), s % 3 == 0 ? 0.0 : random.uniform(0.1, 0.9)});
    }
    springs.list.push_back({150, 151, 0.0, 40.0, 0.5});
    Fixture fx(n);
    fx.inv_mass[0] = 0.0;  // the anchor is pinned
    for (std::size_t i = 0; i < n; ++i) {
        fx.x.set(i, random.uniform(0.0, 1.0) * random.unit_vector());
        fx.v.set(i, random.normal(0.0, 1.0) * random.unit_vector());
    }
    fx.x.set(151, fx.x.get(150));
    Vec3Array start(n);
    for (std::size_t i = 0; i < n; ++i) start.set(i, Vec3(0.0, -9.81 * fx.mass[i], 0.0));
    Vec3Array reference = start;
    accumulate(springs, fx.input(), reference.span());
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        SpringPlan plan = plan_springs(springs, n);
        plan.wide = wide;
        using Kind = SpringPlan::Kind;
        std::vector<std::pair<bool, Kind>> runs;
        for (const SpringPlan::Run& r : plan.runs) runs.emplace_back(r.fan, r.kind);
        EXPECT_NE(std::find(runs.begin(), runs.end(), std::pair(true, Kind::linear)), runs.end()) << "the k d fan";
        EXPECT_NE(std::find(runs.begin(), runs.end(), std::pair(true, Kind::mixed)), runs.end()) << "the mixed fan";
        EXPECT_NE(std::find(runs.begin(), runs.end(), std::pair(false, Kind::stretch)), runs.end()) << "the rope";
        EXPECT_EQ(plan.loose_kind, Kind::mixed);

        Vec3Array all = start;
        EXPECT_TRUE(accumulate(springs, plan, fx.input(), all.span())) << "the fast pass ran";
        EXPECT_TRUE(same_bits(reference, all)) << "every particle, the anchor too";

        // For an acceleration the anchor's sum is left out: it keeps the force
        // it came with, and every free particle its bits.
        Vec3Array free = start;
        EXPECT_TRUE(accumulate(springs, plan, fx.input(), free.span(), true)) << "the fast pass ran";
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3Array& expected = fx.inv_mass[i] == 0.0 ? start : reference;
            for (int k = 0; k < 3; ++k) {
                const double a = free.span().c[k][i], b = expected.span().c[k][i];
                EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "particle " << i << " component " << k;
            }
        }
    }
}

// What the separate passes ParticleForces ran before leave in f: the zero
// pass (finish.from_zero) or `before`, the reference loop, M⁻¹
// (finish.to_acceleration); where skip_pinned, a pinned particle's sum left
// out (f as it came, times its inverse mass 0 for an acceleration).
Vec3Array separate_passes(const Springs& springs, const Fixture& fx, const Vec3Array& before,
                          const SpringFinish& finish, bool skip_pinned) {
    const std::size_t n = fx.x.size();
    Vec3Array f = finish.from_zero ? Vec3Array(n) : before;
    Vec3Array summed = f;
    accumulate(springs, fx.input(), summed.span());
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 value = skip_pinned && fx.inv_mass[i] == 0.0 ? f.get(i) : summed.get(i);
        if (finish.to_acceleration) {
            for (int k = 0; k < 3; ++k) value[k] *= fx.inv_mass[i];
        }
        f.set(i, value);
    }
    return f;
}

TEST(Spring, FastPassFinishesAnAccelerationWithTheSeparatePassesBits) {
    // The pass as the last generator of an acceleration: it starts from zero
    // (no generator before) or from a force, and multiplies by the inverse
    // mass. Against the separate passes ParticleForces ran before (zero,
    // the reference loop, M⁻¹), on a fan to a pinned anchor (a pinned single
    // particle, skipped), a rope (a block), random springs (singles), ten
    // particles without springs at the end and one in the middle; and on a
    // spring of length 0 (the fallback). The fan is direct: where the
    // anchor's sum is skipped, its beads are summed as their forces are
    // computed.
    const std::size_t n = 120;
    Springs springs;
    for (std::uint32_t b = 1; b <= 30; ++b) springs.list.push_back({0, b, 0.0, 1.0 + 0.1 * b, 0.0});
    for (std::uint32_t i = 32; i < 80; ++i) springs.list.push_back({i, i + 1, 0.05, 300.0, 0.2});
    Random random(23);
    for (int s = 0; s < 60; ++s) {
        const auto i = static_cast<std::uint32_t>(random.uniform(81.0, 109.0));
        springs.list.push_back({i, i + 1 + static_cast<std::uint32_t>(s % 3), 0.1, random.uniform(1.0, 500.0), 0.3});
    }
    Fixture fx(n);
    fx.inv_mass[0] = 0.0;  // the anchor is pinned
    for (std::size_t i = 0; i < n; ++i) fx.v.set(i, random.normal(0.0, 1.0) * random.unit_vector());
    Vec3Array weight(n);  // a force from before (gravity, say)
    for (std::size_t i = 0; i < n; ++i) weight.set(i, Vec3(0.0, -9.81 * fx.mass[i], 0.0));
    auto expected = [&](const SpringFinish& finish, bool skip_pinned) {
        return separate_passes(springs, fx, weight, finish, skip_pinned);
    };
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        SpringPlan plan = plan_springs(springs, n);
        plan.wide = wide;
        ASSERT_FALSE(plan.blocks.empty());
        ASSERT_FALSE(plan.singles.empty());
        ASSERT_GE(plan.bare.size(), 2u) << "particle 31 and the last ten";
        ASSERT_TRUE(std::any_of(plan.runs.begin(), plan.runs.end(), [](const auto& r) { return r.direct; }))
            << "the fan: beads without other springs";
        for (const bool length_zero : {false, true}) {
            if (length_zero) fx.x.set(90, fx.x.get(91));  // a spring of rest length 0.1 m and length 0
            for (const SpringFinish finish : {SpringFinish{false, false}, SpringFinish{false, true},
                                              SpringFinish{true, false}, SpringFinish{true, true}}) {
                for (const bool skip_pinned : {false, true}) {
                    SCOPED_TRACE(testing::Message()
                                 << "from_zero " << finish.from_zero << ", to_acceleration " << finish.to_acceleration
                                 << ", skip_pinned " << skip_pinned << ", length 0 " << length_zero);
                    Vec3Array f = weight;
                    if (finish.from_zero) {  // what it holds must not matter
                        for (std::size_t i = 0; i < n; ++i) f.set(i, Vec3::Constant(std::nan("")));
                    }
                    EXPECT_EQ(accumulate(springs, plan, fx.input(), f.span(), skip_pinned, finish), !length_zero);
                    // (the fallback sums the anchor too: its expected value is the summed one)
                    EXPECT_TRUE(same_bits(f, expected(finish, skip_pinned && !length_zero)));
                }
            }
        }
        fx.x.set(90, Fixture(n).x.get(90));
    }
}

TEST(Spring, ADirectFanReadsASharedStiffnessAndInverseMassOnce) {
    // The report's batch: beads of one mass, each on a spring of one
    // stiffness to a pinned hook. The plan sees the shared k; the pass sees
    // the shared inverse mass while ForceInput::masses stays the stamp it
    // looked at (read again when the stamp moves; never kept at stamp 0).
    // Every finish gives the separate passes' bits (zero, the reference
    // loop, M⁻¹; the hook's sum left out), the beads' masses shared or not.
    const std::size_t n = 41;
    Springs springs;
    for (std::uint32_t b = 1; b < n; ++b) springs.list.push_back({0, b, 0.0, 2.5, 0.0});
    Fixture fx(n);
    std::fill(fx.mass.begin(), fx.mass.end(), 3.0);
    std::fill(fx.inv_mass.begin(), fx.inv_mass.end(), 1.0 / 3.0);
    fx.inv_mass[0] = 0.0;  // the hook is pinned
    Vec3Array weight(n);   // a force from before
    for (std::size_t i = 0; i < n; ++i) weight.set(i, Vec3(0.0, -9.81 * fx.mass[i], 0.0));
    auto expected = [&](const SpringFinish& finish) { return separate_passes(springs, fx, weight, finish, true); };
    auto pass = [&](SpringPlan& plan, std::uint64_t masses, const SpringFinish& finish) {
        Vec3Array f = finish.from_zero ? Vec3Array(n) : weight;
        if (finish.from_zero) {  // what it holds must not matter
            for (std::size_t i = 0; i < n; ++i) f.set(i, Vec3::Constant(std::nan("")));
        }
        ForceInput in = fx.input();
        in.masses = masses;
        EXPECT_TRUE(accumulate(springs, plan, in, f.span(), true, finish)) << "the fast pass ran";
        return f;
    };
    for (const bool wide : {false, true}) {
        if (wide && !avx2_available()) continue;
        SCOPED_TRACE(wide ? "AVX2 build" : "pinned build");
        SpringPlan plan = plan_springs(springs, n);
        plan.wide = wide;
        ASSERT_EQ(plan.runs.size(), 1u);
        const SpringPlan::Run& fan = plan.runs[0];
        ASSERT_TRUE(fan.direct);
        EXPECT_TRUE(fan.same_k);
        for (const SpringFinish finish : {SpringFinish{false, false}, SpringFinish{false, true},
                                          SpringFinish{true, false}, SpringFinish{true, true}}) {
            SCOPED_TRACE(testing::Message()
                         << "from_zero " << finish.from_zero << ", to_acceleration " << finish.to_acceleration);
            fx.inv_mass[17] = 1.0 / 3.0;
            EXPECT_TRUE(same_bits(pass(plan, 0, finish), expected(finish))) << "stamp 0";
            EXPECT_FALSE(fan.same_inv_mass) << "stamp 0 promises nothing";
            EXPECT_TRUE(same_bits(pass(plan, 7, finish), expected(finish))) << "one mass";
            EXPECT_TRUE(fan.same_inv_mass);
            fx.inv_mass[17] = 0.25;  // a bead's mass written, and the stamp moved on
            EXPECT_TRUE(same_bits(pass(plan, 8, finish), expected(finish))) << "bead 17's mass its own";
            EXPECT_FALSE(fan.same_inv_mass);
            fx.inv_mass[17] = 1.0 / 3.0;
            EXPECT_TRUE(same_bits(pass(plan, 9, finish), expected(finish))) << "one mass again";
            EXPECT_TRUE(fan.same_inv_mass);
        }
    }
    // One spring's stiffness its own: not shared, the same bits.
    springs.list[20].k = 2.5000000000000004;
    SpringPlan plan = plan_springs(springs, n);
    ASSERT_EQ(plan.runs.size(), 1u);
    EXPECT_FALSE(plan.runs[0].same_k);
    EXPECT_TRUE(same_bits(pass(plan, 1, {true, true}), expected({true, true})));
}

// Two particles and one generator between them (a bead on its anchor, a
// planet around a pinned sun) take their own path in acceleration(), the
// sums in registers (sim/pair_forces.h); two springs on them, the
// few-spring evaluation on two particles. force_and_jacobians sums the
// same forces on the general path: times 1/m, the same bits (bits, not
// values: -0 is not +0 here), with no field, with linear drag, and with
// quadratic drag too; particle 0 pinned, particle 1 pinned, or neither; the
// spring listed from either particle, with a rest length and a damper or
// without either, a damper alone; gravity softened or not, and two
// unsoftened particles at one point (no force).
TEST(PairPaths, GiveTheGeneralPathsBits) {
    auto bits = [](double value) { return std::bit_cast<std::uint64_t>(value); };
    const std::vector<double> mass = {2.0, 0.3};
    const std::vector<std::vector<double>> inverse_masses = {{0.0, 1.0 / 0.3}, {0.5, 0.0}, {0.5, 1.0 / 0.3}};
    Springs from_anchor, to_anchor, damper_alone, both;
    from_anchor.list = {{0, 1, 0.0, 4.0, 0.0}};
    to_anchor.list = {{1, 0, 0.6, 9.0, 0.3}};
    damper_alone.list = {{0, 1, 0.0, 5.0, 0.4}};
    both.list = {from_anchor.list[0], to_anchor.list[0]};
    const std::vector<std::vector<ForceDef>> pair_forces = {
        {from_anchor}, {to_anchor}, {damper_alone}, {both}, {NewtonGravity{1.5, 0.0}}, {NewtonGravity{1.5, 0.2}}};
    const std::vector<std::vector<ForceDef>> fields = {
        {}, {UniformGravity{}, LinearDrag{0.05}}, {UniformGravity{}, LinearDrag{0.05}, QuadraticDrag{0.01}}};
    Random random(5);
    for (std::size_t g = 0; g < pair_forces.size(); ++g) {
        for (std::size_t f = 0; f < fields.size(); ++f) {
            for (const std::vector<double>& inv_mass : inverse_masses) {
                std::vector<ForceDef> defs = fields[f];
                defs.insert(defs.end(), pair_forces[g].begin(), pair_forces[g].end());
                ParticleForces forces(defs, mass, inv_mass);
                for (int trial = 0; trial < 30; ++trial) {
                    SCOPED_TRACE("generator " + std::to_string(g) + ", field " + std::to_string(f) + ", 1/m " +
                                 std::to_string(inv_mass[0]) + " " + std::to_string(inv_mass[1]) + ", trial " +
                                 std::to_string(trial));
                    Vec3Array x(2), v(2), a(2), sum(2);
                    x.set(0, random.uniform(0.0, 2.0) * random.unit_vector());
                    x.set(1, trial == 0 ? x.get(0) : random.uniform(0.1, 3.0) * random.unit_vector());
                    v.set(0, random.normal(0.0, 1.0) * random.unit_vector());
                    v.set(1, random.normal(0.0, 1.0) * random.unit_vector());
                    forces.acceleration(0.0, 0, x.span(), v.span(), a.span());
                    Jacobians jacobians;
                    forces.force_and_jacobians(0.0, 0, x.span(), v.span(), sum.span(), jacobians);
                    for (std::size_t i = 0; i < 2; ++i) {
                        for (int k = 0; k < 3; ++k) {
                            EXPECT_EQ(bits(a.get(i)[k]), bits(sum.get(i)[k] * inv_mass[i]))
                                << "particle " << i << " axis " << k;
                        }
                    }
                    EXPECT_TRUE(std::isfinite(a.get(1).x()));
                }
            }
        }
    }
}

TEST(Spring, PotentialIsHalfKStretchSquared) {
    Fixture fx(2);
    fx.x.set(0, Vec3::Zero());
    fx.x.set(1, Vec3(0.0, 3.0, 4.0));  // length 5 m
    Springs springs{{{0, 1, 2.0, 10.0, 0.0}}};
    EXPECT_NEAR(potential_energy(springs, fx.input()), 0.5 * 10.0 * 9.0, 1e-12) << "J";
}

// f = -∇U: the potential's central difference matches the force.
void expect_force_is_minus_gradient(const ForceDef& def, Fixture fx) {
    const Vec3Array f = force_of(def, fx);
    const double h = 1e-6;
    for (std::size_t i = 0; i < fx.x.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double x0 = fx.x.span().c[k][i];
            fx.x.span().c[k][i] = x0 + h;
            const double up = std::visit([&](const auto& g) { return potential_energy(g, fx.input()); }, def);
            fx.x.span().c[k][i] = x0 - h;
            const double down = std::visit([&](const auto& g) { return potential_energy(g, fx.input()); }, def);
            fx.x.span().c[k][i] = x0;
            EXPECT_NEAR(f.span().c[k][i], -(up - down) / (2 * h), 1e-5)
                << force_name(def) << " particle " << i << " axis " << k << ", N";
        }
    }
}

TEST(Potentials, ForceIsMinusGradient) {
    expect_force_is_minus_gradient(UniformGravity{}, Fixture(4));
    expect_force_is_minus_gradient(Springs{{{0, 1, 0.5, 100, 0}, {1, 2, 1.0, 40, 0}, {0, 3, 0.0, 5, 0}}}, Fixture(4));
    expect_force_is_minus_gradient(NewtonGravity{2.0, 0.1}, Fixture(4));
    expect_force_is_minus_gradient(NewtonGravity{1.5, 0.0}, Fixture(3));
    expect_force_is_minus_gradient(CentralGravity{Vec3(0.2, -0.1, 0.3), 2.0}, Fixture(4));
    // Particle 2 partly under water, particle 3 fully, 0 and 1 above.
    expect_force_is_minus_gradient(Buoyancy{0.2, 1000.0, 9.81, 0.3, 0.0, {}}, Fixture(4));
}

// The analytic Jacobians match central differences of the force.
void expect_jacobians_match(const ForceDef& def, Fixture fx, double tol) {
    const std::size_t n = fx.x.size();
    Jacobians jac;
    std::visit([&](const auto& g) { accumulate_jacobians(g, fx.input(), jac); }, def);
    Eigen::SparseMatrix<double> dfdx(3 * n, 3 * n), dfdv(3 * n, 3 * n);
    dfdx.setFromTriplets(jac.dfdx.begin(), jac.dfdx.end());
    dfdv.setFromTriplets(jac.dfdv.begin(), jac.dfdv.end());
    const double h = 1e-6;
    for (Vec3Array* var : {&fx.x, &fx.v}) {
        const Eigen::SparseMatrix<double>& analytic = (var == &fx.x) ? dfdx : dfdv;
        for (std::size_t j = 0; j < n; ++j) {
            for (int c = 0; c < 3; ++c) {
                double& value = var->span().c[c][j];
                const double saved = value;
                value = saved + h;
                const Vec3Array up = force_of(def, fx);
                value = saved - h;
                const Vec3Array down = force_of(def, fx);
                value = saved;
                for (std::size_t i = 0; i < n; ++i) {
                    for (int r = 0; r < 3; ++r) {
                        const double numeric = (up.span().c[r][i] - down.span().c[r][i]) / (2 * h);
                        EXPECT_NEAR(analytic.coeff(3 * i + r, 3 * j + c), numeric, tol)
                            << force_name(def) << (var == &fx.x ? " df/dx" : " df/dv") << " (" << i << "," << r
                            << ") by (" << j << "," << c << ")";
                    }
                }
            }
        }
    }
}

TEST(Jacobians, MatchCentralDifferences) {
    // Springs all stretched (the clamped transverse term only differs under
    // compression) and without damping (its ∂/∂x term is left out on purpose).
    Fixture fx(3);
    expect_jacobians_match(Springs{{{0, 1, 0.1, 100, 0}, {1, 2, 0.2, 40, 0}}}, fx, 1e-4);
    expect_jacobians_match(Springs{{{0, 2, 0.0, 30, 0}}}, fx, 1e-4);
    expect_jacobians_match(LinearDrag{0.7}, fx, 1e-6);
    expect_jacobians_match(QuadraticDrag{0.3}, fx, 1e-6);
    expect_jacobians_match(NewtonGravity{2.0, 0.05}, fx, 1e-4);
    expect_jacobians_match(CentralGravity{Vec3(0.2, -0.1, 0.3), 2.0}, fx, 1e-4);
    expect_jacobians_match(UniformGravity{}, fx, 1e-9);
    Fixture four(4);
    expect_jacobians_match(Buoyancy{0.2, 1000.0, 9.81, 0.3, 2.5, {}}, four, 1e-3);
}

TEST(Drag, OpposesVelocity) {
    Fixture fx(3);
    const Vec3Array lin = force_of(LinearDrag{0.5}, fx);
    const Vec3Array quad = force_of(QuadraticDrag{0.2}, fx);
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec3 v = fx.v.get(i);
        EXPECT_LT((lin.get(i) + 0.5 * v).norm(), 1e-15) << "N";
        EXPECT_LT((quad.get(i) + 0.2 * v.norm() * v).norm(), 1e-15) << "N";
    }
}

TEST(ParticleForces, UniformFieldEqualsTheGeneratorsItSums) {
    // Gravity and drag run as one fused field; the generators' own
    // accumulate() stays the definition. Both must give the same force (to
    // round-off: the field sums the coefficients before multiplying).
    Fixture fx(7);
    fx.inv_mass[3] = 0.0;  // a pinned particle gets no acceleration
    const std::vector<ForceDef> forces = {UniformGravity{Vec3(0.0, -9.81, 0.0)}, LinearDrag{0.3}, QuadraticDrag{0.05},
                                          UniformGravity{Vec3(0.5, 0.0, -0.2)}, LinearDrag{0.1}};
    ParticleForces summed(forces, fx.mass, fx.inv_mass);
    ASSERT_NE(summed.uniform_field(), nullptr);
    Vec3Array a(7);
    summed.acceleration(0.0, 0, fx.x.span(), fx.v.span(), a.span());
    for (std::size_t i = 0; i < 7; ++i) {
        Vec3 f = Vec3::Zero();
        for (const ForceDef& def : forces) {
            f += force_of(def, fx).get(i);
        }
        EXPECT_LT((a.get(i) - f * fx.inv_mass[i]).norm(), 1e-14 * (1.0 + f.norm())) << "m/s², particle " << i;
    }
    EXPECT_EQ(a.get(3), Vec3::Zero());

    // With a coupled force beside it the field is no longer the whole force.
    std::vector<ForceDef> with_spring = forces;
    with_spring.push_back(Springs{{{0, 1, 0.5, 10.0, 0.0}}});
    EXPECT_EQ(ParticleForces(with_spring, fx.mass, fx.inv_mass).uniform_field(), nullptr);
}

// A local generator may be evaluated block by block (World::step_once does
// when every generator is local): the blocks must give the whole system's
// force, bit for bit, and Jacobians shifted by each block's first index.
void expect_same_block_by_block(const ForceDef& def, const Fixture& fx, std::size_t split) {
    ASSERT_TRUE(std::visit([](const auto& g) { return is_local(g); }, def)) << force_name(def);
    const std::size_t n = fx.x.size();
    const Vec3Array whole = force_of(def, fx);
    Vec3Array blocks(n);
    Jacobians whole_jac, block_jac;
    std::visit([&](const auto& g) { accumulate_jacobians(g, fx.input(), whole_jac); }, def);
    for (const auto& range : {std::pair{std::size_t{0}, split}, std::pair{split, n - split}}) {
        // Plain names, not a structured binding: clang before 16 cannot
        // capture a binding in the lambdas below.
        const std::size_t first = range.first, count = range.second;
        const ForceInput in{0.0,
                            first,
                            fx.x.span().block(first, count),
                            fx.v.span().block(first, count),
                            fx.mass.data() + first,
                            fx.inv_mass.data() + first};
        std::visit([&](const auto& g) { accumulate(g, in, blocks.span().block(first, count)); }, def);
        Jacobians jac;
        std::visit([&](const auto& g) { accumulate_jacobians(g, in, jac); }, def);
        const int shift = static_cast<int>(3 * first);
        for (const auto& e : jac.dfdx) block_jac.dfdx.emplace_back(e.row() + shift, e.col() + shift, e.value());
        for (const auto& e : jac.dfdv) block_jac.dfdv.emplace_back(e.row() + shift, e.col() + shift, e.value());
    }
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(blocks.get(i), whole.get(i)) << force_name(def) << " particle " << i;
    auto same = [&](const auto& a, const auto& b) {
        Eigen::SparseMatrix<double> ma(3 * n, 3 * n), mb(3 * n, 3 * n);
        ma.setFromTriplets(a.begin(), a.end());
        mb.setFromTriplets(b.begin(), b.end());
        return Eigen::MatrixXd(ma - mb).isZero(0.0);
    };
    EXPECT_TRUE(same(whole_jac.dfdx, block_jac.dfdx)) << force_name(def) << " df/dx";
    EXPECT_TRUE(same(whole_jac.dfdv, block_jac.dfdv)) << force_name(def) << " df/dv";
}

TEST(ParticleForces, LocalGeneratorsGiveTheSameForceBlockByBlock) {
    Fixture fx(7);
    Wind lone;
    lone.velocity = Vec3(2, 0, -1);
    lone.particles = {6, 1, 3};
    expect_same_block_by_block(lone, fx, 3);
    expect_same_block_by_block(CentralGravity{Vec3(0.2, -0.1, 0.3), 2.0}, fx, 3);
    expect_same_block_by_block(Buoyancy{0.5, 1000.0, 9.81, 0.4, 3.0, {}}, fx, 3);
    expect_same_block_by_block(Buoyancy{0.5, 1000.0, 9.81, 0.4, 3.0, {5, 2, 0}}, fx, 3);
    ShockWave shock;
    shock.speed = 1.0;
    shock.thickness = 4.0;  // at t = 0 the shell covers r < 2 m
    expect_same_block_by_block(shock, fx, 4);
    expect_same_block_by_block(ControlForces{{{0.0, 1.0, {6, 0, 3}, Vec3(1, 2, 3)}, {-1.0, 0.5, {3}, Vec3(0, 1, 0)}}},
                               fx, 3);
    Wind cloth;
    cloth.triangles = {{0, 1, 2}};
    EXPECT_FALSE(is_local(cloth)) << "a wind with triangles couples their corners";
}

TEST(ParticleForces, SceneFileNames) {
    EXPECT_STREQ(force_name(Wind{}), "wind");
    EXPECT_STREQ(force_name(Buoyancy{}), "buoyancy");
    EXPECT_STREQ(force_name(ShockWave{}), "shock_wave");
    EXPECT_STREQ(force_name(ControlForces{}), "control");
    EXPECT_STREQ(force_name(CentralGravity{}), "central_gravity");
}

TEST(NewtonGravity, InverseSquareLaw) {
    Fixture fx(2);
    fx.x.set(0, Vec3::Zero());
    fx.x.set(1, Vec3(2.0, 0.0, 0.0));
    fx.mass = {3.0, 5.0};
    const Vec3Array f = force_of(NewtonGravity{1.0, 0.0}, fx);
    EXPECT_NEAR(f.get(0).x(), 1.0 * 3.0 * 5.0 / 4.0, 1e-12) << "N, G m1 m2 / r²";
    EXPECT_NEAR(f.get(1).x(), -1.0 * 3.0 * 5.0 / 4.0, 1e-12) << "N";
}

TEST(Validation, RefusesBadParameters) {
    auto message_of = [](const ForceDef& def, std::size_t n) -> std::string {
        try {
            validate_forces({def}, n);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(message_of(Springs{{{0, 1, 1.0, -3.0, 0.0}}}, 2),
              "springs[0].k must be >= 0 and finite, in N/m (got -3)");
    EXPECT_EQ(message_of(Springs{{{0, 0, 1.0, 3.0, 0.0}}}, 2), "springs[0] joins particle 0 to itself");
    EXPECT_EQ(message_of(Springs{{{0, 1, 1.0, 3.0, 0.0}, {1, 7, 1.0, 3.0, 0.0}}}, 2),
              "springs[1] joins particles 1 and 7, but there are only 2");
    EXPECT_EQ(message_of(Springs{{{0, 1, -1.0, 3.0, 0.0}}}, 2),
              "springs[0].rest must be >= 0 and finite, in m (got -1)");
    EXPECT_EQ(message_of(Springs{{{0, 1, 1.0, NAN, 0.0}}}, 2),
              "springs[0].k must be >= 0 and finite, in N/m (got nan)");
    EXPECT_NE(message_of(Springs{{{0, 1, 1.0, 3.0, -1.0}}}, 2), "");
    EXPECT_NE(message_of(LinearDrag{-0.1}, 1), "");
    EXPECT_NE(message_of(QuadraticDrag{INFINITY}, 1), "");
    EXPECT_NE(message_of(NewtonGravity{0.0, 0.0}, 1), "");
    EXPECT_NE(message_of(NewtonGravity{1.0, -1.0}, 1), "");
    EXPECT_NE(message_of(CentralGravity{Vec3::Zero(), -1.0}, 1), "");
    EXPECT_NE(message_of(UniformGravity{Vec3(0, NAN, 0)}, 1), "");
    EXPECT_EQ(message_of(Springs{{{0, 1, 1.0, 3.0, 0.0}}}, 2), "");
}

}  // namespace
}  // namespace sim
