// RigidWorld's contacts: which pairs of geoms may collide (not bodies one or
// two joints apart, not asleep against static), and the contact joints'
// surface parameters.
#include "sim/error.h"
#include "sim/rigid_impl.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>

namespace sim {

using rigid_detail::to_vec;

namespace {

constexpr int kMaxContacts = 4;  // per colliding pair of geoms

// How fast the two bodies close along the contact's normal, m/s (ODE's
// normal points into body a, from b; a missing body is the static world).
double closing_speed(const dContactGeom& c, dBodyID a, dBodyID b) {
    dVector3 va = {0, 0, 0}, vb = {0, 0, 0};
    if (a != nullptr) dBodyGetPointVel(a, c.pos[0], c.pos[1], c.pos[2], va);
    if (b != nullptr) dBodyGetPointVel(b, c.pos[0], c.pos[1], c.pos[2], vb);
    return -((va[0] - vb[0]) * c.normal[0] + (va[1] - vb[1]) * c.normal[1] + (va[2] - vb[2]) * c.normal[2]);
}

}  // namespace

std::uint32_t RigidWorld::Impl::index_of(dBodyID body) {
    return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(dBodyGetData(body)));
}

// Bodies one or two joints apart do not collide (parent and child,
// grandparent and grandchild, siblings): in a ragdoll their shapes meet
// at every joint and the contacts fight the joints, so that a ragdoll
// at rest creeps and never sleeps (Jolt's ragdolls filter the same
// pairs). Farther bodies (a hand and a thigh) collide.
bool RigidWorld::Impl::jointed_within_two(dBodyID a, dBodyID b) {
    if (dAreConnectedExcluding(a, b, dJointTypeContact)) return true;
    const int n = dBodyGetNumJoints(a);
    for (int k = 0; k < n; ++k) {
        const dJointID j = dBodyGetJoint(a, k);
        if (dJointGetType(j) == dJointTypeContact) continue;
        for (int side = 0; side < 2; ++side) {
            const dBodyID middle = dJointGetBody(j, side);
            if (middle != nullptr && middle != a && dAreConnectedExcluding(middle, b, dJointTypeContact)) return true;
        }
    }
    return false;
}

// ODE's broad phase calls this for each pair of geoms whose boxes overlap.
void RigidWorld::Impl::near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<Impl*>(data);
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    // Nothing to do unless one side moves: static against static, asleep
    // against asleep or static.
    const bool moving_a = ba != nullptr && dBodyIsEnabled(ba), moving_b = bb != nullptr && dBodyIsEnabled(bb);
    if (!moving_a && !moving_b) return;
    if (ba == bb) return;  // parts of one compound body
    if (ba != nullptr && bb != nullptr) {
        if (self->settings.self_collision ? jointed_within_two(ba, bb)
                                          : self->group_of[index_of(ba)] == self->group_of[index_of(bb)]) {
            return;
        }
    }
    dContact contact[kMaxContacts];
    const int n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
    if (n == 0) return;
    // An awake body touching a sleeping one: a gentle touch (the awake
    // body itself slow enough to sleep) meets the sleeper as static
    // ground, so that the solver's jitter in a pile does not wake what
    // has settled, over and over; a real blow wakes it (and, through
    // its joints, its whole group).
    if (moving_a != moving_b && ba != nullptr && bb != nullptr) {
        const dBodyID awake = moving_a ? ba : bb, asleep = moving_a ? bb : ba;
        if (self->slow(awake)) {
            (moving_a ? bb : ba) = nullptr;
        } else {
            dBodyEnable(asleep);
        }
    }
    for (int i = 0; i < n; ++i) {
        dSurfaceParameters& s = contact[i].surface;
        // Slip is ODE's CFM on the friction rows (which else take the world's,
        // the joints' 0): as soft as the normal row, which keeps a stack still.
        s.mode = dContactBounce | dContactApprox1 | dContactSoftERP | dContactSoftCFM | dContactSlip1 | dContactSlip2;
        s.slip1 = s.slip2 = self->settings.contact_cfm;
        s.mu = self->settings.friction;
        s.bounce = self->settings.restitution;
        s.bounce_vel = self->settings.bounce_velocity;
        s.soft_erp = self->settings.contact_erp;
        // An impact (closing faster than bounce_velocity) is a rigid row: a
        // soft one gives back less than e, more so the smaller the step (the
        // study's §3); a resting contact stays soft.
        s.soft_cfm =
            closing_speed(contact[i].geom, ba, bb) > self->settings.bounce_velocity ? 0.0 : self->settings.contact_cfm;
        dJointID j = dJointCreateContact(self->world, self->contact_group, &contact[i]);
        dJointAttach(j, ba, bb);
        ++self->contacts;
    }
    for (const dBodyID body : {ba, bb}) {
        if (body != nullptr) self->slots[index_of(body)].touched = true;
    }
}

void RigidWorld::Impl::begin_step() {
    for (Slot& s : slots) {
        if (s.body == nullptr) continue;
        s.before = to_vec(dBodyGetPosition(s.body));
        s.touched = false;
    }
}

void RigidWorld::Impl::sweep() {
    if (statics.empty()) return;
    for (Slot& s : slots) {
        if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
        double thinnest = kMaxBodySize;  // m, half extent or radius
        for (const BodyPart& p : s.parts) {
            thinnest = std::min(thinnest, p.shape == RigidShape::box ? 0.5 * p.size.minCoeff() : p.size.x());
        }
        const Vec3 to = to_vec(dBodyGetPosition(s.body));
        const double travel = (to - s.before).norm();  // m
        if (travel <= 0.5 * thinnest) continue;        // the contacts see it
        const Vec3 dir = (to - s.before) / travel;
        dGeomRaySetLength(ray, travel);
        dGeomRaySet(ray, s.before.x(), s.before.y(), s.before.z(), dir.x(), dir.y(), dir.z());
        double nearest = travel;  // m along the ray
        Vec3 normal = Vec3::Zero();
        for (const dGeomID g : statics) {
            dContactGeom hit;
            if (dCollide(ray, g, 1, &hit, sizeof hit) > 0 && hit.depth < nearest) {
                nearest = hit.depth;
                normal = to_vec(hit.normal);
            }
        }
        if (normal == Vec3::Zero()) continue;
        if (normal.dot(dir) > 0.0) normal = -normal;  // facing where it came from
        const Vec3 x = s.before + nearest * dir + thinnest * normal;
        Vec3 v = to_vec(dBodyGetLinearVel(s.body));
        const double vn = v.dot(normal);  // m/s, < 0: into the surface
        if (vn < 0.0) v -= (1.0 + (-vn > settings.bounce_velocity ? settings.restitution : 0.0)) * vn * normal;
        dBodySetPosition(s.body, x.x(), x.y(), x.z());
        dBodySetLinearVel(s.body, v.x(), v.y(), v.z());
    }
}

}  // namespace sim
