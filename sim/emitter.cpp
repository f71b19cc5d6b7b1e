#include "sim/emitter.h"

#include "sim/error.h"
#include "sim/random.h"
#include "sim/rotation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace sim {

namespace {

// The launch velocity of particle k's n-th birth.
Vec3 launch_velocity(const Emitter& e, std::uint32_t k, std::int64_t n) {
    Random r(e.seed ^ (0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(n) * e.count + k + 1)));
    // Uniform over the spherical cap of half-angle `cone` around +Z, then
    // rotated onto the direction: cos θ uniform in [cos cone, 1].
    const double cos_max = std::cos(e.cone * std::numbers::pi / 180.0);
    const double cos_t = 1.0 - r.uniform() * (1.0 - cos_max);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double phi = 2.0 * std::numbers::pi * r.uniform();
    const Vec3 local(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
    const Eigen::Quaterniond to_direction = rotation_from_z(e.direction);
    const double speed = e.speed * (1.0 + e.speed_jitter * (2.0 * r.uniform() - 1.0));
    return speed * (to_direction * local);
}

}  // namespace

void validate(const Emitter& e, std::size_t particle_count, std::size_t index) {
    const std::string name = "emitters[" + std::to_string(index) + "]";
    if (e.count == 0 || static_cast<std::size_t>(e.first) + e.count > particle_count) {
        throw InputError(name + " owns particles " + std::to_string(e.first) + " .. " +
                         std::to_string(static_cast<std::size_t>(e.first) + e.count) + ", but there are " +
                         std::to_string(particle_count));
    }
    if (!e.position.allFinite()) throw InputError(name + ".position must be finite, in m");
    if (!e.direction.allFinite() || std::abs(e.direction.norm() - 1.0) > 1e-9) {
        throw InputError(name + ".direction must be a unit vector");
    }
    require_positive(e.speed, name + ".speed", "m/s");
    require_positive(e.rate, name + ".rate", "particles/s");
    if (!(e.cone >= 0.0 && e.cone <= 180.0)) {
        throw InputError(name + ".cone must be within 0 .. 180, in degrees (got " + format_value(e.cone) + ")");
    }
    if (!(e.speed_jitter >= 0.0 && e.speed_jitter <= 1.0)) {
        throw InputError(name + ".speed_jitter must be within 0 .. 1 (got " + format_value(e.speed_jitter) + ")");
    }
}

Vec3 parked_position(const Emitter& e) { return e.position - Vec3(0.0, 100.0, 0.0); }

bool born(const Emitter& e, std::uint32_t k, double t) { return static_cast<double>(k) < t * e.rate; }

std::size_t emit(const Emitter& e, double t0, double t1, ParticleState& state) {
    // Births are at t = (k + n count) / rate: each index b = k + n count with
    // t0 <= b / rate < t1 (half-open, so consecutive steps share no birth).
    // The indices are counted in double, exact below 2^53: beyond it two
    // births share an index and the sequence is lost, so that is refused.
    constexpr double kExact = 0x1p53;  // births, the last index a double counts exactly
    const double b_first = std::max(std::ceil(t0 * e.rate), 0.0);
    const double b_end = std::ceil(t1 * e.rate);
    if (!(b_end <= kExact)) {
        throw InputError("emitter: " + format_value(b_end) + " births by t = " + format_value(t1) + " s (rate " +
                         format_value(e.rate) + "/s) are beyond 2^53, where a double no longer counts them");
    }
    if (!(b_end > b_first)) return 0;
    // A particle born twice in [t0, t1) keeps only its last birth (each sets
    // its x, v and inverse mass anew): of more than `count` births, only the
    // last `count` are made, with the same bits, so that a step of rate · h
    // births costs at most `count` of them (rate 1e7/s, h 10 s: 1e8).
    const auto end = static_cast<std::int64_t>(b_end);
    const auto first = std::max(static_cast<std::int64_t>(b_first), end - static_cast<std::int64_t>(e.count));
    for (std::int64_t b = first; b < end; ++b) {
        const auto k = static_cast<std::uint32_t>(b % e.count);
        const std::int64_t n = b / e.count;
        const std::size_t i = e.first + k;
        state.x.set(i, e.position);
        state.v.set(i, launch_velocity(e, k, n));
        state.inv_mass[i] = 1.0 / state.mass[i];
    }
    return static_cast<std::size_t>(b_end - b_first);
}

}  // namespace sim
