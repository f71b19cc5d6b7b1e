#include "sim/forces.h"

#include <algorithm>

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
    all_local_ = std::all_of(forces.begin(), forces.end(), [](const ForceDef& force) {
        return std::visit([](const auto& g) { return is_local(g); }, force);
    });
}

ForceInput ParticleForces::input(double t, std::size_t first, ConstVec3Span x, ConstVec3Span v) const {
    return {t, first, x, v, mass_->data() + first, inv_mass_->data() + first};
}

void ParticleForces::sum_forces(const ForceInput& in, Vec3Span f) const {
    for (int k = 0; k < 3; ++k) {
        std::fill(f.c[k], f.c[k] + f.n, 0.0);
    }
    for (const ForceDef& force : *forces_) {
        std::visit([&](const auto& g) { accumulate(g, in, f); }, force);
    }
}

void ParticleForces::acceleration(double t, std::size_t first, ConstVec3Span x, ConstVec3Span v, Vec3Span a) {
    const ForceInput in = input(t, first, x, v);
    sum_forces(in, a);
    for (int k = 0; k < 3; ++k) {
        double* ak = a.c[k];
        for (std::size_t i = 0; i < a.n; ++i) {
            ak[i] *= in.inv_mass[i];
        }
    }
    particle_evaluations_ += x.n;
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
