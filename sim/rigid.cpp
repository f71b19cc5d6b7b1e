#include "sim/rigid.h"

#include "sim/error.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <variant>
#include <mutex>
#include <numbers>

namespace sim {

namespace {

// ODE's init/close, reference-counted: the first world initialises the
// library, the last one closes it.
class OdeLibrary {
public:
    OdeLibrary() {
        const std::lock_guard lock(mutex());
        if (count()++ == 0) dInitODE2(0);
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
    require_positive(s.sleep_angular_speed, "rigid.sleep_angular_speed", "rad/s");
    require_positive(s.sleep_time, "rigid.sleep_time", "s");
}

namespace {

int size_components(RigidShape shape) {
    return shape == RigidShape::box ? 3 : shape == RigidShape::sphere ? 1 : 2;
}

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
        std::uint32_t idle_steps = 0;  // steps in a row below the sleep speeds
        bool asleep = false;           // disabled by sleep (ODE may wake it)
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
    std::vector<std::uint32_t> group_of;  // sleep: union-find parents over body slots

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

    // ODE's broad phase calls this for each pair of geoms whose boxes overlap.
    static void near_callback(void* data, dGeomID a, dGeomID b) {
        auto* self = static_cast<Impl*>(data);
        dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
        // Nothing to do unless one side moves: static against static, asleep
        // against asleep or static.
        const bool moving_a = ba != nullptr && dBodyIsEnabled(ba), moving_b = bb != nullptr && dBodyIsEnabled(bb);
        if (!moving_a && !moving_b) return;
        if (ba == bb) return;  // parts of one compound body
        if (ba != nullptr && bb != nullptr && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
        dContact contact[kMaxContacts];
        const int n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
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

    std::uint32_t find(std::uint32_t i) {
        while (group_of[i] != i) i = group_of[i] = group_of[group_of[i]];
        return i;
    }

    // Sleep: count each body's quiet steps; a group of jointed bodies whose
    // every body has been quiet for sleep_time is disabled at rest. A body
    // that ODE re-enabled (a contact or a joint to an awake body) starts
    // counting again.
    void sleep(double h) {
        const double ls2 = settings.sleep_speed * settings.sleep_speed;
        const double as2 = settings.sleep_angular_speed * settings.sleep_angular_speed;
        const auto needed = static_cast<std::uint32_t>(std::ceil(settings.sleep_time / h));
        group_of.resize(slots.size());
        for (std::uint32_t i = 0; i < slots.size(); ++i) {
            group_of[i] = i;
            Slot& s = slots[i];
            if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
            if (s.asleep) {  // woken by ODE
                s.asleep = false;
                s.idle_steps = 0;
            }
            const bool quiet = to_vec(dBodyGetLinearVel(s.body)).squaredNorm() < ls2 &&
                               to_vec(dBodyGetAngularVel(s.body)).squaredNorm() < as2;
            s.idle_steps = quiet ? s.idle_steps + 1 : 0;
        }
        for (const JointSlot& js : joints) {
            if (js.joint == nullptr || js.def.b == BodyId{}) continue;
            const std::uint32_t ra = find(js.def.a.index), rb = find(js.def.b.index);
            group_of[std::max(ra, rb)] = std::min(ra, rb);
        }
        // A group sleeps when none of its awake bodies is short of `needed`.
        std::vector<char> stays_awake(slots.size(), 0);
        for (std::uint32_t i = 0; i < slots.size(); ++i) {
            const Slot& s = slots[i];
            if (s.body != nullptr && !s.asleep && s.idle_steps < needed) stays_awake[find(i)] = 1;
        }
        for (std::uint32_t i = 0; i < slots.size(); ++i) {
            Slot& s = slots[i];
            if (s.body == nullptr || s.asleep || stays_awake[find(i)]) continue;
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
    const Vec3 com = centroid + def.com;  // the ballast shift keeps that inertia

    dBodyID body = dBodyCreate(m.world);
    dBodySetMass(body, &mass);
    std::vector<dGeomID> geoms;
    for (BodyPart& part : parts) {
        part.offset -= com;  // from now on relative to the centre of mass
        dGeomID geom = create_geom(m.space, part.shape, part.size);
        dGeomSetBody(geom, body);
        if (part.offset != Vec3::Zero()) dGeomSetOffsetPosition(geom, part.offset.x(), part.offset.y(), part.offset.z());
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

    std::uint32_t index;
    if (!m.free_slots.empty()) {
        index = m.free_slots.back();
        m.free_slots.pop_back();
    } else {
        index = static_cast<std::uint32_t>(m.slots.size());
        m.slots.emplace_back();
    }
    Impl::Slot& s = m.slots[index];
    s.body = body;
    s.geoms = std::move(geoms);
    s.parts = std::move(parts);
    s.idle_steps = 0;
    s.asleep = false;
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
    m.contacts = 0;
    dSpaceCollide(m.space, &m, &Impl::near_callback);
    if (m.settings.quickstep) {
        dWorldQuickStep(m.world, dt);
    } else {
        dWorldStep(m.world, dt);
    }
    dJointGroupEmpty(m.contact_group);
    if (m.settings.sleep) m.sleep(dt);
    ++m.steps;
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
    const bool ball_limits = def.type == JointType::ball && (def.lo <= def.hi || def.lo2 <= def.hi2 || def.lo3 <= def.hi3);
    if ((def.type == JointType::universal || ball_limits) && std::abs(def.axis.dot(def.axis2)) > 1e-6) {
        throw InputError("joint.axis2 must be perpendicular to joint.axis for a universal joint or a limited ball joint");
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
    const auto& js = impl_->joint(id);
    dVector3 p1, p2;
    switch (js.def.type) {
        case JointType::ball:
            dJointGetBallAnchor(js.joint, p1);
            dJointGetBallAnchor2(js.joint, p2);
            break;
        case JointType::hinge:
            dJointGetHingeAnchor(js.joint, p1);
            dJointGetHingeAnchor2(js.joint, p2);
            break;
        case JointType::universal:
            dJointGetUniversalAnchor(js.joint, p1);
            dJointGetUniversalAnchor2(js.joint, p2);
            break;
        default:
            return 0.0;
    }
    return (to_vec(p1) - to_vec(p2)).norm();
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
    for (std::uint32_t i = 0; i < impl_->slots.size(); ++i) {
        const auto& s = impl_->slots[i];
        if (s.body == nullptr) continue;
        const BodyId id{i, s.generation};
        const BodyState st = state(id);
        const Eigen::Matrix3d R = st.orientation.toRotationMatrix();
        const Vec3 w_body = R.transpose() * st.angular_velocity;
        e += 0.5 * mass(id) * st.velocity.squaredNorm() + 0.5 * w_body.dot(inertia(id) * w_body);
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
    }
    impl_->steps = steps;
}

}  // namespace sim
