#include "sim/rigid.h"

#include "sim/error.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <numbers>
#include <type_traits>
#include <variant>

namespace sim {

namespace {

// ODE's init/close, reference-counted: the first world initialises the
// library, the last one closes it.
// ODE's messages (not errors: an error or debug message aborts) go to the
// world stepping on this thread, else to stderr.
struct SolverMessages {
    struct Said {
        std::string text;  // the first, formatted
        int times = 0;
    };
    std::vector<std::pair<std::string, Said>> by_format;  // in order first said
};
thread_local SolverMessages* g_stepping = nullptr;

void on_ode_message(int number, const char* format, va_list args) {
    char text[512];
    std::vsnprintf(text, sizeof text, format, args);
    if (g_stepping == nullptr) {
        std::fprintf(stderr, "ODE message %d: %s\n", number, text);
        return;
    }
    auto& list = g_stepping->by_format;
    auto it = std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == format; });
    if (it == list.end()) it = list.insert(list.end(), {format, {text, 0}});
    ++it->second.times;
}

class OdeLibrary {
public:
    OdeLibrary() {
        const std::lock_guard lock(mutex());
        if (count()++ == 0) {
            dInitODE2(0);
            dSetMessageHandler(&on_ode_message);
        }
        dAllocateODEDataForThread(dAllocateMaskAll);
    }
    ~OdeLibrary() {
        const std::lock_guard lock(mutex());
        if (--count() == 0) dCloseODE();
    }
    OdeLibrary(const OdeLibrary&) = delete;
    OdeLibrary& operator=(const OdeLibrary&) = delete;

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    static int& count() {
        static int n = 0;
        return n;
    }
};

Vec3 to_vec(const dReal* v) { return {v[0], v[1], v[2]}; }

constexpr int kMaxContacts = 4;  // per colliding pair of geoms

}  // namespace

void validate(const RigidSettings& s) {
    if (!s.gravity.allFinite()) throw InputError("rigid.gravity must be finite, in m/s²");
    if (s.iterations < 1 || s.iterations > 10'000) {
        throw InputError("rigid.iterations must be within 1 .. 10000 (got " + std::to_string(s.iterations) + ")");
    }
    require_nonnegative(s.friction, "rigid.friction", "");
    if (!(s.restitution >= 0.0 && s.restitution <= 1.0)) {
        throw InputError("rigid.restitution must be within 0 .. 1 (got " + format_value(s.restitution) + ")");
    }
    require_nonnegative(s.bounce_velocity, "rigid.bounce_velocity", "m/s");
    if (!(s.erp > 0.0 && s.erp <= 1.0))
        throw InputError("rigid.erp must be within 0 .. 1 (got " + format_value(s.erp) + ")");
    require_nonnegative(s.cfm, "rigid.cfm", "");
    if (!std::isfinite(s.ground_height)) throw InputError("rigid.ground_height must be finite, in m");
    require_positive(s.sleep_speed, "rigid.sleep_speed", "m/s");
    require_positive(s.sleep_time, "rigid.sleep_time", "s");
    if (s.position_iterations < 0 || s.position_iterations > 100) {
        throw InputError("rigid.position_iterations must be within 0 .. 100 (got " +
                         std::to_string(s.position_iterations) + ")");
    }
}

namespace {

int size_components(RigidShape shape) { return shape == RigidShape::box ? 3 : shape == RigidShape::sphere ? 1 : 2; }

void require_unit(const Eigen::Quaterniond& q, const std::string& name) {
    if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-6) {
        throw InputError(name + " must be a unit quaternion");
    }
}

}  // namespace

void validate(const BodyDef& b) {
    if (b.parts.empty()) {
        for (int k = 0; k < size_components(b.shape); ++k) require_positive(b.size[k], "body.size", "m");
    }
    for (std::size_t p = 0; p < b.parts.size(); ++p) {
        const BodyPart& part = b.parts[p];
        const std::string name = "body.parts[" + std::to_string(p) + "]";
        for (int k = 0; k < size_components(part.shape); ++k) require_positive(part.size[k], name + ".size", "m");
        require_positive(part.density, name + ".density", "kg/m³");
        if (!part.offset.allFinite()) throw InputError(name + ".offset must be finite, in m");
        require_unit(part.orientation, name + ".orientation");
    }
    if (b.mass == 0.0) {
        if (b.parts.empty()) require_positive(b.density, "body.density", "kg/m³");
    } else {
        require_positive(b.mass, "body.mass", "kg");
    }
    if (!b.position.allFinite() || !b.velocity.allFinite() || !b.angular_velocity.allFinite() || !b.com.allFinite()) {
        throw InputError("body.position, velocity, angular_velocity and com must be finite");
    }
    require_unit(b.orientation, "body.orientation");
}

struct RigidWorld::Impl {
    OdeLibrary library;
    RigidSettings settings;
    dWorldID world = nullptr;
    dSpaceID space = nullptr;
    dJointGroupID contact_group = nullptr;
    dGeomID ground = nullptr;
    struct Slot {
        dBodyID body = nullptr;
        std::vector<dGeomID> geoms;   // one per part
        std::vector<BodyPart> parts;  // offsets from the centre of mass, body frame
        std::uint32_t generation = 0;
        double mass = 1.0;                                          // kg
        Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();      // kg·m², body frame
        Eigen::Matrix3d inv_inertia = Eigen::Matrix3d::Identity();  // its inverse
        std::uint32_t idle_steps = 0;       // its group's steps in a row at rest (1: a window starts)
        double sleep_energy = 0.0;          // J/kg, its group's smoothed kinetic energy per kilogram
        Vec3 rest_position = Vec3::Zero();  // where the window started
        Eigen::Quaterniond rest_orientation = Eigen::Quaterniond::Identity();
        bool asleep = false;  // disabled by sleep (ODE may wake it)
    };
    std::vector<Slot> slots;
    std::vector<std::uint32_t> free_slots;
    struct JointSlot {
        dJointID joint = nullptr;
        dJointID amotor = nullptr;  // a ball joint's swing and twist limits
        JointDef def;
        std::uint32_t generation = 0;
    };
    std::vector<JointSlot> joints;
    std::vector<std::uint32_t> free_joints;
    double stops_h = 0.0;  // the step the stop ERP/CFM were computed for
    std::uint64_t steps = 0;
    std::size_t contacts = 0;
    SolverMessages messages;
    std::vector<std::uint32_t> group_of;                        // union-find parents over body slots: jointed groups
    std::vector<double> group_energy, group_moved, group_mass;  // sleep's scratch, by group root
    std::vector<char> group_woken;                              // ... and whether its window starts again this step

    const Slot& slot(BodyId id) const {
        if (id.index >= slots.size() || slots[id.index].body == nullptr ||
            slots[id.index].generation != id.generation) {
            throw InputError("no such rigid body (index " + std::to_string(id.index) + ", generation " +
                             std::to_string(id.generation) + "): removed, or of another world");
        }
        return slots[id.index];
    }

    const JointSlot& joint(JointId id) const {
        if (id.index >= joints.size() || joints[id.index].joint == nullptr ||
            joints[id.index].generation != id.generation) {
            throw InputError("no such joint (index " + std::to_string(id.index) + ", generation " +
                             std::to_string(id.generation) + ")");
        }
        return joints[id.index];
    }

    // Sets a joint parameter on axis 0, 1 or 2 of the joint (a ball joint's
    // axes are its angular motor's), whatever its type.
    static void set_param(const JointSlot& js, int param, double value, int axis = 0) {
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
    static bool axis_motion(const JointSlot& js, int axis, double& position, double& rate) {
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
    void speculative_stops(double h) {
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
                double lo_now = lo, hi_now = hi, erp_now = settings.erp;  // ODE's default stop ERP
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
    void update_stops(double h) {
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

    static std::uint32_t index_of(dBodyID body) {
        return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(dBodyGetData(body)));
    }

    // Bodies one or two joints apart do not collide (parent and child,
    // grandparent and grandchild, siblings): in a ragdoll their shapes meet
    // at every joint and the contacts fight the joints, so that a ragdoll
    // at rest creeps and never sleeps (Jolt's ragdolls filter the same
    // pairs). Farther bodies (a hand and a thigh) collide.
    static bool jointed_within_two(dBodyID a, dBodyID b) {
        if (dAreConnectedExcluding(a, b, dJointTypeContact)) return true;
        const int n = dBodyGetNumJoints(a);
        for (int k = 0; k < n; ++k) {
            const dJointID j = dBodyGetJoint(a, k);
            if (dJointGetType(j) == dJointTypeContact) continue;
            for (int side = 0; side < 2; ++side) {
                const dBodyID middle = dJointGetBody(j, side);
                if (middle != nullptr && middle != a && dAreConnectedExcluding(middle, b, dJointTypeContact))
                    return true;
            }
        }
        return false;
    }

    // ODE's broad phase calls this for each pair of geoms whose boxes overlap.
    static void near_callback(void* data, dGeomID a, dGeomID b) {
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
            s.mode = dContactBounce | dContactApprox1 | dContactSoftERP | dContactSoftCFM;
            s.mu = self->settings.friction;
            s.bounce = self->settings.restitution;
            s.bounce_vel = self->settings.bounce_velocity;
            s.soft_erp = self->settings.erp;
            s.soft_cfm = self->settings.cfm;
            dJointID j = dJointCreateContact(self->world, self->contact_group, &contact[i]);
            dJointAttach(j, ba, bb);
            ++self->contacts;
        }
    }

    // ω over h by RK4 on Euler's torque-free equations in the body frame,
    // I ω̇ = -ω × I ω (see RigidSettings::gyroscopic_rk4).
    void gyroscopic(double h) {
        for (Slot& s : slots) {
            if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
            const dReal* q = dBodyGetQuaternion(s.body);
            const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
            const Vec3 w0 = R.transpose() * to_vec(dBodyGetAngularVel(s.body));
            auto f = [&](const Vec3& w) -> Vec3 { return -(s.inv_inertia * w.cross(s.inertia * w)); };
            const Vec3 k1 = f(w0);
            const Vec3 k2 = f(w0 + 0.5 * h * k1);
            const Vec3 k3 = f(w0 + 0.5 * h * k2);
            const Vec3 k4 = f(w0 + h * k3);
            const Vec3 w = R * (w0 + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4));
            dBodySetAngularVel(s.body, w.x(), w.y(), w.z());
        }
    }

    // Where a joint's anchor is on each of its bodies, world frame, m.
    static bool anchors(const JointSlot& js, Vec3& p1, Vec3& p2) {
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

    // Position iterations (RigidSettings::position_iterations): for each
    // joint, the anchor gap C = |p2 - p1| along n is closed by a positional
    // impulse λ = C / (w1 + w2), with each body's generalised inverse mass
    // w = 1/m + (r × n)ᵀ I⁻¹ (r × n) (r: from its centre of mass to its
    // anchor): x += λ n / m, and a rotation I⁻¹ (r × λ n) applied to its
    // quaternion. A body asleep or the static world does not move.
    void stabilize() {
        struct Side {
            dBodyID body = nullptr;
            double inv_mass = 0.0;
            Eigen::Matrix3d inv_inertia = Eigen::Matrix3d::Zero();  // world frame
            Vec3 x = Vec3::Zero();
            Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
        };
        auto side = [&](BodyId id) {
            Side s;
            if (id == BodyId{}) return s;
            const Slot& slot = slots[id.index];
            if (!dBodyIsEnabled(slot.body)) return s;
            s.body = slot.body;
            dMass m;
            dBodyGetMass(slot.body, &m);
            s.inv_mass = 1.0 / m.mass;
            s.x = to_vec(dBodyGetPosition(slot.body));
            const dReal* q = dBodyGetQuaternion(slot.body);
            s.q = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
            const Eigen::Matrix3d R = s.q.toRotationMatrix();
            s.inv_inertia = R * slot.inv_inertia * R.transpose();
            return s;
        };
        auto move = [](const Side& s, const Vec3& impulse, const Vec3& r) {
            if (s.body == nullptr) return;
            const Vec3 x = s.x + s.inv_mass * impulse;
            const Vec3 dtheta = s.inv_inertia * r.cross(impulse);
            Eigen::Quaterniond q = s.q;
            const Eigen::Quaterniond spin(0.0, dtheta.x(), dtheta.y(), dtheta.z());
            q.coeffs() += 0.5 * (spin * s.q).coeffs();
            q.normalize();
            dBodySetPosition(s.body, x.x(), x.y(), x.z());
            const dQuaternion oq = {q.w(), q.x(), q.y(), q.z()};
            dBodySetQuaternion(s.body, oq);
        };
        for (int it = 0; it < settings.position_iterations; ++it) {
            for (const JointSlot& js : joints) {
                Vec3 p1, p2;
                if (js.joint == nullptr || !anchors(js, p1, p2)) continue;
                const Vec3 gap = p2 - p1;
                const double c = gap.norm();
                if (c < 1e-12) continue;
                const Vec3 n = gap / c;
                const Side a = side(js.def.a), b = side(js.def.b);
                if (a.body == nullptr && b.body == nullptr) continue;
                const Vec3 ra = p1 - a.x, rb = p2 - b.x;
                const Vec3 ca = ra.cross(n), cb = rb.cross(n);
                const double w = a.inv_mass + ca.dot(a.inv_inertia * ca) + b.inv_mass + cb.dot(b.inv_inertia * cb);
                const Vec3 impulse = (c / w) * n;
                move(a, impulse, ra);
                move(b, -impulse, rb);
            }
        }
    }

    // Slow enough to fall asleep: the body's group's smoothed kinetic energy
    // per kilogram within sleep's limit, that of twice sleep_speed.
    bool slow(dBodyID body) const {
        const double v = 2.0 * settings.sleep_speed;
        return slots[index_of(body)].sleep_energy <= 0.5 * v * v;
    }

    std::uint32_t find(std::uint32_t i) {
        while (group_of[i] != i) i = group_of[i] = group_of[group_of[i]];
        return i;
    }

    // The groups of bodies joined by joints (a ragdoll, a chain): union-find
    // over the body slots, rebuilt every step (joints come and go).
    void build_groups() {
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
    double kinetic(const Slot& s) const {
        const dReal* q = dBodyGetQuaternion(s.body);
        const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
        const Vec3 w = R.transpose() * to_vec(dBodyGetAngularVel(s.body));
        return 0.5 * s.mass * to_vec(dBodyGetLinearVel(s.body)).squaredNorm() + 0.5 * w.dot(s.inertia * w);
    }

    // How far a body has moved from its rest pose, weighted: m |Δx|² + Δθᵀ I Δθ
    // (kg·m²), Δθ its turn in its own frame.
    double displacement(const Slot& s) const {
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
    //    creep does not.
    // A group idle for sleep_time is disabled at rest. A group that ODE
    // re-enabled (a contact, a joint to an awake body) starts again. Each
    // body keeps its group's figures, so that body_states() carries them.
    void sleep(double h) {
        const double energy_limit = 2.0 * settings.sleep_speed * settings.sleep_speed;  // J/kg, ½ (2 v)²
        const double reach = settings.sleep_speed * settings.sleep_time;                // m
        const double blend = std::min(1.0, h / (0.25 * settings.sleep_time));
        const auto needed = static_cast<std::uint32_t>(std::ceil(settings.sleep_time / h));
        group_energy.assign(slots.size(), 0.0);
        group_moved.assign(slots.size(), 0.0);
        group_mass.assign(slots.size(), 0.0);
        group_woken.assign(slots.size(), 0);
        for (std::uint32_t i = 0; i < slots.size(); ++i) {
            Slot& s = slots[i];
            if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
            const std::uint32_t root = find(i);
            group_energy[root] += kinetic(s);
            group_moved[root] += displacement(s);
            group_mass[root] += s.mass;
            if (s.asleep) group_woken[root] = 1;
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
                if (group_woken[root] == 0 && s.idle_steps > 0 && moved <= reach) {
                    if (s.sleep_energy <= energy_limit) ++s.idle_steps;
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
            if (s.body == nullptr || !dBodyIsEnabled(s.body) || s.idle_steps < needed) continue;
            dBodySetLinearVel(s.body, 0, 0, 0);
            dBodySetAngularVel(s.body, 0, 0, 0);
            dBodyDisable(s.body);
            s.asleep = true;
        }
    }
};

RigidWorld::RigidWorld(const RigidSettings& settings) : impl_(std::make_unique<Impl>()) {
    validate(settings);
    Impl& m = *impl_;
    m.settings = settings;
    m.world = dWorldCreate();
    dWorldSetGravity(m.world, settings.gravity.x(), settings.gravity.y(), settings.gravity.z());
    dWorldSetERP(m.world, settings.erp);
    dWorldSetCFM(m.world, settings.cfm);
    dWorldSetQuickStepNumIterations(m.world, settings.iterations);
    m.space = dHashSpaceCreate(nullptr);
    m.contact_group = dJointGroupCreate(0);
    if (settings.ground) m.ground = dCreatePlane(m.space, 0, 1, 0, settings.ground_height);
}

RigidWorld::RigidWorld(const RigidModel& model) : RigidWorld(model.settings) {
    std::vector<BodyId> ids;
    for (const BodyDef& body : model.bodies) ids.push_back(add_body(body));
    for (std::size_t k = 0; k < model.joints.size(); ++k) {
        const RigidJoint& rj = model.joints[k];
        auto ref = [&](int i, const char* which) {
            if (i < -1 || i >= static_cast<int>(ids.size())) {
                throw InputError("joints[" + std::to_string(k) + "]." + which + " is body " + std::to_string(i) +
                                 ", but there are " + std::to_string(ids.size()));
            }
            return i < 0 ? BodyId{} : ids[static_cast<std::size_t>(i)];
        };
        JointDef def = rj.joint;
        def.a = ref(rj.a, "a");
        def.b = ref(rj.b, "b");
        if (def.a == BodyId{}) throw InputError("joints[" + std::to_string(k) + "].a must be a body");
        add_joint(def);
    }
}

RigidWorld::~RigidWorld() {
    Impl& m = *impl_;
    for (const auto& js : m.joints) {
        if (js.joint != nullptr) dJointDestroy(js.joint);
        if (js.amotor != nullptr) dJointDestroy(js.amotor);
    }
    dJointGroupDestroy(m.contact_group);
    dSpaceDestroy(m.space);  // destroys its geoms (the space owns them by default)
    dWorldDestroy(m.world);  // and the bodies
}

namespace {

void set_mass(dMass* mass, RigidShape shape, double density, const Vec3& size) {
    switch (shape) {
        case RigidShape::box:
            dMassSetBox(mass, density, size.x(), size.y(), size.z());
            break;
        case RigidShape::sphere:
            dMassSetSphere(mass, density, size.x());
            break;
        case RigidShape::capsule:
            dMassSetCapsule(mass, density, 3, size.x(), size.y());
            break;
        case RigidShape::cylinder:
            dMassSetCylinder(mass, density, 3, size.x(), size.y());
            break;
    }
}

dGeomID create_geom(dSpaceID space, RigidShape shape, const Vec3& size) {
    switch (shape) {
        case RigidShape::box:
            return dCreateBox(space, size.x(), size.y(), size.z());
        case RigidShape::sphere:
            return dCreateSphere(space, size.x());
        case RigidShape::capsule:
            return dCreateCapsule(space, size.x(), size.y());
        case RigidShape::cylinder:
            return dCreateCylinder(space, size.x(), size.y());
    }
    return nullptr;
}

void to_ode(const Eigen::Quaterniond& q, dQuaternion out) {
    out[0] = q.w();
    out[1] = q.x();
    out[2] = q.y();
    out[3] = q.z();
}

// A one-shape body is a compound of one part.
std::vector<BodyPart> parts_of(const BodyDef& def) {
    if (!def.parts.empty()) return def.parts;
    // density 1 is scaled to `mass` when a mass is given
    return {BodyPart{def.shape, def.size, Vec3::Zero(), Eigen::Quaterniond::Identity(),
                     def.mass > 0.0 ? 1.0 : def.density}};
}

// The parts' mass about the shape frame's origin (scaled to `total` when > 0).
dMass mass_of_parts(const std::vector<BodyPart>& parts, double total) {
    dMass mass;
    dMassSetZero(&mass);
    for (const BodyPart& part : parts) {
        dMass piece;
        set_mass(&piece, part.shape, part.density, part.size);
        dMatrix3 R;
        dQuaternion q;
        to_ode(part.orientation, q);
        dQtoR(q, R);
        dMassRotate(&piece, R);
        dMassTranslate(&piece, part.offset.x(), part.offset.y(), part.offset.z());
        dMassAdd(&mass, &piece);
    }
    if (total > 0.0) dMassAdjust(&mass, total);
    return mass;
}

}  // namespace

double mass_of(const BodyDef& def) {
    validate(def);
    return mass_of_parts(parts_of(def), def.mass).mass;
}

BodyId RigidWorld::add_body(const BodyDef& def) {
    validate(def);
    Impl& m = *impl_;
    std::vector<BodyPart> parts = parts_of(def);
    dMass mass = mass_of_parts(parts, def.mass);
    // Moved so that the centre of mass is the body's origin (ODE requires it there).
    const Vec3 centroid(mass.c[0], mass.c[1], mass.c[2]);
    dMassTranslate(&mass, -centroid.x(), -centroid.y(), -centroid.z());  // inertia about the centroid
    const Vec3 com = centroid + def.com;                                 // the ballast shift keeps that inertia

    dBodyID body = dBodyCreate(m.world);
    dBodySetMass(body, &mass);
    const std::uint32_t index = m.free_slots.empty() ? static_cast<std::uint32_t>(m.slots.size()) : m.free_slots.back();
    dBodySetData(body, reinterpret_cast<void*>(static_cast<std::uintptr_t>(index)));  // its slot, for the collider
    if (m.settings.gyroscopic_rk4) dBodySetGyroscopicMode(body, 0);                   // done before each step instead
    std::vector<dGeomID> geoms;
    for (BodyPart& part : parts) {
        part.offset -= com;  // from now on relative to the centre of mass
        dGeomID geom = create_geom(m.space, part.shape, part.size);
        dGeomSetBody(geom, body);
        if (part.offset != Vec3::Zero())
            dGeomSetOffsetPosition(geom, part.offset.x(), part.offset.y(), part.offset.z());
        if (part.orientation.coeffs() != Eigen::Quaterniond::Identity().coeffs()) {
            dQuaternion q;
            to_ode(part.orientation, q);
            dGeomSetOffsetQuaternion(geom, q);
        }
        geoms.push_back(geom);
    }
    dBodySetPosition(body, def.position.x(), def.position.y(), def.position.z());
    dQuaternion q;
    to_ode(def.orientation, q);
    dBodySetQuaternion(body, q);
    dBodySetLinearVel(body, def.velocity.x(), def.velocity.y(), def.velocity.z());
    dBodySetAngularVel(body, def.angular_velocity.x(), def.angular_velocity.y(), def.angular_velocity.z());

    if (!m.free_slots.empty()) {
        m.free_slots.pop_back();
    } else {
        m.slots.emplace_back();
    }
    Impl::Slot& s = m.slots[index];
    s.body = body;
    s.geoms = std::move(geoms);
    s.parts = std::move(parts);
    s.idle_steps = 0;
    s.sleep_energy = 0.0;
    s.asleep = false;
    s.mass = mass.mass;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) s.inertia(r, c) = mass.I[4 * r + c];  // dMatrix3 rows are padded to 4
    }
    s.inv_inertia = s.inertia.inverse();
    return {index, s.generation};
}

void RigidWorld::add_static(const Collider& collider) {
    Impl& m = *impl_;
    auto place = [](dGeomID g, const Vec3& center, const Eigen::Matrix3d& rotation) {
        dGeomSetPosition(g, center.x(), center.y(), center.z());
        dMatrix3 R;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) R[4 * r + c] = rotation(r, c);  // rows padded to 4
            R[4 * r + 3] = 0.0;
        }
        dGeomSetRotation(g, R);
    };
    std::visit(
        [&](const auto& c) {
            using T = std::decay_t<decltype(c)>;
            if constexpr (std::is_same_v<T, PlaneCollider>) {
                dCreatePlane(m.space, c.normal.x(), c.normal.y(), c.normal.z(), c.offset);
            } else if constexpr (std::is_same_v<T, SphereCollider>) {
                dGeomID g = dCreateSphere(m.space, c.radius);
                dGeomSetPosition(g, c.center.x(), c.center.y(), c.center.z());
            } else if constexpr (std::is_same_v<T, BoxCollider>) {
                const Vec3 full = 2.0 * c.half_extents;
                place(dCreateBox(m.space, full.x(), full.y(), full.z()), c.center, c.rotation);
            } else {  // capsule: ODE's lies along its local z
                const Vec3 axis = c.b - c.a;
                const double length = axis.norm();
                const Eigen::Matrix3d R =
                    length > 0.0 ? Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis / length).toRotationMatrix()
                                 : Eigen::Matrix3d::Identity();
                place(dCreateCapsule(m.space, c.radius, length), 0.5 * (c.a + c.b), R);
            }
        },
        collider);
}

void RigidWorld::remove_body(BodyId id) {
    Impl& m = *impl_;
    const Impl::Slot& s = m.slot(id);
    for (dGeomID g : s.geoms) dGeomDestroy(g);
    dBodyDestroy(s.body);
    Impl::Slot& mut = m.slots[id.index];
    mut.body = nullptr;
    mut.geoms.clear();
    mut.parts.clear();
    ++mut.generation;  // the old id is stale from now on
    m.free_slots.push_back(id.index);
}

bool RigidWorld::alive(BodyId id) const {
    const Impl& m = *impl_;
    return id.index < m.slots.size() && m.slots[id.index].body != nullptr &&
           m.slots[id.index].generation == id.generation;
}

std::size_t RigidWorld::body_count() const { return impl_->slots.size() - impl_->free_slots.size(); }

void RigidWorld::step(double dt) {
    if (!(dt > 0.0) || !std::isfinite(dt))
        throw InputError("dt must be > 0 and finite, in s (got " + format_value(dt) + ")");
    Impl& m = *impl_;
    // ODE's one random generator, seeded by this world alone (see the header).
    dRandSetSeed(static_cast<unsigned long>(m.settings.seed * 0x9E3779B97F4A7C15ull + m.steps));
    m.update_stops(dt);
    if (m.settings.speculative_stops) m.speculative_stops(dt);
    if (m.settings.gyroscopic_rk4) m.gyroscopic(dt);
    m.contacts = 0;
    m.build_groups();
    dSpaceCollide(m.space, &m, &Impl::near_callback);
    g_stepping = &m.messages;
    if (m.settings.quickstep) {
        dWorldQuickStep(m.world, dt);
    } else {
        dWorldStep(m.world, dt);
    }
    g_stepping = nullptr;
    dJointGroupEmpty(m.contact_group);
    if (m.settings.position_iterations > 0) m.stabilize();
    if (m.settings.sleep) m.sleep(dt);
    ++m.steps;
}

std::vector<std::string> RigidWorld::solver_messages() const {
    std::vector<std::string> out;
    for (const auto& [format, said] : impl_->messages.by_format) {
        out.push_back(said.times == 1 ? said.text : said.text + " (" + std::to_string(said.times) + " times)");
    }
    return out;
}

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

std::uint64_t RigidWorld::steps() const { return impl_->steps; }
std::size_t RigidWorld::contacts() const { return impl_->contacts; }

BodyState RigidWorld::state(BodyId id) const {
    const dBodyID b = impl_->slot(id).body;
    BodyState s;
    s.position = to_vec(dBodyGetPosition(b));
    const dReal* q = dBodyGetQuaternion(b);
    s.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    s.velocity = to_vec(dBodyGetLinearVel(b));
    s.angular_velocity = to_vec(dBodyGetAngularVel(b));
    s.awake = dBodyIsEnabled(b) != 0;
    s.idle_steps = impl_->slots[id.index].idle_steps;
    s.sleep_energy = impl_->slots[id.index].sleep_energy;
    s.rest_position = impl_->slots[id.index].rest_position;
    s.rest_orientation = impl_->slots[id.index].rest_orientation;
    return s;
}

bool RigidWorld::awake(BodyId id) const { return dBodyIsEnabled(impl_->slot(id).body) != 0; }

std::size_t RigidWorld::awake_count() const {
    return static_cast<std::size_t>(std::count_if(impl_->slots.begin(), impl_->slots.end(), [](const auto& s) {
        return s.body != nullptr && dBodyIsEnabled(s.body);
    }));
}

std::vector<MassRatio> RigidWorld::mass_ratios_above(double limit) const {
    std::vector<MassRatio> out;
    for (std::uint32_t k = 0; k < impl_->joints.size(); ++k) {
        const auto& js = impl_->joints[k];
        if (js.joint == nullptr || js.def.b == BodyId{}) continue;
        const double ma = mass(js.def.a), mb = mass(js.def.b);
        const double ratio = std::max(ma, mb) / std::min(ma, mb);
        if (ratio > limit) out.push_back({JointId{k, js.generation}, ratio});
    }
    std::stable_sort(out.begin(), out.end(), [](const MassRatio& x, const MassRatio& y) { return x.ratio > y.ratio; });
    return out;
}

std::vector<PlacedPart> RigidWorld::placed_parts() const {
    std::vector<PlacedPart> out;
    for (std::uint32_t i = 0; i < impl_->slots.size(); ++i) {
        const auto& s = impl_->slots[i];
        if (s.body == nullptr) continue;
        const Vec3 x = to_vec(dBodyGetPosition(s.body));
        const dReal* q = dBodyGetQuaternion(s.body);
        const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
        for (const BodyPart& part : s.parts) {
            out.push_back({BodyId{i, s.generation}, part.shape, part.size, x + rotation * part.offset,
                           rotation * part.orientation});
        }
    }
    return out;
}

double RigidWorld::mass(BodyId id) const {
    dMass m;
    dBodyGetMass(impl_->slot(id).body, &m);
    return m.mass;
}

Eigen::Matrix3d RigidWorld::inertia(BodyId id) const {
    dMass m;
    dBodyGetMass(impl_->slot(id).body, &m);
    Eigen::Matrix3d I;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) I(r, c) = m.I[4 * r + c];  // dMatrix3 rows are padded to 4
    }
    return I;
}

double RigidWorld::kinetic_energy() const {
    double e = 0.0;
    for (const auto& s : impl_->slots) {
        if (s.body != nullptr) e += impl_->kinetic(s);
    }
    return e;
}

double RigidWorld::potential_energy() const {
    double e = 0.0;
    for (std::uint32_t i = 0; i < impl_->slots.size(); ++i) {
        const auto& s = impl_->slots[i];
        if (s.body == nullptr) continue;
        const BodyId id{i, s.generation};
        e -= mass(id) * impl_->settings.gravity.dot(state(id).position);
    }
    return e;
}

std::uint64_t RigidWorld::hash() const {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a offset basis
    auto mix = [&](double v) {
        unsigned char bytes[sizeof v];
        std::memcpy(bytes, &v, sizeof v);
        for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;  // FNV prime
    };
    for (const auto& s : impl_->slots) {
        if (s.body == nullptr) continue;
        for (const dReal* v : {dBodyGetPosition(s.body), dBodyGetLinearVel(s.body), dBodyGetAngularVel(s.body)}) {
            for (int k = 0; k < 3; ++k) mix(v[k]);
        }
        const dReal* q = dBodyGetQuaternion(s.body);
        for (int k = 0; k < 4; ++k) mix(q[k]);
    }
    return h;
}

std::vector<BodyId> RigidWorld::bodies() const {
    std::vector<BodyId> ids;
    for (std::uint32_t i = 0; i < impl_->slots.size(); ++i) {
        if (impl_->slots[i].body != nullptr) ids.push_back({i, impl_->slots[i].generation});
    }
    return ids;
}

std::vector<BodyState> RigidWorld::body_states() const {
    std::vector<BodyState> out;
    for (const BodyId id : bodies()) out.push_back(state(id));
    return out;
}

void RigidWorld::set_body_states(const std::vector<BodyState>& states, std::uint64_t steps) {
    const std::vector<BodyId> ids = bodies();
    if (states.size() != ids.size()) {
        throw InputError("snapshot has " + std::to_string(states.size()) + " rigid bodies, the world has " +
                         std::to_string(ids.size()));
    }
    for (std::size_t k = 0; k < ids.size(); ++k) {
        const dBodyID b = impl_->slot(ids[k]).body;
        const BodyState& s = states[k];
        dBodySetPosition(b, s.position.x(), s.position.y(), s.position.z());
        const dQuaternion q = {s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z()};
        dBodySetQuaternion(b, q);
        dBodySetLinearVel(b, s.velocity.x(), s.velocity.y(), s.velocity.z());
        dBodySetAngularVel(b, s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z());
        if (s.awake) {
            dBodyEnable(b);
        } else {
            dBodyDisable(b);
        }
        impl_->slots[ids[k].index].asleep = !s.awake;
        impl_->slots[ids[k].index].idle_steps = s.idle_steps;
        impl_->slots[ids[k].index].sleep_energy = s.sleep_energy;
        impl_->slots[ids[k].index].rest_position = s.rest_position;
        impl_->slots[ids[k].index].rest_orientation = s.rest_orientation;
    }
    impl_->steps = steps;
}

void RigidWorld::add_force_at(BodyId id, const Vec3& force, const Vec3& point) {
    const dBodyID b = impl_->slot(id).body;
    if (!force.allFinite() || !point.allFinite()) {
        throw InputError("add_force_at: force and point must be finite (body " + std::to_string(id.index) + ")");
    }
    dBodyEnable(b);
    impl_->slots[id.index].asleep = false;
    impl_->slots[id.index].idle_steps = 0;
    dBodyAddForceAtPos(b, force.x(), force.y(), force.z(), point.x(), point.y(), point.z());
}

}  // namespace sim
