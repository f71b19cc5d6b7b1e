// RigidWorld: the ODE library's lifetime and messages, bodies and static
// colliders, the step (its stages in order), and the queries. Joints,
// contacts, stabilisation and sleep have their own files (rigid_impl.h).
#include "sim/rigid.h"

#include "sim/error.h"
#include "sim/rigid_impl.h"
#include "sim/rotation.h"
#include "sim/state_hash.h"

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

using rigid_detail::SolverMessages;
using rigid_detail::to_vec;

namespace {

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

std::mutex& ode_mutex() {
    static std::mutex m;
    return m;
}
int& ode_users() {
    static int n = 0;
    return n;
}

}  // namespace

namespace rigid_detail {

OdeLibrary::OdeLibrary() {
    const std::lock_guard lock(ode_mutex());
    if (ode_users()++ == 0) {
        dInitODE2(0);
        dSetMessageHandler(&on_ode_message);
    }
    dAllocateODEDataForThread(dAllocateMaskAll);
}
OdeLibrary::~OdeLibrary() {
    const std::lock_guard lock(ode_mutex());
    if (--ode_users() == 0) dCloseODE();
}

}  // namespace rigid_detail

// ODE was initialised with automatic tracking (dInitODE2(0)): the thread's
// data is freed when it exits, and an explicit cleanup is not allowed. Where
// no world exists, ODE is not initialised and there is nothing to prepare.
void prepare_rigid_thread() {
    const std::lock_guard lock(ode_mutex());
    if (ode_users() > 0) dAllocateODEDataForThread(dAllocateMaskAll);
}

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
    for (const auto& [erp, name] : {std::pair{s.joint_erp, "joint_erp"}, {s.contact_erp, "contact_erp"}}) {
        if (!(erp > 0.0 && erp <= 1.0))
            throw InputError(std::string("rigid.") + name + " must be within 0 .. 1 (got " + format_value(erp) + ")");
    }
    require_nonnegative(s.joint_cfm, "rigid.joint_cfm", "");
    require_nonnegative(s.contact_cfm, "rigid.contact_cfm", "");
    if (!std::isfinite(s.ground_height)) throw InputError("rigid.ground_height must be finite, in m");
    require_positive(s.sleep_speed, "rigid.sleep_speed", "m/s");
    require_positive(s.sleep_time, "rigid.sleep_time", "s");
    require_nonnegative(s.position_slop, "rigid.position_slop", "m");
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

void require_within(double value, double lo, double hi, const std::string& name, const char* unit) {
    if (!(value >= lo && value <= hi)) {
        throw InputError(name + " must be within " + format_value(lo) + " .. " + format_value(hi) + ", in " + unit +
                         " (got " + format_value(value) + ")");
    }
}

void require_size(const Vec3& size, RigidShape shape, const std::string& name) {
    for (int k = 0; k < size_components(shape); ++k) require_within(size[k], kMinBodySize, kMaxBodySize, name, "m");
}

std::vector<BodyPart> parts_of(const BodyDef& def);
dMass mass_of_parts(const std::vector<BodyPart>& parts, double total);

// Everything but the mass's range (mass_of reports the mass of such a body).
void validate_shape(const BodyDef& b) {
    if (b.parts.empty()) require_size(b.size, b.shape, "body.size");
    for (std::size_t p = 0; p < b.parts.size(); ++p) {
        const BodyPart& part = b.parts[p];
        const std::string name = "body.parts[" + std::to_string(p) + "]";
        require_size(part.size, part.shape, name + ".size");
        require_positive(part.density, name + ".density", "kg/m³");
        if (!(part.offset.cwiseAbs().maxCoeff() <= kMaxBodySize))
            throw InputError(name + ".offset must be within +-" + format_value(kMaxBodySize) + ", in m");
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
    if (!(b.position.cwiseAbs().maxCoeff() <= kMaxBodyReach))
        throw InputError("body.position must be within +-" + format_value(kMaxBodyReach) + ", in m");
    if (!(b.com.cwiseAbs().maxCoeff() <= kMaxBodySize))
        throw InputError("body.com must be within +-" + format_value(kMaxBodySize) + ", in m");
    require_unit(b.orientation, "body.orientation");
}

}  // namespace

void validate(const BodyDef& b) {
    validate_shape(b);
    require_within(mass_of_parts(parts_of(b), b.mass).mass, kMinBodyMass, kMaxBodyMass, "body mass", "kg");
}

RigidWorld::RigidWorld(const RigidSettings& settings) : impl_(std::make_unique<Impl>()) {
    validate(settings);
    Impl& m = *impl_;
    m.settings = settings;
    m.world = dWorldCreate();
    dWorldSetGravity(m.world, settings.gravity.x(), settings.gravity.y(), settings.gravity.z());
    dWorldSetERP(m.world, settings.joint_erp);  // contacts set their own
    dWorldSetCFM(m.world, settings.joint_cfm);
    dWorldSetQuickStepNumIterations(m.world, settings.iterations);
    m.space = dHashSpaceCreate(nullptr);
    m.contact_group = dJointGroupCreate(0);
    if (settings.ground) m.ground = dCreatePlane(m.space, 0, 1, 0, settings.ground_height);
    if (m.ground != nullptr) m.statics.push_back(m.ground);
    m.ray = dCreateRay(nullptr, 1.0);  // in no space: the swept test's alone
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
    dGeomDestroy(m.ray);
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
    validate_shape(def);
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
                m.statics.push_back(dCreatePlane(m.space, c.normal.x(), c.normal.y(), c.normal.z(), c.offset));
            } else if constexpr (std::is_same_v<T, SphereCollider>) {
                dGeomID g = dCreateSphere(m.space, c.radius);
                dGeomSetPosition(g, c.center.x(), c.center.y(), c.center.z());
                m.statics.push_back(g);
            } else if constexpr (std::is_same_v<T, BoxCollider>) {
                const Vec3 full = 2.0 * c.half_extents;
                m.statics.push_back(dCreateBox(m.space, full.x(), full.y(), full.z()));
                place(m.statics.back(), c.center, c.rotation);
            } else {  // capsule: ODE's lies along its local z
                const Vec3 axis = c.b - c.a;
                const double length = axis.norm();
                const Eigen::Matrix3d R =
                    length > 0.0 ? rotation_from_z(axis / length).toRotationMatrix() : Eigen::Matrix3d::Identity();
                m.statics.push_back(dCreateCapsule(m.space, c.radius, length));
                place(m.statics.back(), 0.5 * (c.a + c.b), R);
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
    if (!(dt >= kMinRigidStep) || !std::isfinite(dt)) {
        throw InputError("a rigid step must be at least " + format_value(kMinRigidStep) + " s and finite (got " +
                         format_value(dt) + ")");
    }
    Impl& m = *impl_;
    // ODE's one random generator, seeded by this world alone (see the header).
    dRandSetSeed(static_cast<unsigned long>(m.settings.seed * 0x9E3779B97F4A7C15ull + m.steps));
    m.update_stops(dt);
    if (m.settings.speculative_stops) m.speculative_stops(dt);
    m.build_groups();
    if (m.settings.articulated) m.find_trees();
    if (m.settings.gyroscopic_rk4) m.gyroscopic(dt);
    m.begin_step();
    m.contacts = 0;
    dSpaceCollide(m.space, &m, &Impl::near_callback);
    m.hold_trees();  // trees touching nothing leave ODE's step
    g_stepping = &m.messages;
    if (m.settings.quickstep) {
        dWorldQuickStep(m.world, dt);
    } else {
        dWorldStep(m.world, dt);
    }
    g_stepping = nullptr;
    m.step_trees(dt);
    dJointGroupEmpty(m.contact_group);
    m.sweep();
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

Vec3 RigidWorld::momentum() const {
    Vec3 p = Vec3::Zero();
    for (const BodyId id : bodies()) p += mass(id) * state(id).velocity;
    return p;
}

Vec3 RigidWorld::angular_momentum() const {
    Vec3 l = Vec3::Zero();
    for (const BodyId id : bodies()) {
        const BodyState s = state(id);
        const Eigen::Matrix3d R = s.orientation.toRotationMatrix();
        l += s.position.cross(mass(id) * s.velocity) + R * inertia(id) * R.transpose() * s.angular_velocity;
    }
    return l;
}

std::uint64_t RigidWorld::hash() const {
    Fnv1a h;
    for (const auto& s : impl_->slots) {
        if (s.body == nullptr) continue;
        for (const dReal* v : {dBodyGetPosition(s.body), dBodyGetLinearVel(s.body), dBodyGetAngularVel(s.body)}) {
            for (int k = 0; k < 3; ++k) h.add(v[k]);
        }
        const dReal* q = dBodyGetQuaternion(s.body);
        for (int k = 0; k < 4; ++k) h.add(q[k]);
    }
    return h.value();
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
