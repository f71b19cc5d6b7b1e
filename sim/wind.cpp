#include "sim/wind.h"

#include "sim/error.h"
#include "sim/random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace sim {

namespace {

// Key k's gust: three normal draws from a generator seeded by (seed, k) alone.
Vec3 gust_key(const Wind& w, std::int64_t k) {
    Random r(w.seed ^ (0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(k + 1)));
    const double gx = r.normal(), gy = r.normal(), gz = r.normal();
    return w.gust_strength * Vec3(gx, gy, gz);
}

}  // namespace

Vec3 wind_at(const Wind& w, double t) {
    if (w.gust_strength == 0.0) return w.velocity;
    const double u = t / w.gust_period;
    // The key before t, clamped to ±2^62 (NaN to the lower end) before it
    // becomes an integer, so that no conversion overflows. Beyond 2^53
    // periods (a gust period far below the step) a double has no fraction
    // left and the gust holds still.
    constexpr double kLastKey = 0x1p62;
    const double key = u >= -kLastKey ? std::min(std::floor(u), kLastKey) : -kLastKey;
    const auto k = static_cast<std::int64_t>(key);
    const double s = std::clamp(u - key, 0.0, 1.0);
    const double ease = s * s * (3.0 - 2.0 * s);  // smoothstep: zero slope at both keys
    const Vec3 a = gust_key(w, k), b = gust_key(w, k + 1);
    return w.velocity + a + ease * (b - a);
}

void validate(const Wind& w, std::size_t particle_count) {
    if (!w.velocity.allFinite()) {
        throw InputError("wind.velocity must be finite, in m/s (got " + format_value(w.velocity.x()) + ", " +
                         format_value(w.velocity.y()) + ", " + format_value(w.velocity.z()) + ")");
    }
    require_nonnegative(w.air_density, "wind.air_density", "kg/m³");
    require_nonnegative(w.drag_coefficient, "wind.drag_coefficient", "");
    require_nonnegative(w.radius, "wind.radius", "m");
    require_nonnegative(w.gust_strength, "wind.gust_strength", "m/s");
    require_positive(w.gust_period, "wind.gust_period", "s");
    auto check = [&](std::uint32_t p, const std::string& what) {
        if (p >= particle_count) {
            throw InputError("wind." + what + " names particle " + std::to_string(p) + ", but there are only " +
                             std::to_string(particle_count));
        }
    };
    for (std::size_t k = 0; k < w.triangles.size(); ++k) {
        for (std::uint32_t p : w.triangles[k]) check(p, "triangles[" + std::to_string(k) + "]");
    }
    for (std::size_t k = 0; k < w.particles.size(); ++k) check(w.particles[k], "particles[" + std::to_string(k) + "]");
}

void accumulate(const Wind& w, const ForceInput& in, Vec3Span f) {
    const Vec3 wind = wind_at(w, in.t);
    const double half_rho_cd = 0.5 * w.air_density * w.drag_coefficient;
    for (const auto& [a, b, c] : w.triangles) {  // with triangles the block is the whole system (first = 0)
        const Vec3 xa = in.x.get(a), xb = in.x.get(b), xc = in.x.get(c);
        const Vec3 cross = (xb - xa).cross(xc - xa);  // |cross| = 2 A
        const double twice_area = cross.norm();
        if (twice_area == 0.0) continue;  // a degenerate triangle has no face to push
        const Vec3 n = cross / twice_area;
        const Vec3 u = wind - (in.v.get(a) + in.v.get(b) + in.v.get(c)) / 3.0;
        const double un = u.dot(n);
        const Vec3 third = (half_rho_cd * 0.5 * twice_area * un * std::abs(un) / 3.0) * n;
        f.add(a, third);
        f.add(b, third);
        f.add(c, third);
    }
    // Lone particles: global indices, of which a block (when the wind is
    // local) holds those in [first, first + n).
    const double section = std::numbers::pi * w.radius * w.radius;
    for (std::uint32_t p : w.particles) {
        if (p < in.first || p - in.first >= in.x.n) continue;
        const std::size_t i = p - in.first;
        const Vec3 u = wind - in.v.get(i);
        f.add(i, (half_rho_cd * section * u.norm()) * u);
    }
}

}  // namespace sim
