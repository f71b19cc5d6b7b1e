// RigidWorld's sleep, by group of jointed bodies (a ragdoll sleeps whole):
// union-find groups, their smoothed energy and displacement.
#include "sim/error.h"
#include "sim/rigid_impl.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sim {

using rigid_detail::to_vec;

// Slow enough to fall asleep: the body's group's smoothed kinetic energy
// per kilogram within sleep's limit, that of twice sleep_speed.
bool RigidWorld::Impl::slow(dBodyID body) const {
    const double v = 2.0 * settings.sleep_speed;
    return slots[index_of(body)].sleep_energy <= 0.5 * v * v;
}

std::uint32_t RigidWorld::Impl::find(std::uint32_t i) {
    while (group_of[i] != i) i = group_of[i] = group_of[group_of[i]];
    return i;
}

// The groups of bodies joined by joints (a ragdoll, a chain): union-find
// over the body slots, rebuilt every step (joints come and go).
void RigidWorld::Impl::build_groups() {
    group_of.resize(slots.size());
    for (std::uint32_t i = 0; i < slots.size(); ++i) group_of[i] = i;
    for (const JointSlot& js : joints) {
        if (js.joint == nullptr || js.def.b == BodyId{}) continue;
        const std::uint32_t ra = find(js.def.a.index), rb = find(js.def.b.index);
        group_of[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (std::uint32_t i = 0; i < slots.size(); ++i) find(i);  // flatten: group_of[i] is the root
}

// Kinetic energy of a body, ½ m v² + ½ ωᵀ I ω (J).
double RigidWorld::Impl::kinetic(const Slot& s) const {
    const dReal* q = dBodyGetQuaternion(s.body);
    const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    const Vec3 w = R.transpose() * to_vec(dBodyGetAngularVel(s.body));
    return 0.5 * s.mass * to_vec(dBodyGetLinearVel(s.body)).squaredNorm() + 0.5 * w.dot(s.inertia * w);
}

// How far a body has moved from its rest pose, weighted: m |Δx|² + Δθᵀ I Δθ
// (kg·m²), Δθ its turn in its own frame.
double RigidWorld::Impl::displacement(const Slot& s) const {
    const Vec3 dx = to_vec(dBodyGetPosition(s.body)) - s.rest_position;
    const dReal* q = dBodyGetQuaternion(s.body);
    const Eigen::AngleAxisd turn(s.rest_orientation.conjugate() * Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
    const Vec3 dtheta = turn.angle() * turn.axis();
    return s.mass * dx.squaredNorm() + dtheta.dot(s.inertia * dtheta);
}

// Sleep, by group of jointed bodies (a whole ragdoll, or one free body),
// both weighted by mass so that a light hand does not keep a 70 kg
// ragdoll awake:
//  - its kinetic energy per kilogram, smoothed over a quarter of
//    sleep_time, is under that of twice sleep_speed (½ (2 v)²), and
//  - it has not moved, since it became idle, farther than sleep_speed ·
//    sleep_time (the mass-weighted RMS of its bodies' displacements and
//    turns): the mean speed over the window, as ODE averages velocity
//    samples, so that the iterative solver's jitter in a pile (which
//    never stops, and averages to nothing) counts as rest and a slow
//    creep does not;
//  - hung from the world by a joint and touching nothing this step (no
//    jitter to forgive), its kinetic energy per kilogram now under that
//    of a tenth of sleep_speed.
// A group idle for sleep_time is disabled at rest. A group that ODE
// re-enabled (a contact, a joint to an awake body) starts again. Each
// body keeps its group's figures, so that body_states() carries them.
void RigidWorld::Impl::sleep(double h) {
    const double energy_limit = 2.0 * settings.sleep_speed * settings.sleep_speed;        // J/kg, ½ (2 v)²
    const double still_limit = 0.5 * 0.01 * settings.sleep_speed * settings.sleep_speed;  // J/kg, ½ (v/10)²
    const double reach = settings.sleep_speed * settings.sleep_time;                      // m
    const double blend = std::min(1.0, h / (0.25 * settings.sleep_time));
    // Steps idle before sleep, kept a double: sleep_time / h is any positive
    // number (1e300 s over 1 ms is 1e303 steps, no integer holds it; such a
    // group never sleeps, as asked), and idle_steps, a uint32, is compared
    // with it exactly.
    const double needed = std::ceil(settings.sleep_time / h);
    group_energy.assign(slots.size(), 0.0);
    group_moved.assign(slots.size(), 0.0);
    group_mass.assign(slots.size(), 0.0);
    group_woken.assign(slots.size(), 0);
    group_touched.assign(slots.size(), 0);
    group_hung.assign(slots.size(), 0);
    for (const JointSlot& js : joints) {
        if (js.joint != nullptr && js.def.b == BodyId{}) group_hung[find(js.def.a.index)] = 1;
    }
    for (std::uint32_t i = 0; i < slots.size(); ++i) {
        Slot& s = slots[i];
        if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
        const std::uint32_t root = find(i);
        group_energy[root] += kinetic(s);
        group_moved[root] += displacement(s);
        group_mass[root] += s.mass;
        if (s.asleep) group_woken[root] = 1;
        if (s.touched) group_touched[root] = 1;
        s.asleep = false;
    }
    for (std::uint32_t i = 0; i < slots.size(); ++i) {
        Slot& s = slots[i];
        if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
        const std::uint32_t root = find(i);
        if (root == i) {  // the group's lowest slot: visited before the others
            const double e = group_energy[root] / group_mass[root];
            const double moved = std::sqrt(group_moved[root] / group_mass[root]);
            s.sleep_energy = group_woken[root] != 0 ? e : s.sleep_energy + blend * (e - s.sleep_energy);
            // Hung from the world and touching nothing, a group has no
            // solver jitter to forgive: it must be still now (a swing is slow
            // only near its turns).
            const bool swinging = group_hung[root] != 0 && group_touched[root] == 0 && e > still_limit;
            if (group_woken[root] == 0 && s.idle_steps > 0 && moved <= reach && !swinging) {
                // Saturating, not wrapping to 0 (which would start a new
                // window): a window of 2³² steps or more then never ends.
                constexpr std::uint32_t kMost = std::numeric_limits<std::uint32_t>::max();
                if (s.sleep_energy <= energy_limit && s.idle_steps < kMost) ++s.idle_steps;
            } else {
                s.idle_steps = 1;  // a new window, from here
                group_woken[root] = 1;
            }
        } else {
            s.sleep_energy = slots[root].sleep_energy;
            s.idle_steps = slots[root].idle_steps;
        }
        if (group_woken[root] != 0) {  // woken, moved or new: the window starts here
            s.rest_position = to_vec(dBodyGetPosition(s.body));
            const dReal* q = dBodyGetQuaternion(s.body);
            s.rest_orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
        }
    }
    for (Slot& s : slots) {
        if (s.body == nullptr || !dBodyIsEnabled(s.body) || static_cast<double>(s.idle_steps) < needed) continue;
        dBodySetLinearVel(s.body, 0, 0, 0);
        dBodySetAngularVel(s.body, 0, 0, 0);
        dBodyDisable(s.body);
        s.asleep = true;
    }
}

}  // namespace sim
