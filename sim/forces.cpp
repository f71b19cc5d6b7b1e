#include "sim/forces.h"

#include "sim/cpu.h"
#include "sim/overloaded.h"
#include "sim/pair_forces.h"

#include <algorithm>
#include <chrono>
#include <type_traits>

namespace sim {

const char* force_name(const ForceDef& force) {
    return std::visit(Overloaded{
                          [](const UniformGravity&) { return "gravity"; },
                          [](const NewtonGravity&) { return "newton_gravity"; },
                          [](const Springs&) { return "springs"; },
                          [](const LinearDrag&) { return "linear_drag"; },
                          [](const QuadraticDrag&) { return "quadratic_drag"; },
                          [](const Wind&) { return "wind"; },
                          [](const Buoyancy&) { return "buoyancy"; },
                          [](const ShockWave&) { return "shock_wave"; },
                          [](const ControlForces&) { return "control"; },
                          [](const CentralGravity&) { return "central_gravity"; },
                      },
                      force);
}

void validate_forces(const std::vector<ForceDef>& forces, std::size_t particle_count) {
    for (const ForceDef& force : forces) {
        std::visit([&](const auto& g) { validate(g, particle_count); }, force);
    }
}

namespace {

// The generators whose force never reads v. With a damper of c = 0 a
// spring's force still adds 0 · (dv · n), which is +0 or -0 for any finite
// dv and changes no sum (k (|d| - ℓ) is never -0): the same bits whatever v.
bool reads_no_velocity(const ForceDef& force) {
    if (const auto* springs = std::get_if<Springs>(&force)) {
        return std::all_of(springs->list.begin(), springs->list.end(), [](const Spring& s) { return s.c == 0.0; });
    }
    return std::holds_alternative<UniformGravity>(force) || std::holds_alternative<NewtonGravity>(force) ||
           std::holds_alternative<CentralGravity>(force);
}

}  // namespace

ParticleForces::ParticleForces(const std::vector<ForceDef>& forces, const std::vector<double>& mass,
                               const std::vector<double>& inv_mass)
    : forces_(&forces), mass_(&mass), inv_mass_(&inv_mass), wide_(avx2_available()) {
    for (const ForceDef& force : forces) {
        all_local_ = all_local_ && std::visit([](const auto& g) { return is_local(g); }, force);
        velocity_free_ = velocity_free_ && reads_no_velocity(force);
        if (const auto* gravity = std::get_if<UniformGravity>(&force)) {
            field_.g += gravity->g;
        } else if (const auto* drag = std::get_if<LinearDrag>(&force)) {
            field_.c += drag->c;
            ++field_.linear_drags;
        } else if (const auto* drag2 = std::get_if<QuadraticDrag>(&force)) {
            field_.c2 += drag2->c;
        } else {
            others_.push_back(&force);
            const auto* springs = std::get_if<Springs>(&force);
            plans_.push_back(springs ? plan_springs(*springs, mass.size()) : SpringPlan{});
            continue;
        }
        has_field_ = true;
    }
    springs_last_ = !others_.empty() && std::holds_alternative<Springs>(*others_.back()) && !plans_.back().few;
    if (others_.size() == 1) {
        central_only_ = std::get_if<CentralGravity>(others_[0]);
        const auto* springs = std::get_if<Springs>(others_[0]);
        if (springs != nullptr && plans_[0].few) {
            few_ = {springs, has_field_ ? &field_ : nullptr};
            if (springs->list.size() == 1) spring_pair_ = {&springs->list[0], few_.field};
        }
        if (const auto* gravity = std::get_if<NewtonGravity>(others_[0])) {
            pair_gravity_ = {gravity, has_field_ ? &field_ : nullptr};
        }
    }
}

void ParticleForces::set_wide(bool wide) {
    wide_ = wide && avx2_available();
    for (SpringPlan& plan : plans_) plan.wide = wide_;
}

ForceInput ParticleForces::input(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v) const {
    return {t, first, x, v, mass_->data() + first, inv_mass_->data() + first, masses_};
}

namespace {

constexpr std::size_t kFew = kFewSpringParticles;  // particles: fewer go one at a time, at the pinned width

// The field loop, compiled once per case so that neither the square root of
// quadratic drag nor the inverse-mass multiply costs anything when unused.
// Plain pointers and scalars only (a struct passed in makes GCC reload its
// members every iteration and give up vectorising); __restrict because the
// output never overlaps the velocity or mass arrays.
template <bool kQuadratic, bool kToAcceleration>
void field_loop(const double* __restrict vx, const double* __restrict vy, const double* __restrict vz,
                const double* __restrict m, const double* __restrict inv_m, double* __restrict ox,
                double* __restrict oy, double* __restrict oz, std::size_t n, double gx, double gy, double gz, double c,
                double c2) {
    for (std::size_t i = 0; i < n; ++i) {
        const FieldForce f = field_force<kQuadratic>(m[i], vx[i], vy[i], vz[i], gx, gy, gz, c, c2);
        const double scale = kToAcceleration ? inv_m[i] : 1.0;
        ox[i] = f.x * scale;
        oy[i] = f.y * scale;
        oz[i] = f.z * scale;
    }
}

}  // namespace

void ParticleForces::field_pass(const ForceInput& in, const Vec3Span& out, bool to_acceleration) const {
    const bool quadratic = field_.c2 != 0.0;
    auto run = [&](auto quadratic_constant, auto acceleration_constant) {
        run_at_width(
            wide_ && out.n > kFew,
            [](auto... a) {
                field_loop<decltype(quadratic_constant)::value, decltype(acceleration_constant)::value>(a...);
            },
            in.v.c[0], in.v.c[1], in.v.c[2], in.mass, in.inv_mass, out.c[0], out.c[1], out.c[2], out.n, field_.g.x(),
            field_.g.y(), field_.g.z(), field_.c, field_.c2);
    };
    if (quadratic) {
        to_acceleration ? run(std::true_type{}, std::true_type{}) : run(std::true_type{}, std::false_type{});
    } else {
        to_acceleration ? run(std::false_type{}, std::true_type{}) : run(std::false_type{}, std::false_type{});
    }
}

namespace {

// f = 0, one component at a time. A few particles are stored one value at a
// time: memset's wide (or string) stores cannot be forwarded to the scalar
// loads of the spring pass that follows, which then waits for them to
// retire (a third of a one-spring evaluation, measured).
inline void zero(const Vec3Span& f) {
    if (f.n <= kFew) {
#pragma GCC unroll 4
        for (std::size_t i = 0; i < kFew; ++i) {
            if (i < f.n) f.c[0][i] = f.c[1][i] = f.c[2][i] = 0.0;
        }
        return;
    }
    for (int k = 0; k < 3; ++k) std::fill(f.c[k], f.c[k] + f.n, 0.0);
}

// a *= 1 / m, particle by particle (one loop for the three components).
// A few particles one at a time: a vector load of forces just written one by
// one (a spring's scatter) waits for the stores to retire.
void scale_by_inverse_mass(double* __restrict a0, double* __restrict a1, double* __restrict a2,
                           const double* __restrict inv_m, std::size_t n) {
    if (n <= kFew) {
        for (std::size_t i = 0; i < n && i < kFew; ++i) {
            a0[i] *= inv_m[i];
            a1[i] *= inv_m[i];
            a2[i] *= inv_m[i];
        }
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        a0[i] *= inv_m[i];
        a1[i] *= inv_m[i];
        a2[i] *= inv_m[i];
    }
}

// a = M⁻¹ f(x, v) for a FewSprings force on the particles [first, first +
// x.n), x.n <= kFewSpringParticles (mass and inv_mass: the block's): the
// field's force (or 0), then the springs in list order (accumulate's
// reference loop), then M⁻¹, one particle at a time: the general path's
// operations on each particle.
[[gnu::always_inline]] inline void few_spring_acceleration(const FewSprings& few, double t, std::size_t first,
                                                           const ConstVec3Span& x, const ConstVec3Span& v,
                                                           const double* mass, const double* inv_mass,
                                                           const Vec3Span& a) {
    const std::size_t n = x.n;
    double* a0 = a.c[0];
    double* a1 = a.c[1];
    double* a2 = a.c[2];
    // One value at a time, the loops unrolled to kFewSpringParticles: memset's
    // or a vector loop's wide stores cannot be forwarded to the scalar loads
    // of the spring loop, which then waits for them to retire.
    if (few.field == nullptr) {
#pragma GCC unroll 4
        for (std::size_t i = 0; i < kFewSpringParticles; ++i) {
            if (i < n) a0[i] = a1[i] = a2[i] = 0.0;
        }
    } else {
        const UniformField& g = *few.field;
        auto field = [&](auto quadratic) {
#pragma GCC unroll 4
            for (std::size_t i = 0; i < kFewSpringParticles; ++i) {
                if (i >= n) break;
                const FieldForce f = field_force<decltype(quadratic)::value>(mass[i], v.c[0][i], v.c[1][i], v.c[2][i],
                                                                             g.g.x(), g.g.y(), g.g.z(), g.c, g.c2);
                a0[i] = f.x, a1[i] = f.y, a2[i] = f.z;
            }
        };
        g.c2 != 0.0 ? field(std::true_type{}) : field(std::false_type{});
    }
    accumulate(*few.springs, ForceInput{t, first, x, v, mass, inv_mass}, a);
#pragma GCC unroll 4
    for (std::size_t i = 0; i < kFewSpringParticles; ++i) {
        if (i >= n) break;
        a0[i] *= inv_mass[i];
        a1[i] *= inv_mass[i];
        a2[i] *= inv_mass[i];
    }
}

}  // namespace

void ParticleForces::sum_forces(const ForceInput& in, const Vec3Span& f, bool skip_pinned) const {
    add_forces(in, f, skip_pinned, false);
}

// sum_forces, inlined into acceleration: on one particle on one spring the
// calls cost as much as the force.
[[gnu::always_inline]] inline bool ParticleForces::add_forces(const ForceInput& in, const Vec3Span& f, bool skip_pinned,
                                                              bool to_acceleration) const {
    const bool fold = to_acceleration && springs_last_;
    const SpringFinish finish{.from_zero = fold && !has_field_ && others_.size() == 1, .to_acceleration = fold};
    if (has_field_) {
        field_pass(in, f, false);
    } else if (!finish.from_zero) {
        zero(f);
    }
    for (std::size_t k = 0; k < others_.size(); ++k) {
        if (const auto* springs = std::get_if<Springs>(others_[k])) {
            const auto start = spring_time_ ? SpringClock::now() : SpringClock::time_point{};
            if (plans_[k].few) {
                accumulate(*springs, in, f);  // what the fast pass would fall back to (no call on the way)
            } else {
                accumulate(*springs, plans_[k], in, f, skip_pinned, k + 1 == others_.size() ? finish : SpringFinish{});
            }
            if (spring_time_) {
                spring_time_->seconds += std::chrono::duration<double>(SpringClock::now() - start).count();
                spring_time_->reads += 2;
            }
        } else {
            std::visit([&](const auto& g) { accumulate(g, in, f); }, *others_[k]);
        }
    }
    return fold;
}

// A fixed attractor alone (a swarm of test particles; with a field or not):
// its pass also applies M⁻¹, and starts from zero itself when there is no
// field (one pass instead of zero, accumulate and scale). Out of line: the
// spring path's fixed cost stays as it was.
[[gnu::noinline]] void ParticleForces::central_acceleration(const ForceInput& in, const Vec3Span& a) const {
    if (has_field_) field_pass(in, a, false);
    to_acceleration(*central_only_, in, a, !has_field_, wide_);
}

void ParticleForces::acceleration(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                                  const Vec3Span& a) {
    particle_evaluations_ += x.n;
    // One particle on one spring (the report's oscillators), a few beads on a
    // few springs, a planet around a pinned sun (the report's Kepler orbits):
    // on so small a system the general path's dispatch (the generator list,
    // the plan, the spring clock, the widths) costs as much as the force. The
    // same operations on each particle as that path.
    if (const SpringPair* pair = spring_pair(x.n)) {
        pair::spring_acceleration(*pair, x.c, v.c, mass_->data() + first, inv_mass_->data() + first, a.c);
        return;
    }
    if (const FewSprings* few = few_springs(x.n)) {
        few_spring_acceleration(*few, t, first, x, v, mass_->data() + first, inv_mass_->data() + first, a);
        return;
    }
    if (pair_gravity_.gravity != nullptr && x.n == 2) {  // (not local: x is the whole system)
        pair::gravity_acceleration(pair_gravity_, x.c, v.c, mass_->data() + first, inv_mass_->data() + first, a.c);
        return;
    }
    general_acceleration(input(t, first, x, v), a);
}

[[gnu::noinline]] void ParticleForces::general_acceleration(const ForceInput& in, const Vec3Span& a) const {
    if (others_.empty() && has_field_) {
        field_pass(in, a, true);  // one pass: force and M⁻¹ together
        return;
    }
    if (central_only_ != nullptr) {
        central_acceleration(in, a);
        return;
    }
    // A pinned particle's acceleration is its force times 0: the spring pass
    // may leave its sum out (see accumulate's skip_pinned).
    if (add_forces(in, a, true, true)) return;
    run_at_width(
        wide_ && a.n > kFew, [](auto... p) { scale_by_inverse_mass(p...); }, a.c[0], a.c[1], a.c[2], in.inv_mass, a.n);
}

void ParticleForces::force_and_jacobians(double t, std::size_t first, const ConstVec3Span& x, const ConstVec3Span& v,
                                         const Vec3Span& f, Jacobians& jac) {
    const ForceInput in = input(t, first, x, v);
    sum_forces(in, f, false);
    for (const ForceDef& force : *forces_) {
        std::visit([&](const auto& g) { accumulate_jacobians(g, in, jac); }, force);
    }
    particle_evaluations_ += x.n;
}

double ParticleForces::potential_energy(double t, ConstVec3Span x, ConstVec3Span v) const {
    const ForceInput in = input(t, 0, x, v);
    double u = 0.0;
    for (const ForceDef& force : *forces_) {
        u += std::visit([&](const auto& g) { return sim::potential_energy(g, in); }, force);
    }
    return u;
}

}  // namespace sim
