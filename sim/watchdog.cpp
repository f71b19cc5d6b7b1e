#include "sim/watchdog.h"

#include "sim/cpu.h"
#include "sim/error.h"
#include "sim/rigid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

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

namespace {

// The quick pass's loop, built twice below. Comparisons and products are
// exact at any vector width, and it only counts: both builds agree.
[[gnu::always_inline]] inline std::size_t suspect_loop(const double* x0, const double* x1, const double* x2,
                                                       const double* v0, const double* v1, const double* v2,
                                                       std::size_t n, double max_speed2, double box) {
    std::size_t passed = 0;  // a count, not a bool: GCC vectorises the loop only so
    for (std::size_t i = 0; i < n; ++i) {
        passed += passes(x0[i], x1[i], x2[i], v0[i], v1[i], v2[i], max_speed2, box);
    }
    return n - passed;
}

using SuspectLoop = std::size_t (*)(const double*, const double*, const double*, const double*, const double*,
                                    const double*, std::size_t, double, double);

template <typename... A>
std::size_t suspects_base(A... a) {
    return suspect_loop(a...);
}

#if defined(__x86_64__) && defined(__GNUC__)
// Twice as wide where the CPU has AVX2 (chosen at run time, as the spring pass).
template <typename... A>
[[gnu::target("avx2")]] std::size_t suspects_avx2(A... a) {
    return suspect_loop(a...);
}
#endif

SuspectLoop suspect_pass() {
    static const SuspectLoop pass = [] {
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx2_available())
            return &suspects_avx2<const double*, const double*, const double*, const double*, const double*,
                                  const double*, std::size_t, double, double>;
#endif
        return &suspects_base<const double*, const double*, const double*, const double*, const double*, const double*,
                              std::size_t, double, double>;
    }();
    return pass;
}

}  // namespace

std::size_t count_suspects(const WatchdogLimits& limits, const ConstVec3Span& x, const ConstVec3Span& v) {
    auto count_all = [&] {
        return suspect_pass()(x.c[0], x.c[1], x.c[2], v.c[0], v.c[1], v.c[2], x.n, limits.max_speed * limits.max_speed,
                              limits.world_half_extent);
    };
    // A few particles (one on a spring is a whole step of ~50 ns): one at a
    // time, leaving at the first suspect to count them all. No vector loop:
    // its loads of coordinates the step has just stored one by one would
    // wait for those stores.
    constexpr std::size_t kSmall = 4;
    if (x.n <= kSmall) {
        for (std::size_t i = 0; i < x.n; ++i) {
            if (is_suspect(x.c[0][i], x.c[1][i], x.c[2][i], v.c[0][i], v.c[1][i], v.c[2][i],
                           limits.max_speed * limits.max_speed, limits.world_half_extent)) {
                return count_all();
            }
        }
        return 0;
    }
    return count_all();
}

Verdict check(const WatchdogLimits& limits, const ParticleState& state, double energy, double initial_energy,
              std::uint64_t frame, std::optional<std::size_t> suspects) {
    if (!limits.enabled) return {};
    // The quick pass only flags; the slow path below finds which rule and
    // which particle, in the documented order, when anything is off.
    if (!suspects) suspects = count_suspects(limits, state.x.span(), state.v.span());
    if (*suspects > 0) {
        const Verdict found = first_violation(
            limits, state.size(), [&](std::size_t i) { return state.x.get(i); },
            [&](std::size_t i) { return state.v.get(i); }, frame);
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
                     const std::vector<Vec3>& velocities, std::uint64_t frame,
                     const std::vector<Vec3>& angular_velocities) {
    // ODE cannot place a body past kMaxBodyReach (it aborts): watchdog or not, that stops the run.
    WatchdogLimits held = limits;
    if (!limits.enabled) held.max_speed = std::numeric_limits<double>::max(), held.world_half_extent = kMaxBodyReach;
    held.world_half_extent = std::min(held.world_half_extent, kMaxBodyReach);
    Verdict v = first_violation(
        held, positions.size(), [&](std::size_t i) { return positions[i]; },
        [&](std::size_t i) { return velocities[i]; }, frame);
    for (std::size_t i = 0; i < angular_velocities.size() && !v.exploded(); ++i) {
        const double spin = angular_velocities[i].norm();
        if (!(spin <= kMaxBodySpin)) v = exploded(frame, "spin", i, spin, kMaxBodySpin);
    }
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
    if (quantity == "spin") {
        return text + subject + " " + std::to_string(index) + " spins at " + short_value(value) + " rad/s > " +
               short_value(limit) + " rad/s, past what ODE can step";
    }
    if (quantity == "bounds") {
        return text + subject + " " + std::to_string(index) + " is " + short_value(value) +
               " m from the origin along an axis, outside the world box (" + short_value(limit) + " m)";
    }
    return text + "energy " + short_value(value) + " J > " + short_value(limit) +
           " J (E0 = " + short_value(initial_energy) + " J)";
}

}  // namespace sim
