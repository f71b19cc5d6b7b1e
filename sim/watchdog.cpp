#include "sim/watchdog.h"

#include "sim/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sim {
namespace {

std::string short_value(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

Verdict exploded(std::uint64_t frame, const char* quantity, std::size_t index, double value, double limit) {
    Verdict v;
    v.status = Verdict::Status::exploded;
    v.frame = frame;
    v.quantity = quantity;
    v.index = index;
    v.value = value;
    v.limit = limit;
    return v;
}

// The per-item rules in their documented order over n items (particles or
// bodies): a non-finite state (lowest index first, position before
// velocity), then speed, then bounds. position(i) and velocity(i) give Vec3.
template <typename Position, typename Velocity>
Verdict first_violation(const WatchdogLimits& limits, std::size_t n, Position position, Velocity velocity,
                        std::uint64_t frame) {
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 x = position(i), v = velocity(i);
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(x[k])) return exploded(frame, "position", i, x[k], 0.0);
        }
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(v[k])) return exploded(frame, "velocity", i, v[k], 0.0);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double speed = velocity(i).norm();
        if (speed > limits.max_speed) return exploded(frame, "speed", i, speed, limits.max_speed);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double reach = position(i).cwiseAbs().maxCoeff();
        if (reach > limits.world_half_extent) return exploded(frame, "bounds", i, reach, limits.world_half_extent);
    }
    return {};
}

}  // namespace

void validate(const WatchdogLimits& limits) {
    require_positive(limits.max_speed, "watchdog.max_speed", "m/s");
    require_positive(limits.world_half_extent, "watchdog.world_half_extent", "m");
    require_positive(limits.energy_floor, "watchdog.energy_floor", "J");
    if (!std::isfinite(limits.energy_growth) || (limits.energy_growth != 0.0 && limits.energy_growth < 1.0)) {
        throw InputError("watchdog.energy_growth must be 0 (off) or >= 1 (got " + format_value(limits.energy_growth) +
                         ")");
    }
    if (!limits.contain.empty() && limits.energy_growth != 0.0) {
        throw InputError("watchdog.energy_growth must be 0 (off) when explosions are contained (" +
                         limits.contain.front().name + "): the energy rule cannot tell whose energy grew");
    }
}

Verdict check(const WatchdogLimits& limits, const ParticleState& state, double energy, double initial_energy,
              std::uint64_t frame) {
    if (!limits.enabled) return {};
    const std::size_t n = state.size();
    const double* x[3] = {state.x.span().c[0], state.x.span().c[1], state.x.span().c[2]};
    const double* v[3] = {state.v.span().c[0], state.v.span().c[1], state.v.span().c[2]};
    // One pass that only flags; the slow path below finds which rule and which
    // particle, in the documented order, when anything is off.
    const double speed2_limit = limits.max_speed * limits.max_speed;
    const double box = limits.world_half_extent;
    std::size_t suspect = 0;  // a count, not a bool: GCC vectorises the loop only so
    for (std::size_t i = 0; i < n; ++i) {
        const double s2 = v[0][i] * v[0][i] + v[1][i] * v[1][i] + v[2][i] * v[2][i];
        const double reach = std::max({std::abs(x[0][i]), std::abs(x[1][i]), std::abs(x[2][i])});
        // NaN fails both comparisons, so !(a <= b) also catches it.
        suspect += !(s2 <= speed2_limit) | !(reach <= box);
    }
    if (suspect > 0) {
        const Verdict found = first_violation(
            limits, n, [&](std::size_t i) { return state.x.get(i); }, [&](std::size_t i) { return state.v.get(i); },
            frame);
        if (found.exploded()) return found;
    }
    if (limits.energy_growth > 0.0) {
        const double allowed = (limits.energy_growth - 1.0) * std::max(std::abs(initial_energy), limits.energy_floor);
        if (!std::isfinite(energy) || energy - initial_energy > allowed) {
            Verdict verdict = exploded(frame, "energy", 0, energy, initial_energy + allowed);
            verdict.initial_energy = initial_energy;
            return verdict;
        }
    }
    return {};
}

Verdict check_bodies(const WatchdogLimits& limits, const std::vector<Vec3>& positions,
                     const std::vector<Vec3>& velocities, std::uint64_t frame) {
    if (!limits.enabled) return {};
    Verdict v = first_violation(
        limits, positions.size(), [&](std::size_t i) { return positions[i]; },
        [&](std::size_t i) { return velocities[i]; }, frame);
    v.subject = "body";
    return v;
}

std::string Verdict::message(std::string_view scene) const {
    std::string text = std::string(scene) + ": ";
    if (!exploded()) return text + "ok";
    text += "exploded at frame " + std::to_string(frame) + ": ";
    if (quantity == "position" || quantity == "velocity") {
        return text + subject + " " + std::to_string(index) + " " + quantity + " is " + short_value(value);
    }
    if (quantity == "speed") {
        return text + subject + " " + std::to_string(index) + " speed " + short_value(value) + " m/s > " +
               short_value(limit) + " m/s";
    }
    if (quantity == "bounds") {
        return text + subject + " " + std::to_string(index) + " is " + short_value(value) +
               " m from the origin along an axis, outside the world box (" + short_value(limit) + " m)";
    }
    return text + "energy " + short_value(value) + " J > " + short_value(limit) +
           " J (E0 = " + short_value(initial_energy) + " J)";
}

}  // namespace sim
