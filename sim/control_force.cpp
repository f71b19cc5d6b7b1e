#include "sim/control_force.h"

#include "sim/error.h"

#include <cmath>
#include <string>

namespace sim {

void validate(const ControlForces& c, std::size_t particle_count) {
    for (std::size_t k = 0; k < c.keys.size(); ++k) {
        const ControlKey& key = c.keys[k];
        const std::string name = "control.keys[" + std::to_string(k) + "]";
        if (!std::isfinite(key.start) || !std::isfinite(key.end) || !(key.end > key.start)) {
            throw InputError(name + " must have start < end, finite, in s (got " + format_value(key.start) + " .. " +
                             format_value(key.end) + ")");
        }
        if (!key.force.allFinite()) {
            throw InputError(name + ".force must be finite, in N (got " + format_value(key.force.x()) + ", " +
                             format_value(key.force.y()) + ", " + format_value(key.force.z()) + ")");
        }
        for (std::uint32_t p : key.particles) {
            if (p >= particle_count) {
                throw InputError(name + " pushes particle " + std::to_string(p) + ", but there are only " +
                                 std::to_string(particle_count));
            }
        }
    }
}

void accumulate(const ControlForces& c, const ForceInput& in, Vec3Span f) {
    for (const ControlKey& key : c.keys) {
        if (in.t < key.start || in.t >= key.end) continue;
        for (std::uint32_t p : key.particles) {
            if (p >= in.first && p - in.first < in.x.n) f.add(p - in.first, key.force);  // in this block
        }
    }
}

}  // namespace sim
