#include "sim/shock_wave.h"

#include "sim/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace sim {

void validate(const ShockWave& s, std::size_t) {
    if (!s.center.allFinite()) {
        throw InputError("shock_wave.center must be finite, in m (got " + format_value(s.center.x()) + ", " +
                         format_value(s.center.y()) + ", " + format_value(s.center.z()) + ")");
    }
    require_positive(s.speed, "shock_wave.speed", "m/s");
    require_positive(s.thickness, "shock_wave.thickness", "m");
    require_positive(s.reference_distance, "shock_wave.reference_distance", "m");
    if (!std::isfinite(s.start_time)) {
        throw InputError("shock_wave.start_time must be finite, in s (got " + format_value(s.start_time) + ")");
    }
    if (!(s.strength >= 0.0) || !std::isfinite(s.strength)) {
        throw InputError("shock_wave.strength must be >= 0 and finite, in N (got " + format_value(s.strength) + ")");
    }
    if (!(s.max_radius >= 0.0) || !std::isfinite(s.max_radius)) {
        throw InputError("shock_wave.max_radius must be >= 0 and finite, in m (got " + format_value(s.max_radius) +
                         ")");
    }
}

void accumulate(const ShockWave& s, const ForceInput& in, Vec3Span f) {
    if (in.t < s.start_time) return;
    const double front = s.speed * (in.t - s.start_time);
    const double half = 0.5 * s.thickness;
    if (s.max_radius > 0.0 && front - half > s.max_radius) return;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const Vec3 d = in.x.get(i) - s.center;
        const double r = d.norm();
        if (r == 0.0 || std::abs(r - front) >= half) continue;  // at the centre there is no outward
        if (s.max_radius > 0.0 && r > s.max_radius) continue;
        // Inverse-square fall-off, capped inside reference_distance, along
        // d / r. strength / r can overflow only for r within ~1e-300 m of the
        // centre; there the unit direction is formed first. (Elsewhere the
        // first form stays: the goldens' state hashes were recorded with it.)
        const double ratio = s.reference_distance / std::max(r, s.reference_distance);
        const double scale = s.strength * ratio * ratio / r;  // N/m
        f.add(i, std::isfinite(scale) ? Vec3(scale * d) : Vec3((s.strength * ratio * ratio) * (d / r)));
    }
}

}  // namespace sim
