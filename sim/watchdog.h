// The explosion watchdog (docs/design.md "Golden checks"): after every integrator
// step it looks for a non-finite state, a particle too fast, a particle out
// of the world box, or total energy grown past a factor of its initial value,
// and reports the first violation as a Verdict {frame, quantity, index, value}.
// World stops stepping once it has one: no garbage frames after a NaN.
#pragma once

#include "sim/particles.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sim {

// Particles whose explosion is part of the lesson (the stiff spring rope
// beside the XPBD one): when the first violation is one of theirs, the range
// is frozen where it was at the start of that substep (pinned, at rest) and
// the run goes on; the verdict is kept in World::contained().
struct ContainedRange {
    std::string name;         // what the messages call it ("spring rope")
    std::uint32_t first = 0;  // particles [first, first + count)
    std::uint32_t count = 0;
};

struct WatchdogLimits {
    bool enabled = true;
    double max_speed = 500.0;          // m/s; a particle faster than this has exploded
    double world_half_extent = 1.0e4;  // m; |x|, |y| or |z| beyond it is outside the world box (centred on the origin)
    // Energy growth: 0 is off (scenes whose energy may grow: driven, scripted).
    // Otherwise exploded when E - E0 > (energy_growth - 1) max(|E0|, energy_floor).
    double energy_growth = 0.0;
    double energy_floor = 1e-6;  // J; keeps the energy test meaningful when E0 is near 0
    // Contained explosions (see ContainedRange). The energy rule cannot say
    // which particles blew up, so it cannot be combined with them.
    std::vector<ContainedRange> contain;
};

// Throws InputError naming the field and value, e.g.
// "watchdog.max_speed must be > 0 and finite, in m/s (got -3)".
void validate(const WatchdogLimits& limits);

struct Verdict {
    enum class Status { ok, exploded };
    Status status = Status::ok;
    std::uint64_t frame = 0;           // the frame step (World::step call, 1-based) in which it was detected
    std::string quantity;              // "position" or "velocity" (non-finite), "speed", "bounds", "energy"
    std::string subject = "particle";  // what index counts: "particle" or "body"
    std::size_t index = 0;             // particle (or body) index; 0 for energy
    double value = 0.0;                // the offending value in the quantity's unit (m, m/s, J); NaN for non-finite
    double limit = 0.0;                // the limit it broke
    double initial_energy = 0.0;       // J, E0 (energy verdicts)

    bool exploded() const { return status == Status::exploded; }
    // "rope: exploded at frame 37: particle 12 speed 4.1e+06 m/s > 500 m/s"
    std::string message(std::string_view scene) const;
};

// The per-particle rules for one particle at x, v: it passes (1) when every
// coordinate is finite and within ±box and the speed² at most max_speed2
// (NaN fails every comparison, so a <= b is false for it); it is a suspect
// otherwise. Split in two for a method whose passes leave x and v final in
// different loops (Verlet's): each loop counts its half.
//
// The vectorised loops count passes and take suspects as the particles less
// the passes (0 exactly when every particle passes; with a split method, a
// particle may count twice). Counting the failures instead negates every
// mask, an instruction more for each four particles: 2-3% of backward
// Euler's whole step on 1e5 particles (150-153 against 147-151 µs, alternated).
inline int passes_position(double x, double y, double z, double box) {
    // & on ints, not &&: no branch, so the counting loop stays vectorised.
    return static_cast<int>(std::abs(x) <= box) & static_cast<int>(std::abs(y) <= box) &
           static_cast<int>(std::abs(z) <= box);
}
inline int passes_velocity(double vx, double vy, double vz, double max_speed2) {
    const double speed2 = vx * vx + vy * vy + vz * vz;
    return static_cast<int>(speed2 <= max_speed2);
}
inline int passes(double x, double y, double z, double vx, double vy, double vz, double max_speed2, double box) {
    return passes_velocity(vx, vy, vz, max_speed2) & passes_position(x, y, z, box);
}
inline bool is_suspect(double x, double y, double z, double vx, double vy, double vz, double max_speed2, double box) {
    return passes(x, y, z, vx, vy, vz, max_speed2, box) == 0;
}

// The per-particle rules' quick pass over a block: how many particles have a
// non-finite coordinate, a speed above the limit or a coordinate outside the
// world box. It only counts; check() finds which rule and which particle.
std::size_t count_suspects(const WatchdogLimits& limits, const ConstVec3Span& x, const ConstVec3Span& v);

// The first violation in a fixed order: a non-finite state (the lowest
// particle index first; its position before its velocity), then speed, then
// bounds (lowest index first), then energy. `energy`
// is only read when limits.energy_growth > 0. `suspects`: count_suspects
// over the whole state, when the caller has counted them already (the world
// does so block by block inside the integrator's pass); counted here if not.
Verdict check(const WatchdogLimits& limits, const ParticleState& state, double energy, double initial_energy,
              std::uint64_t frame, std::optional<std::size_t> suspects = std::nullopt);

// The same rules (non-finite, speed, bounds) for rigid bodies' centres of
// mass and velocities, body index order; the verdict's subject is "body".
// Whatever the limits, also what ODE can step (sim/rigid.h): a body past
// kMaxBodyReach, or spinning past kMaxBodySpin (quantity "spin"; checked
// where angular velocities are given), has exploded.
Verdict check_bodies(const WatchdogLimits& limits, const std::vector<Vec3>& positions,
                     const std::vector<Vec3>& velocities, std::uint64_t frame,
                     const std::vector<Vec3>& angular_velocities = {});

}  // namespace sim
