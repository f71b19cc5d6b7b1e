// RigidWorld's private parts (its Impl), shared by the files that implement
// it: rigid.cpp (bodies, the step, queries), rigid_joints.cpp (joints, their
// stops), rigid_contacts.cpp (which pairs collide, contact parameters),
// rigid_stabilize.cpp (gyroscopic RK4, positional stabilisation) and
// rigid_sleep.cpp (sleep by jointed group), rigid_articulated.cpp (trees in
// reduced coordinates). Only sim/rigid*.cpp include it:
// no ODE type appears in sim's public headers.
#pragma once

#include "sim/error.h"
#include "sim/rigid.h"

#include <ode/ode.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sim {
namespace rigid_detail {

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

class OdeLibrary {
public:
    OdeLibrary();
    ~OdeLibrary();
    OdeLibrary(const OdeLibrary&) = delete;
    OdeLibrary& operator=(const OdeLibrary&) = delete;
};

inline Vec3 to_vec(const dReal* v) { return {v[0], v[1], v[2]}; }

}  // namespace rigid_detail

struct RigidWorld::Impl {
    rigid_detail::OdeLibrary library;
    RigidSettings settings;
    dWorldID world = nullptr;
    dSpaceID space = nullptr;
    dJointGroupID contact_group = nullptr;
    dGeomID ground = nullptr;
    std::vector<dGeomID> statics;  // the ground and add_static's geoms: what the swept test sees
    dGeomID ray = nullptr;         // the swept test's, in no space
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
        bool asleep = false;         // disabled by sleep (ODE may wake it)
        Vec3 before = Vec3::Zero();  // m, its centre of mass before this step (the swept test)
        bool touched = false;        // a contact this step (sleep: a group touching nothing has no jitter)
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
    rigid_detail::SolverMessages messages;
    std::vector<std::uint32_t> group_of;                        // union-find parents over body slots: jointed groups
    std::vector<double> group_energy, group_moved, group_mass;  // sleep's scratch, by group root
    std::vector<char> group_woken;                              // ... and whether its window starts again this step
    std::vector<char> group_touched;                            // ... whether it touched anything this step
    std::vector<char> group_hung;                               // ... and whether a joint holds it to the world

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

    // Joints and their stops (rigid_joints.cpp).
    // Sets a joint parameter on axis 0, 1 or 2 of the joint (a ball joint's
    // axes are its angular motor's), whatever its type.
    static void set_param(const JointSlot& js, int param, double value, int axis = 0);
    // A limited axis's position (rad or m) and rate now, for speculative stops.
    static bool axis_motion(const JointSlot& js, int axis, double& position, double& rate);
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
    void speculative_stops(double h);
    // Stop ERP/CFM from stiffness and damping at step h.
    void update_stops(double h);
    // Where a joint's anchor is on each of its bodies, world frame, m.
    static bool anchors(const JointSlot& js, Vec3& p1, Vec3& p2);

    // Contacts (rigid_contacts.cpp).
    static std::uint32_t index_of(dBodyID body);
    // Bodies one or two joints apart do not collide (parent and child,
    // grandparent and grandchild, siblings): in a ragdoll their shapes meet
    // at every joint and the contacts fight the joints, so that a ragdoll
    // at rest creeps and never sleeps (Jolt's ragdolls filter the same
    // pairs). Farther bodies (a hand and a thigh) collide.
    static bool jointed_within_two(dBodyID a, dBodyID b);
    // ODE's broad phase calls this for each pair of geoms whose boxes overlap.
    static void near_callback(void* data, dGeomID a, dGeomID b);

    // What the step adds to ODE's solver (rigid_stabilize.cpp).
    // ω over h by RK4 on Euler's torque-free equations in the body frame,
    // I ω̇ = -ω × I ω (see RigidSettings::gyroscopic_rk4).
    void gyroscopic(double h);
    // Position iterations (RigidSettings::position_iterations): for each
    // joint, the anchor gap C = |p2 - p1| along n is closed by a positional
    // impulse λ = C / (w1 + w2), with each body's generalised inverse mass
    // w = 1/m + (r × n)ᵀ I⁻¹ (r × n) (r: from its centre of mass to its
    // anchor): x += λ n / m, and a rotation I⁻¹ (r × λ n) applied to its
    // quaternion. A body asleep or the static world does not move.
    void stabilize();
    // The swept test (continuous collision against static geometry): a body
    // that moved more than half its thinnest extent in the step is traced
    // from where it was (begin_step) to where it is by a ray against
    // the ground and the static geoms; at the nearest hit it stops its
    // thinnest half extent short, along the hit's normal, and its normal
    // velocity bounces with the contacts' restitution (rigid_contacts.cpp).
    // Before the step: each body's position (the swept test), no contact yet.
    void begin_step();
    void sweep();

    // Reduced coordinates (rigid_articulated.cpp): this step's trees hung
    // from the world, each root first, its bodies' slots, the joint to each
    // one's parent (its index in `slots` of the tree; -1 the world) and spin.
    struct Tree {
        std::vector<std::uint32_t> slots, joints;
        std::vector<int> parents;
        std::vector<Vec3> spin;  // rad/s, before the gyroscopic pass
    };
    std::vector<Tree> trees;
    void find_trees();
    void hold_trees();
    void step_trees(double h);

    // Sleep (rigid_sleep.cpp).
    // Slow enough to fall asleep: the body's group's smoothed kinetic energy
    // per kilogram within sleep's limit, that of twice sleep_speed.
    bool slow(dBodyID body) const;
    std::uint32_t find(std::uint32_t i);
    // The groups of bodies joined by joints (a ragdoll, a chain): union-find
    // over the body slots, rebuilt every step (joints come and go).
    void build_groups();
    // Kinetic energy of a body, ½ m v² + ½ ωᵀ I ω (J).
    double kinetic(const Slot& s) const;
    // How far a body has moved from its rest pose, weighted: m |Δx|² + Δθᵀ I Δθ
    // (kg·m²), Δθ its turn in its own frame.
    double displacement(const Slot& s) const;
    // Puts to sleep the groups at rest for sleep_time; the rule is written
    // above its definition.
    void sleep(double h);
};

}  // namespace sim
