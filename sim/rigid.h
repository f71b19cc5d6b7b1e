// Rigid bodies through ODE (Debian's libode-dev, 0.16): the lecture's rigid
// bodies (mass, barycenter, inertia tensor), stepped by ODE's solver, with
// contacts from ODE's collider in a hash space.
//
// A thin RAII layer: ODE's init/close, its world, space, contact group and
// bodies live behind RigidWorld; callers hold BodyId {index, generation}
// values (an id of a removed body is detected, not dereferenced). No raw ODE
// handle leaves this file's .cpp.
//
// Determinism: ODE's quickstep shuffles constraints with ODE's one global
// random generator. Before every step the world seeds it from its own seed
// and step count, so two worlds stepped in any interleaving (side-by-side
// videos, the same scene twice in one process) give the same bits as each
// alone.
#pragma once

#include "sim/collisions.h"
#include "sim/vec3_array.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sim {

struct BodyId {
    std::uint32_t index = ~0u;
    std::uint32_t generation = 0;
    bool operator==(const BodyId&) const = default;
};

enum class RigidShape { box, sphere, capsule, cylinder };

// One solid piece of a compound body (a T-handle's bar, a hammer's head),
// placed in the body's shape frame. Its mass counts in proportion to its
// volume times `density`.
struct BodyPart {
    RigidShape shape = RigidShape::box;
    Vec3 size = Vec3(0.5, 0.5, 0.5);                                  // m, as BodyDef::size
    Vec3 offset = Vec3::Zero();                                       // m, of the part's centre in the shape frame
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // of the part in the shape frame
    double density = 1000.0;                                          // kg/m³ (> 0)
};

// A body as a scene describes it: one shape, or (when `parts` is not empty)
// a compound of parts. Mass comes from `mass` if > 0 (the parts keep their
// density ratios), else from the densities and volumes; the inertia tensor
// from the shapes (parallel axis theorem for the parts).
struct BodyDef {
    RigidShape shape = RigidShape::box;
    // box: full extents along x, y, z; sphere: radius = size.x; capsule and
    // cylinder: radius = size.x, length = size.y of the straight part, along
    // the body's local z (ODE's convention).
    Vec3 size = Vec3(0.5, 0.5, 0.5);  // m
    std::vector<BodyPart> parts;      // a compound body: shape and size are ignored
    double mass = 1.0;                // kg (> 0), or 0 to use density
    double density = 1000.0;          // kg/m³ (> 0), when mass is 0
    Vec3 position = Vec3::Zero();     // m, of the centre of mass
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Vec3 velocity = Vec3::Zero();          // m/s
    Vec3 angular_velocity = Vec3::Zero();  // rad/s, world frame
    // A shift of the centre of mass from where the shapes' uniform density
    // puts it (the shape frame's origin for one shape; the mass-weighted mean
    // of the parts' centres for a compound), in the shape frame: a ballast.
    // The body's origin is its centre of mass (the lecture: the barycenter
    // need not be the local origin); the geometry is drawn and collides
    // shifted accordingly.
    Vec3 com = Vec3::Zero();  // m
};

// What ODE can take: past these its checks abort the process (issue 51): its
// hash space's integer cells overflow past kMaxBodyReach (2^28 m at its 1/8 m
// cells, with margin); extreme masses and sizes give its solver NaN, which its
// quaternion normalisation asserts on. validate(BodyDef) and the loader hold
// bodies to them; a body that leaves kMaxBodyReach stops the run (check_bodies).
constexpr double kMinBodyMass = 1e-3;  // kg, each body
constexpr double kMaxBodyMass = 1e6;   // kg
constexpr double kMinBodySize = 1e-3;  // m, each extent, radius or length
constexpr double kMaxBodySize = 1e3;   // m; also a part's offset and com
constexpr double kMaxBodyReach = 1e8;  // m, |x|, |y|, |z| of a body's centre of mass
// A spin past this stops the run (check_bodies): the gyroscopic RK4 step
// overflows a few steps later and ODE asserts on the NaN quaternion.
constexpr double kMaxBodySpin = 1e4;    // rad/s
constexpr double kMinRigidStep = 1e-9;  // s, the least step (ODE divides by it: ERP / h, CFM / h)
constexpr double kMaxJointForce = 1e9;  // N or N·m: joint friction, motor force (past it ODE's solver overflows)

struct RigidSettings {
    Vec3 gravity = Vec3(0, -9.81, 0);  // m/s²
    bool quickstep = true;             // dWorldQuickStep (iterative) or dWorldStep (exact LCP)
    int iterations = 20;               // quickstep iterations per step
    double friction = 0.8;             // Coulomb μ of every contact
    double restitution = 0.1;          // 0 .. 1
    double bounce_velocity = 0.2;      // m/s: slower impacts do not bounce
    // Joints: ODE's error reduction (a share of the gap closed per step) and
    // constraint force mixing. Stiff and unsoftened, ODE's correction acts
    // along the constraint at the step's start and keeps a swing's energy
    // (docs/studies/rigid-closed-forms.md §1: 90° pendulum -38 % -> -1.7 %).
    double joint_erp = 0.8;  // 0 .. 1
    double joint_cfm = 0.0;  // >= 0
    // Contacts and joint stops (the one-sided rows): softer, which keeps a
    // stack from jittering and a ragdoll's limits from fighting its joints.
    double contact_erp = 0.2;    // 0 .. 1
    double contact_cfm = 1e-5;   // >= 0
    bool ground = true;          // a static plane y = ground_height
    double ground_height = 0.0;  // m
    std::uint64_t seed = 1;      // for quickstep's constraint order
    // The gyroscopic term of Euler's equations, I ω̇ = -ω × I ω (what makes
    // a T-handle flip about its intermediate axis). ODE's own treatment is
    // implicit and dissipative: a free spin loses energy and settles about
    // the largest axis (6% in 10 s on the inertia scene's T-handle). Here
    // each step first advances ω in the body frame by RK4 on the torque-free
    // equations, then ODE steps without its term: energy and |L| of a free
    // spin are kept to O(h⁴) per step.
    bool gyroscopic_rk4 = true;
    // A tree of bodies hung from the world by hinges and ball joints (no
    // limits, motors or friction), touching nothing and pushed by nothing
    // else, steps in reduced coordinates (sim/articulated.h): joints exact, a
    // top's precession and a chain's energy kept (the study's §8); else ODE.
    bool articulated = true;
    // Position iterations after ODE's step (as Jolt's): each pulls every
    // ball, hinge and universal joint's two anchors to within position_slop
    // by a nonlinear Gauss-Seidel pass over positions and orientations,
    // velocities left alone; 0: ODE alone. A tumbling ragdoll's joints then
    // stand millimetres apart, not centimetres. The slop leaves a swing's
    // small gap to ERP: pulled at the step's end, along the constraint there,
    // it would lose about (ω h)² of the swing's energy a step (the study's §1).
    int position_iterations = 2;
    double position_slop = 1e-3;  // m
    // Joint stops turned on a step early near a stop (Box2D's speculative
    // limits; see RigidWorld::Impl::speculative_stops): a limb hit hard stops
    // at its limit instead of swinging far past it and creeping back.
    bool speculative_stops = true;
    // Bodies joined by joints, directly or through others (a ragdoll, a
    // chain), collide with each other only if true, and then only when three
    // or more joints apart. Off by default, as in most engines' ragdolls:
    // ODE's iterative solver cannot settle a limb resting on its own torso
    // (a closed loop of contacts and joints), and the ragdoll creeps forever.
    bool self_collision = false;
    // Sleep (ODE's auto-disable): a group of bodies held together by joints
    // (a whole ragdoll at once, or one free body) that for sleep_time has
    // moved no farther than sleep_speed · sleep_time (its mean speed: the
    // iterative solver's jitter in a pile averages out) and has a kinetic
    // energy per kilogram under that of twice sleep_speed, both weighted by
    // mass (hung from the world and touching nothing, so without the
    // solver's jitter: under that of a tenth of sleep_speed at every step,
    // or a pendulum sleeps at a turn), is disabled: not stepped, not counted as moving, until a contact
    // from a moving body or an awake jointed body wakes it. PhysX's default
    // threshold is 0.1 m/s too.
    bool sleep = true;
    double sleep_speed = 0.1;  // m/s, RMS over the group's mass
    double sleep_time = 0.5;   // s
};

// Throws InputError naming the field ("rigid.iterations must be ...").
void validate(const RigidSettings& settings);
void validate(const BodyDef& body);

// The body's mass, kg: `mass`, or the parts' densities times their volumes
// (validated but for the mass's own range, so that a loader can report it).
double mass_of(const BodyDef& body);

// Joints between two bodies (or a body and the world: b invalid).
struct JointId {
    std::uint32_t index = ~0u;
    std::uint32_t generation = 0;
    bool operator==(const JointId&) const = default;
};

enum class JointType { ball, hinge, universal, slider, fixed };

struct JointDef {
    JointType type = JointType::ball;
    BodyId a;                    // first body
    BodyId b;                    // second body; default (invalid): the static world
    Vec3 anchor = Vec3::Zero();  // m, world frame, at creation (ball, hinge, universal)
    Vec3 axis = Vec3::UnitZ();   // unit, world frame: hinge axis, slider direction, universal axis 1
    Vec3 axis2 = Vec3::UnitX();  // unit, universal axis 2 (perpendicular to axis)
    // Limits on the (first) axis: rad for hinge and universal, m for slider;
    // lo > hi means no limit. Stops are springs of stop_stiffness and
    // stop_damping, turned into ODE's ERP and CFM for each step's h
    // (see erp_cfm), so scenes speak in N·m/rad and N·m·s/rad.
    double lo = 1.0, hi = -1.0;
    double stop_stiffness = 0.0;  // 0: ODE's rigid stops (world ERP, no CFM)
    double stop_damping = 0.0;
    // Universal joints: limits on axis2 (rad). Ball joints: swing and twist
    // limits through an angular motor (ODE's AMotor in Euler mode), with
    // `axis` fixed in body a and `axis2` fixed in body b (the twist axis, along
    // b's bone), perpendicular at creation: [lo, hi] bounds the rotation
    // about `axis`, [lo2, hi2] the rotation about axis2 × axis (within
    // ±90°: the swing region is a box in these two angles, not a round
    // cone), [lo3, hi3] the twist about axis2. Limits on a ball joint need
    // body b.
    double lo2 = 1.0, hi2 = -1.0;
    double lo3 = 1.0, hi3 = -1.0;
    // A velocity motor on the (first) axis: rad/s or m/s, up to max_force
    // (N·m or N); max_force 0 is no motor. A motor with velocity 0 is joint
    // friction. On a universal joint and a limited ball joint the other axes
    // get the same max force at velocity 0: friction.
    double motor_velocity = 0.0;
    double motor_max_force = 0.0;
};

// ERP and CFM of a constraint that behaves like a spring kp and damper kd at
// step h (ODE manual, "Using ERP and CFM as a spring"):
//   ERP = h kp / (h kp + kd),   CFM = 1 / (h kp + kd).
struct ErpCfm {
    double erp = 0.0;
    double cfm = 0.0;
};
ErpCfm erp_cfm(double h, double kp, double kd);

struct BodyState {
    Vec3 position = Vec3::Zero();  // m, centre of mass
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Vec3 velocity = Vec3::Zero();          // m/s
    Vec3 angular_velocity = Vec3::Zero();  // rad/s, world frame
    bool awake = true;                     // false: asleep (RigidSettings::sleep)
    std::uint32_t idle_steps = 0;          // its group's steps in a row at rest (sleep)
    double sleep_energy = 0.0;             // J/kg, its group's smoothed kinetic energy per kilogram
    Vec3 rest_position = Vec3::Zero();     // m, where its group's rest window started
    Eigen::Quaterniond rest_orientation = Eigen::Quaterniond::Identity();
};

// A body's piece where it is now: for drawing, and for particles colliding
// with bodies. size is as BodyDef::size.
struct PlacedPart {
    BodyId body;
    RigidShape shape = RigidShape::box;
    Vec3 size = Vec3::Zero();    // m
    Vec3 center = Vec3::Zero();  // m, world frame
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// What a scene's rigid part is: settings, bodies, and joints naming bodies
// by their index in `bodies` (-1: the static world).
struct RigidJoint {
    JointDef joint;  // its a and b are ignored: the indices below name the bodies
    int a = 0;
    int b = -1;
};
struct RigidModel {
    RigidSettings settings;
    std::vector<BodyDef> bodies;
    std::vector<RigidJoint> joints;
    bool empty() const { return bodies.empty(); }
};

// A jointed pair's mass ratio, heavier / lighter. Above kSlowMassRatio the
// iterative solver (quickstep) converges slowly on the pair: a chain under a
// heavy ball stretches. The scene loader and the ragdoll builder warn.
constexpr double kSlowMassRatio = 10.0;
inline double mass_ratio(double a, double b) { return std::max(a, b) / std::min(a, b); }

// ODE keeps data per thread. A thread that steps rigid worlds made on
// another thread calls this first (video steps its scenes on a thread of
// their own), once the worlds exist; the thread that made a world need not.
// The data is freed when the thread exits.
void prepare_rigid_thread();

class RigidWorld {
public:
    explicit RigidWorld(const RigidSettings& settings = {});
    // Every body and joint of the model, in order: body k gets id {k, 0}.
    explicit RigidWorld(const RigidModel& model);
    ~RigidWorld();
    RigidWorld(const RigidWorld&) = delete;
    RigidWorld& operator=(const RigidWorld&) = delete;

    BodyId add_body(const BodyDef& body);  // validates (InputError)
    // Static geometry: bodies collide with it, it never moves. Used for the
    // scene's particle colliders, so one static world serves both.
    void add_static(const Collider& collider);
    void remove_body(BodyId id);  // InputError for a stale id
    bool alive(BodyId id) const;
    std::size_t body_count() const;

    void step(double dt);  // dt > 0 (InputError); collisions, then the solver
    std::uint64_t steps() const;
    std::size_t contacts() const;  // contact joints made in the last step

    JointId add_joint(const JointDef& joint);  // validates (InputError): live bodies, unit axes
    void remove_joint(JointId id);
    // How far apart the joint's anchor is on its two bodies, m (ball, hinge,
    // universal; 0 for others): 0 when the joint is exactly satisfied.
    double joint_separation(JointId id) const;
    // Hinge or universal angle (rad) or slider position (m) relative to creation.
    double joint_position(JointId id) const;

    BodyState state(BodyId id) const;          // InputError for a stale id
    double mass(BodyId id) const;              // kg
    Eigen::Matrix3d inertia(BodyId id) const;  // kg·m², body frame, about the centre of mass
    bool awake(BodyId id) const;
    std::size_t awake_count() const;
    // Every part of every live body, in body index order.
    std::vector<PlacedPart> placed_parts() const;
    double kinetic_energy() const;    // J, ½ m v² + ½ ωᵀ I ω over all bodies
    double potential_energy() const;  // J, -m g·x over all bodies
    Vec3 momentum() const;            // kg·m/s, Σ m v over all bodies
    // kg·m²/s, about the world origin: Σ x × m v + R I Rᵀ ω over all bodies.
    Vec3 angular_momentum() const;
    // FNV-1a over every live body's position, orientation and velocities.
    std::uint64_t hash() const;
    // What ODE's solver reported while this world stepped (ODE prints these
    // to stderr by default): each message once, with how many steps said it,
    // e.g. "LCP internal error, s <= 0 (s=0.0000e+00) (3 times)" from the
    // exact solver meeting a degenerate contact set.
    std::vector<std::string> solver_messages() const;

    // Every body's state (index order; removed bodies skipped) and the step
    // count: what a snapshot of a world needs, and what restores it.
    std::vector<BodyState> body_states() const;
    void set_body_states(const std::vector<BodyState>& states, std::uint64_t steps);
    std::vector<BodyId> bodies() const;  // live ids, index order

    // A force (N) at a world point (m) for the next step only (ODE clears a
    // body's accumulated forces after each step), waking the body: the
    // viewer's mouse drag. InputError for a stale id or a non-finite value.
    void add_force_at(BodyId id, const Vec3& force, const Vec3& point);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace sim
