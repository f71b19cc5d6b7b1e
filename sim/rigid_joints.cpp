// RigidWorld's joints: creating and removing them, their positions, and
// their stops (soft stops from stiffness and damping; speculative stops).
#include "sim/error.h"
#include "sim/rigid_impl.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>

namespace sim {

using rigid_detail::to_vec;

ErpCfm erp_cfm(double h, double kp, double kd) {
    const double denominator = h * kp + kd;
    return {h * kp / denominator, 1.0 / denominator};
}

JointId RigidWorld::add_joint(const JointDef& def) {
    Impl& m = *impl_;
    const dBodyID a = m.slot(def.a).body;
    const dBodyID b = def.b == BodyId{} ? nullptr : m.slot(def.b).body;
    if (!def.anchor.allFinite()) throw InputError("joint.anchor must be finite, in m");
    for (const Vec3* axis : {&def.axis, &def.axis2}) {
        if (!axis->allFinite() || std::abs(axis->norm() - 1.0) > 1e-6)
            throw InputError("joint.axis must be a unit vector");
    }
    const bool ball_limits =
        def.type == JointType::ball && (def.lo <= def.hi || def.lo2 <= def.hi2 || def.lo3 <= def.hi3);
    if ((def.type == JointType::universal || ball_limits) && std::abs(def.axis.dot(def.axis2)) > 1e-6) {
        throw InputError(
            "joint.axis2 must be perpendicular to joint.axis for a universal joint or a limited ball joint");
    }
    if (ball_limits) {
        if (b == nullptr) throw InputError("a ball joint's swing and twist limits need a second body (joint.b)");
        if (def.lo2 <= def.hi2 && (def.lo2 <= -0.5 * std::numbers::pi || def.hi2 >= 0.5 * std::numbers::pi)) {
            throw InputError("a ball joint's lo2 and hi2 must be within ±90° (got " + format_value(def.lo2) + " .. " +
                             format_value(def.hi2) + " rad)");
        }
    }
    require_nonnegative(def.stop_stiffness, "joint.stop_stiffness", "N·m/rad");
    require_nonnegative(def.stop_damping, "joint.stop_damping", "N·m·s/rad");
    require_nonnegative(def.motor_max_force, "joint.motor_max_force", "N·m");
    dJointID j = nullptr;
    switch (def.type) {
        case JointType::ball:
            j = dJointCreateBall(m.world, nullptr);
            dJointAttach(j, a, b);
            dJointSetBallAnchor(j, def.anchor.x(), def.anchor.y(), def.anchor.z());
            break;
        case JointType::hinge:
            j = dJointCreateHinge(m.world, nullptr);
            dJointAttach(j, a, b);
            dJointSetHingeAnchor(j, def.anchor.x(), def.anchor.y(), def.anchor.z());
            dJointSetHingeAxis(j, def.axis.x(), def.axis.y(), def.axis.z());
            break;
        case JointType::universal:
            j = dJointCreateUniversal(m.world, nullptr);
            dJointAttach(j, a, b);
            dJointSetUniversalAnchor(j, def.anchor.x(), def.anchor.y(), def.anchor.z());
            dJointSetUniversalAxis1(j, def.axis.x(), def.axis.y(), def.axis.z());
            dJointSetUniversalAxis2(j, def.axis2.x(), def.axis2.y(), def.axis2.z());
            break;
        case JointType::slider:
            j = dJointCreateSlider(m.world, nullptr);
            dJointAttach(j, a, b);
            dJointSetSliderAxis(j, def.axis.x(), def.axis.y(), def.axis.z());
            break;
        case JointType::fixed:
            j = dJointCreateFixed(m.world, nullptr);
            dJointAttach(j, a, b);
            dJointSetFixed(j);
            break;
    }
    dJointID amotor = nullptr;
    if (ball_limits) {
        // Euler mode: axis 0 fixed in body a, axis 2 in body b, axis 1 their
        // cross product; the angle about axis 1 must stay within ±90°.
        amotor = dJointCreateAMotor(m.world, nullptr);
        dJointAttach(amotor, a, b);
        dJointSetAMotorMode(amotor, dAMotorEuler);
        dJointSetAMotorAxis(amotor, 0, 1, def.axis.x(), def.axis.y(), def.axis.z());
        dJointSetAMotorAxis(amotor, 2, 2, def.axis2.x(), def.axis2.y(), def.axis2.z());
    }
    const Impl::JointSlot made{j, amotor, def, 0};
    const double limits[3][2] = {{def.lo, def.hi}, {def.lo2, def.hi2}, {def.lo3, def.hi3}};
    const int limited_axes = def.type == JointType::ball ? 3 : def.type == JointType::universal ? 2 : 1;
    for (int axis = 0; axis < limited_axes; ++axis) {
        if (limits[axis][0] > limits[axis][1]) continue;
        Impl::set_param(made, dParamLoStop, limits[axis][0], axis);
        Impl::set_param(made, dParamHiStop, limits[axis][1], axis);
        // A stop is one-sided, as a contact: as soft (stiff stops under a
        // ragdoll's impact fight its joints, centimetres apart for seconds).
        Impl::set_param(made, dParamStopERP, m.settings.contact_erp, axis);
        Impl::set_param(made, dParamStopCFM, m.settings.contact_cfm, axis);
    }
    if (def.motor_max_force > 0.0) {
        for (int axis = 0; axis < limited_axes; ++axis) {
            Impl::set_param(made, dParamVel, axis == 0 ? def.motor_velocity : 0.0, axis);
            Impl::set_param(made, dParamFMax, def.motor_max_force, axis);
        }
    }
    std::uint32_t index;
    if (!m.free_joints.empty()) {
        index = m.free_joints.back();
        m.free_joints.pop_back();
    } else {
        index = static_cast<std::uint32_t>(m.joints.size());
        m.joints.emplace_back();
    }
    m.joints[index].joint = j;
    m.joints[index].amotor = amotor;
    m.joints[index].def = def;
    m.stops_h = 0.0;  // recompute stop ERP/CFM at the next step
    return {index, m.joints[index].generation};
}

void RigidWorld::remove_joint(JointId id) {
    Impl& m = *impl_;
    dJointDestroy(m.joint(id).joint);
    if (m.joints[id.index].amotor != nullptr) dJointDestroy(m.joints[id.index].amotor);
    m.joints[id.index].joint = nullptr;
    m.joints[id.index].amotor = nullptr;
    ++m.joints[id.index].generation;
    m.free_joints.push_back(id.index);
}

double RigidWorld::joint_separation(JointId id) const {
    Vec3 p1, p2;
    return Impl::anchors(impl_->joint(id), p1, p2) ? (p1 - p2).norm() : 0.0;
}

double RigidWorld::joint_position(JointId id) const {
    const auto& js = impl_->joint(id);
    switch (js.def.type) {
        case JointType::hinge:
            return dJointGetHingeAngle(js.joint);
        case JointType::slider:
            return dJointGetSliderPosition(js.joint);
        case JointType::universal:
            return dJointGetUniversalAngle1(js.joint);
        default:
            return 0.0;
    }
}

// Sets a joint parameter on axis 0, 1 or 2 of the joint (a ball joint's
// axes are its angular motor's), whatever its type.
void RigidWorld::Impl::set_param(const JointSlot& js, int param, double value, int axis) {
    const int p = param + axis * dParamGroup;
    switch (js.def.type) {
        case JointType::hinge:
            if (axis == 0) dJointSetHingeParam(js.joint, p, value);
            break;
        case JointType::slider:
            if (axis == 0) dJointSetSliderParam(js.joint, p, value);
            break;
        case JointType::universal:
            if (axis < 2) dJointSetUniversalParam(js.joint, p, value);
            break;
        case JointType::ball:
            if (js.amotor != nullptr) dJointSetAMotorParam(js.amotor, p, value);
            break;
        case JointType::fixed:
            break;
    }
}

// A limited axis's position (rad or m) and rate now, for speculative stops.
bool RigidWorld::Impl::axis_motion(const JointSlot& js, int axis, double& position, double& rate) {
    switch (js.def.type) {
        case JointType::hinge:
            position = dJointGetHingeAngle(js.joint);
            rate = dJointGetHingeAngleRate(js.joint);
            return true;
        case JointType::slider:
            position = dJointGetSliderPosition(js.joint);
            rate = dJointGetSliderPositionRate(js.joint);
            return true;
        case JointType::universal:
            position = axis == 0 ? dJointGetUniversalAngle1(js.joint) : dJointGetUniversalAngle2(js.joint);
            rate = axis == 0 ? dJointGetUniversalAngle1Rate(js.joint) : dJointGetUniversalAngle2Rate(js.joint);
            return true;
        case JointType::ball:
            if (js.amotor == nullptr) return false;
            position = dJointGetAMotorAngle(js.amotor, axis);
            rate = dJointGetAMotorAngleRate(js.amotor, axis);
            return true;
        case JointType::fixed:
            return false;
    }
    return false;
}

// Speculative stops (Box2D's speculative joint limits, in ODE's terms).
// ODE turns a stop on only once the joint is past it at the start of a
// step, so a limb hit hard swings far past its stop within one step (an
// elbow 0.5 rad past straight when a ragdoll lands on its hand) and
// creeps back by ERP. Near a stop (within a step's travel and a margin)
// the stop is turned on early instead, as a row that lets the joint
// close the gap in this step and no more: with the stop placed at the
// joint's mirror image across the real stop and a stop ERP of -1, ODE's
// row asks rate <= (hi - position) / h (rate >= (lo - position) / h at
// the low stop). Past a stop, or far from both, the stops are ODE's own
// (the world's ERP pushes a joint past its stop back).
void RigidWorld::Impl::speculative_stops(double h) {
    constexpr double kMargin = 0.15;  // rad (m for a slider): turned on this close without motion
    for (const JointSlot& js : joints) {
        // Soft stops (a stop stiffness) are springs: nothing to foresee.
        if (js.joint == nullptr || js.def.stop_stiffness > 0.0) continue;
        const double limits[3][2] = {{js.def.lo, js.def.hi}, {js.def.lo2, js.def.hi2}, {js.def.lo3, js.def.hi3}};
        for (int axis = 0; axis < 3; ++axis) {
            const double lo = limits[axis][0], hi = limits[axis][1];
            double position = 0.0, rate = 0.0;
            if (lo > hi || !axis_motion(js, axis, position, rate)) continue;
            // Within reach of one stop only: less than half the range.
            const double reach = std::min(kMargin + 2.0 * h * std::abs(rate), 0.49 * (hi - lo));
            double lo_now = lo, hi_now = hi, erp_now = settings.contact_erp;  // a stop's own ERP (add_joint)
            if (position < hi && hi - position < reach) {
                hi_now = 2.0 * position - hi;
                erp_now = -1.0;
            } else if (position > lo && position - lo < reach) {
                lo_now = 2.0 * position - lo;
                erp_now = -1.0;
            }
            // ODE keeps lo <= hi when set one at a time: widen first, then narrow.
            set_param(js, dParamLoStop, -dInfinity, axis);
            set_param(js, dParamHiStop, dInfinity, axis);
            set_param(js, dParamLoStop, lo_now, axis);
            set_param(js, dParamHiStop, hi_now, axis);
            set_param(js, dParamStopERP, erp_now, axis);
        }
    }
}

// Stop ERP/CFM from stiffness and damping at step h.
void RigidWorld::Impl::update_stops(double h) {
    if (h == stops_h) return;
    stops_h = h;
    for (const JointSlot& js : joints) {
        if (js.joint == nullptr || js.def.stop_stiffness <= 0.0) continue;
        const ErpCfm e = erp_cfm(h, js.def.stop_stiffness, js.def.stop_damping);
        for (int axis = 0; axis < 3; ++axis) {
            set_param(js, dParamStopERP, e.erp, axis);
            set_param(js, dParamStopCFM, e.cfm, axis);
        }
    }
}

// Where a joint's anchor is on each of its bodies, world frame, m.
bool RigidWorld::Impl::anchors(const JointSlot& js, Vec3& p1, Vec3& p2) {
    dVector3 a, b;
    switch (js.def.type) {
        case JointType::ball:
            dJointGetBallAnchor(js.joint, a);
            dJointGetBallAnchor2(js.joint, b);
            break;
        case JointType::hinge:
            dJointGetHingeAnchor(js.joint, a);
            dJointGetHingeAnchor2(js.joint, b);
            break;
        case JointType::universal:
            dJointGetUniversalAnchor(js.joint, a);
            dJointGetUniversalAnchor2(js.joint, b);
            break;
        default:
            return false;
    }
    p1 = to_vec(a);
    p2 = to_vec(b);
    return true;
}

}  // namespace sim
