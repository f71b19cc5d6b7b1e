#include "sim/rigid.h"

#include "sim/error.h"

#include <ode/ode.h>

#include <cmath>
#include <cstring>
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

constexpr int kMaxContacts = 8;  // per colliding pair of geoms

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
}

void validate(const BodyDef& b) {
    for (int k = 0; k < (b.shape == RigidShape::box ? 3 : b.shape == RigidShape::sphere ? 1 : 2); ++k) {
        require_positive(b.size[k], "body.size", "m");
    }
    if (b.mass == 0.0) {
        require_positive(b.density, "body.density", "kg/m³");
    } else {
        require_positive(b.mass, "body.mass", "kg");
    }
    if (!b.position.allFinite() || !b.velocity.allFinite() || !b.angular_velocity.allFinite() || !b.com.allFinite()) {
        throw InputError("body.position, velocity, angular_velocity and com must be finite");
    }
    if (!b.orientation.coeffs().allFinite() || std::abs(b.orientation.norm() - 1.0) > 1e-6) {
        throw InputError("body.orientation must be a unit quaternion");
    }
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
        dGeomID geom = nullptr;
        std::uint32_t generation = 0;
    };
    std::vector<Slot> slots;
    std::vector<std::uint32_t> free_slots;
    struct JointSlot {
        dJointID joint = nullptr;
        JointDef def;
        std::uint32_t generation = 0;
    };
    std::vector<JointSlot> joints;
    std::vector<std::uint32_t> free_joints;
    double stops_h = 0.0;  // the step the stop ERP/CFM were computed for
    std::uint64_t steps = 0;
    std::size_t contacts = 0;

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

    // Sets a joint parameter on the joint's first axis, whatever its type.
    static void set_param(dJointID j, JointType type, int param, double value) {
        switch (type) {
            case JointType::hinge:
                dJointSetHingeParam(j, param, value);
                break;
            case JointType::slider:
                dJointSetSliderParam(j, param, value);
                break;
            case JointType::universal:
                dJointSetUniversalParam(j, param, value);
                break;
            case JointType::ball:
                dJointSetBallParam(j, param, value);
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
            set_param(js.joint, js.def.type, dParamStopERP, e.erp);
            set_param(js.joint, js.def.type, dParamStopCFM, e.cfm);
        }
    }

    // ODE's broad phase calls this for each pair of geoms whose boxes overlap.
    static void near_callback(void* data, dGeomID a, dGeomID b) {
        auto* self = static_cast<Impl*>(data);
        dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
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
    }
    dJointGroupDestroy(m.contact_group);
    dSpaceDestroy(m.space);  // destroys its geoms (the space owns them by default)
    dWorldDestroy(m.world);  // and the bodies
}

BodyId RigidWorld::add_body(const BodyDef& def) {
    validate(def);
    Impl& m = *impl_;
    dMass mass;
    const double rho = def.mass > 0.0 ? 1.0 : def.density;  // scaled to `mass` below when given
    dGeomID geom = nullptr;
    switch (def.shape) {
        case RigidShape::box:
            dMassSetBox(&mass, rho, def.size.x(), def.size.y(), def.size.z());
            geom = dCreateBox(m.space, def.size.x(), def.size.y(), def.size.z());
            break;
        case RigidShape::sphere:
            dMassSetSphere(&mass, rho, def.size.x());
            geom = dCreateSphere(m.space, def.size.x());
            break;
        case RigidShape::capsule:
            dMassSetCapsule(&mass, rho, 3, def.size.x(), def.size.y());
            geom = dCreateCapsule(m.space, def.size.x(), def.size.y());
            break;
        case RigidShape::cylinder:
            dMassSetCylinder(&mass, rho, 3, def.size.x(), def.size.y());
            geom = dCreateCylinder(m.space, def.size.x(), def.size.y());
            break;
    }
    if (def.mass > 0.0) dMassAdjust(&mass, def.mass);
    dBodyID body = dBodyCreate(m.world);
    dBodySetMass(body, &mass);  // about the body origin = the centre of mass
    dGeomSetBody(geom, body);
    if (def.com != Vec3::Zero()) dGeomSetOffsetPosition(geom, -def.com.x(), -def.com.y(), -def.com.z());
    dBodySetPosition(body, def.position.x(), def.position.y(), def.position.z());
    const dQuaternion q = {def.orientation.w(), def.orientation.x(), def.orientation.y(), def.orientation.z()};
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
    s.geom = geom;
    return {index, s.generation};
}

void RigidWorld::remove_body(BodyId id) {
    Impl& m = *impl_;
    const Impl::Slot& s = m.slot(id);
    dGeomDestroy(s.geom);
    dBodyDestroy(s.body);
    Impl::Slot& mut = m.slots[id.index];
    mut.body = nullptr;
    mut.geom = nullptr;
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
    if (def.type == JointType::universal && std::abs(def.axis.dot(def.axis2)) > 1e-6) {
        throw InputError("joint.axis2 must be perpendicular to joint.axis for a universal joint");
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
    if (def.lo <= def.hi && def.type != JointType::ball && def.type != JointType::fixed) {
        Impl::set_param(j, def.type, dParamLoStop, def.lo);
        Impl::set_param(j, def.type, dParamHiStop, def.hi);
    }
    if (def.motor_max_force > 0.0) {
        Impl::set_param(j, def.type, dParamVel, def.motor_velocity);
        Impl::set_param(j, def.type, dParamFMax, def.motor_max_force);
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
    m.joints[index].def = def;
    m.stops_h = 0.0;  // recompute stop ERP/CFM at the next step
    return {index, m.joints[index].generation};
}

void RigidWorld::remove_joint(JointId id) {
    Impl& m = *impl_;
    dJointDestroy(m.joint(id).joint);
    m.joints[id.index].joint = nullptr;
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
    return s;
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
        dBodyEnable(b);
    }
    impl_->steps = steps;
}

}  // namespace sim
