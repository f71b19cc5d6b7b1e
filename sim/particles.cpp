#include "sim/particles.h"

#include "sim/error.h"

#include <charconv>
#include <cmath>
#include <string>

namespace sim {

std::string format_value(double value) {
    char buffer[64];
    auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

namespace {

std::string expectation(const char* what, const std::string& unit) {
    return std::string(what) + (unit.empty() ? "" : ", in " + unit);
}

}  // namespace

void require_positive(double value, const std::string& name, const std::string& unit) {
    if (!(value > 0.0) || !std::isfinite(value)) {
        throw InputError(name + " must be " + expectation("> 0 and finite", unit) + " (got " + format_value(value) +
                         ")");
    }
}

void require_nonnegative(double value, const std::string& name, const std::string& unit) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
        throw InputError(name + " must be " + expectation(">= 0 and finite", unit) + " (got " + format_value(value) +
                         ")");
    }
}

namespace {

bool is_finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

std::string format_vec(const Vec3& p) {
    return "[" + format_value(p.x()) + ", " + format_value(p.y()) + ", " + format_value(p.z()) + "]";
}

}  // namespace

void validate_particles(const std::vector<ParticleDef>& particles) {
    for (std::size_t i = 0; i < particles.size(); ++i) {
        const ParticleDef& p = particles[i];
        const std::string name = "particles[" + std::to_string(i) + "]";
        if (!(p.mass > 0.0) || !std::isfinite(p.mass)) {
            throw InputError(name + ".mass must be > 0 and finite, in kg (got " + format_value(p.mass) + ")");
        }
        if (!is_finite(p.position)) {
            throw InputError(name + ".position must be finite, in m (got " + format_vec(p.position) + ")");
        }
        if (!(p.radius >= 0.0) || !std::isfinite(p.radius)) {
            throw InputError(name + ".radius must be >= 0 and finite, in m (got " + format_value(p.radius) + ")");
        }
        if (!is_finite(p.velocity)) {
            throw InputError(name + ".velocity must be finite, in m/s (got " + format_vec(p.velocity) + ")");
        }
    }
}

ParticleState make_state(const std::vector<ParticleDef>& particles) {
    const std::size_t n = particles.size();
    ParticleState s;
    s.x.resize(n);
    s.v.resize(n);
    s.mass.resize(n);
    s.inv_mass.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const ParticleDef& p = particles[i];
        s.x.set(i, p.position);
        s.v.set(i, p.pinned ? Vec3::Zero() : p.velocity);
        s.mass[i] = p.mass;
        s.inv_mass[i] = p.pinned ? 0.0 : 1.0 / p.mass;
    }
    return s;
}

}  // namespace sim
