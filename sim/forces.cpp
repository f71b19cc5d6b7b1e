#include "sim/forces.h"

#include <algorithm>
#include <cmath>

namespace sim {

namespace {

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};

}  // namespace

const char* force_name(const ForceDef& force) {
    return std::visit(Overloaded{
                          [](const UniformGravity&) { return "gravity"; },
                          [](const NewtonGravity&) { return "newton_gravity"; },
                          [](const Springs&) { return "springs"; },
                          [](const LinearDrag&) { return "linear_drag"; },
                          [](const QuadraticDrag&) { return "quadratic_drag"; },
                      },
                      force);
}

void validate_forces(const std::vector<ForceDef>& forces, std::size_t particle_count) {
    for (const ForceDef& force : forces) {
        std::visit([&](const auto& g) { validate(g, particle_count); }, force);
    }
}

ParticleForces::ParticleForces(const std::vector<ForceDef>& forces, const std::vector<double>& mass,
                               const std::vector<double>& inv_mass)
    : forces_(&forces), mass_(&mass), inv_mass_(&inv_mass) {
    for (const ForceDef& force : forces) {
        all_local_ = all_local_ && std::visit([](const auto& g) { return is_local(g); }, force);
        if (const auto* gravity = std::get_if<UniformGravity>(&force)) {
            field_.g += gravity->g;
        } else if (const auto* drag = std::get_if<LinearDrag>(&force)) {
            field_.c += drag->c;
        } else if (const auto* drag2 = std::get_if<QuadraticDrag>(&force)) {
            field_.c2 += drag2->c;
        } else {
            others_.push_back(&force);
            continue;
        }
        has_field_ = true;
    }
}

ForceInput ParticleForces::input(double t, std::size_t first, ConstVec3Span x, ConstVec3Span v) const {
    return {t, first, x, v, mass_->data() + first, inv_mass_->data() + first};
}

namespace {

// The field loop, compiled once per case so that neither the square root of
// quadratic drag nor the inverse-mass multiply costs anything when unused.
template <bool kQuadratic, bool kToAcceleration>
void field_loop(const ForceInput& in, Vec3Span out, const Vec3& g, double c, double c2) {
    const double* vx = in.v.c[0];
    const double* vy = in.v.c[1];
    const double* vz = in.v.c[2];
    const double* m = in.mass;
    const double* inv_m = in.inv_mass;
    double* ox = out.c[0];
    double* oy = out.c[1];
    double* oz = out.c[2];
    const double gx = g.x(), gy = g.y(), gz = g.z();
    for (std::size_t i = 0; i < out.n; ++i) {
        double drag = c;
        if constexpr (kQuadratic) {
            drag += c2 * std::sqrt(vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]);
        }
        double fx = m[i] * gx - drag * vx[i];
        double fy = m[i] * gy - drag * vy[i];
        double fz = m[i] * gz - drag * vz[i];
        if constexpr (kToAcceleration) {
            fx *= inv_m[i];
            fy *= inv_m[i];
            fz *= inv_m[i];
        }
        ox[i] = fx;
        oy[i] = fy;
        oz[i] = fz;
    }
}

}  // namespace

void ParticleForces::field_pass(const ForceInput& in, Vec3Span out, bool to_acceleration) const {
    const bool quadratic = field_.c2 != 0.0;
    if (quadratic && to_acceleration) {
        field_loop<true, true>(in, out, field_.g, field_.c, field_.c2);
    } else if (quadratic) {
        field_loop<true, false>(in, out, field_.g, field_.c, field_.c2);
    } else if (to_acceleration) {
        field_loop<false, true>(in, out, field_.g, field_.c, field_.c2);
    } else {
        field_loop<false, false>(in, out, field_.g, field_.c, field_.c2);
    }
}

void ParticleForces::sum_forces(const ForceInput& in, Vec3Span f) const {
    if (has_field_) {
        field_pass(in, f, false);
    } else {
        for (int k = 0; k < 3; ++k) {
            std::fill(f.c[k], f.c[k] + f.n, 0.0);
        }
    }
    for (const ForceDef* force : others_) {
        std::visit([&](const auto& g) { accumulate(g, in, f); }, *force);
    }
}

void ParticleForces::acceleration(double t, std::size_t first, ConstVec3Span x, ConstVec3Span v, Vec3Span a) {
    const ForceInput in = input(t, first, x, v);
    particle_evaluations_ += x.n;
    if (others_.empty() && has_field_) {
        field_pass(in, a, true);  // one pass: force and M⁻¹ together
        return;
    }
    sum_forces(in, a);
    for (int k = 0; k < 3; ++k) {
        double* ak = a.c[k];
        for (std::size_t i = 0; i < a.n; ++i) {
            ak[i] *= in.inv_mass[i];
        }
    }
}

void ParticleForces::force_and_jacobians(double t, std::size_t first, ConstVec3Span x, ConstVec3Span v, Vec3Span f,
                                         Jacobians& jac) {
    const ForceInput in = input(t, first, x, v);
    sum_forces(in, f);
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
