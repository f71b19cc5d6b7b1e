// RigidWorld's reduced-coordinate path (RigidSettings::articulated): trees
// hung from the world, found each step, leave ODE's step for articulated_step.
#include "sim/articulated.h"
#include "sim/rigid_impl.h"

#include <ode/ode.h>

#include <algorithm>
#include <vector>

namespace sim {

using rigid_detail::to_vec;

namespace {

// A joint articulated_step can take: a plain hinge or ball joint.
bool reducible(const JointDef& d) {
    const bool no_limit = !(d.lo <= d.hi) && !(d.lo2 <= d.hi2) && !(d.lo3 <= d.hi3);
    return (d.type == JointType::hinge || d.type == JointType::ball) && no_limit && d.motor_max_force == 0.0;
}

bool pushed(dBodyID b) {  // a force for this step (the viewer's drag)
    return to_vec(dBodyGetForce(b)) != Vec3::Zero() || to_vec(dBodyGetTorque(b)) != Vec3::Zero();
}

// The joint's anchor as body `side` (0 or 1) of the joint places it, world frame.
Vec3 anchor_of(dJointID j, JointType type, int side) {
    dVector3 p;
    if (type == JointType::hinge) {
        side == 0 ? dJointGetHingeAnchor(j, p) : dJointGetHingeAnchor2(j, p);
    } else {
        side == 0 ? dJointGetBallAnchor(j, p) : dJointGetBallAnchor2(j, p);
    }
    return to_vec(p);
}

Eigen::Quaterniond orientation_of(dBodyID b) {
    const dReal* q = dBodyGetQuaternion(b);
    return {q[0], q[1], q[2], q[3]};
}

}  // namespace

// The groups that are trees of reducible joints with one joint to the world,
// awake and pushed by nothing, each ordered root first (breadth first).
// Before the gyroscopic pass, whose update articulated_step does itself.
void RigidWorld::Impl::find_trees() {
    trees.clear();
    const std::size_t n = slots.size();
    std::vector<int> bodies_in(n, 0), joints_in(n, 0), hung_by(n, -1);
    std::vector<char> fit(n, 1);
    for (std::uint32_t i = 0; i < n; ++i) {
        const Slot& s = slots[i];
        if (s.body == nullptr) continue;
        ++bodies_in[group_of[i]];
        if (!dBodyIsEnabled(s.body) || pushed(s.body)) fit[group_of[i]] = 0;
    }
    for (std::uint32_t k = 0; k < joints.size(); ++k) {
        const JointSlot& js = joints[k];
        if (js.joint == nullptr) continue;
        const std::uint32_t root = group_of[js.def.a.index];
        ++joints_in[root];
        if (!reducible(js.def) || (js.def.b == BodyId{} && hung_by[root] >= 0)) fit[root] = 0;
        if (js.def.b == BodyId{}) hung_by[root] = static_cast<int>(k);
    }
    for (std::uint32_t root = 0; root < n; ++root) {
        if (bodies_in[root] == 0 || !fit[root] || hung_by[root] < 0 || joints_in[root] != bodies_in[root]) continue;
        Tree tree;
        tree.joints.push_back(static_cast<std::uint32_t>(hung_by[root]));
        tree.slots.push_back(joints[tree.joints[0]].def.a.index);
        tree.parents.push_back(-1);
        // Breadth first: each joint joins a body in the tree to one not yet in it.
        for (std::size_t next = 0; next < tree.slots.size(); ++next) {
            const std::uint32_t at = tree.slots[next];
            for (std::uint32_t k = 0; k < joints.size(); ++k) {
                const JointDef& d = joints[k].def;
                if (joints[k].joint == nullptr || d.b == BodyId{} || (d.a.index != at && d.b.index != at)) continue;
                const std::uint32_t other = d.a.index == at ? d.b.index : d.a.index;
                if (std::find(tree.slots.begin(), tree.slots.end(), other) != tree.slots.end()) continue;
                tree.slots.push_back(other);
                tree.joints.push_back(k);
                tree.parents.push_back(static_cast<int>(next));
            }
        }
        for (const std::uint32_t i : tree.slots) tree.spin.push_back(to_vec(dBodyGetAngularVel(slots[i].body)));
        trees.push_back(std::move(tree));
    }
}

// After collision: a tree touching nothing leaves ODE's step (disabled for
// it), its spin as before the gyroscopic pass; one touching something stays.
void RigidWorld::Impl::hold_trees() {
    std::erase_if(trees, [&](const Tree& t) {
        return std::any_of(t.slots.begin(), t.slots.end(), [&](std::uint32_t i) { return slots[i].touched; });
    });
    for (const Tree& t : trees) {
        for (std::size_t k = 0; k < t.slots.size(); ++k) {
            const dBodyID b = slots[t.slots[k]].body;
            dBodySetAngularVel(b, t.spin[k].x(), t.spin[k].y(), t.spin[k].z());
            dBodyDisable(b);
        }
    }
}

// The held trees, by articulated_step, written back into ODE's bodies.
void RigidWorld::Impl::step_trees(double h) {
    for (const Tree& t : trees) {
        std::vector<ArticulatedLink> links(t.slots.size());
        std::vector<LinkState> state(t.slots.size());
        for (std::size_t k = 0; k < t.slots.size(); ++k) {
            const Slot& s = slots[t.slots[k]];
            dBodyEnable(s.body);
            const JointSlot& js = joints[t.joints[k]];
            const dJointID j = js.joint;
            const int side = dJointGetBody(j, 0) == s.body ? 0 : 1;  // this body's side of the joint
            const Eigen::Quaterniond q = orientation_of(s.body);
            const Vec3 x = to_vec(dBodyGetPosition(s.body));
            ArticulatedLink& link = links[k];
            link.parent = t.parents[k];
            link.joint = js.def.type == JointType::hinge ? ArticulatedJointType::hinge : ArticulatedJointType::ball;
            link.anchor_in_child = q.conjugate() * (anchor_of(j, js.def.type, side) - x);
            const Vec3 there = anchor_of(j, js.def.type, 1 - side);
            if (link.parent < 0) {
                link.anchor_in_parent = there;
            } else {
                const dBodyID p = slots[t.slots[static_cast<std::size_t>(link.parent)]].body;
                link.anchor_in_parent = orientation_of(p).conjugate() * (there - to_vec(dBodyGetPosition(p)));
            }
            if (js.def.type == JointType::hinge) {
                dVector3 axis;
                dJointGetHingeAxis(j, axis);
                link.axis_in_child = (q.conjugate() * to_vec(axis)).normalized();
            }
            link.mass = s.mass;
            link.inertia = s.inertia;
            state[k] = {x, q, to_vec(dBodyGetLinearVel(s.body)), to_vec(dBodyGetAngularVel(s.body))};
        }
        articulated_step(links, state, settings.gravity, h);
        for (std::size_t k = 0; k < t.slots.size(); ++k) {
            const dBodyID b = slots[t.slots[k]].body;
            const LinkState& s = state[k];
            const dQuaternion q = {s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z()};
            dBodySetPosition(b, s.position.x(), s.position.y(), s.position.z());
            dBodySetQuaternion(b, q);
            dBodySetLinearVel(b, s.velocity.x(), s.velocity.y(), s.velocity.z());
            dBodySetAngularVel(b, s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z());
        }
    }
}

}  // namespace sim
