// The report's rigid problems, as every simulator builds them: a hinged rod
// released at 90°, a heavy symmetric top in steady precession, a chain of 8
// hinged links released horizontal (the cases of
// tests/sim/rigid_accuracy_test.cpp and docs/studies/rigid-closed-forms.md),
// and RigidRun, one simulator of one problem at one step as the measuring
// loop (report_rigid.cpp) sees it: ours through sim::RigidWorld, Bullet's
// two solvers (report_rigid_peers.cpp). Private to scenes/report.
#pragma once

#include "sim/analytic.h"
#include "sim/vec3_array.h"

#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

namespace scenes::report {

inline constexpr double kRigidG = 9.81;  // m/s², straight down (-y)

// A 1 kg box rod 0.1 x 1.0 x 0.1 m hinged about z at its top end (the
// origin), released from rest at θ0 = 90° from hanging straight down.
struct RigidPendulum {
    static constexpr double m = 1.0, length = 1.0, width = 0.1;  // kg, m, m
    static constexpr double d = 0.5;                             // m, hinge to centre of mass
    static constexpr double theta0 = std::numbers::pi / 2.0;     // rad
    static constexpr double inertia = m * (length * length + width * width) / 12.0 + m * d * d;  // kg·m², at the hinge
    // T = 4 √(I / m g d) K(sin(θ0 / 2)), s.
    static double period() { return sim::analytic::pendulum_period(inertia / (m * d), kRigidG, theta0); }  // s
    static double swing_energy() { return m * kRigidG * d * (1.0 - std::cos(theta0)); }                    // J
    static sim::Vec3 center() { return d * sim::Vec3(std::sin(theta0), -std::cos(theta0), 0.0); }          // m
    static Eigen::Quaterniond orientation() {
        return Eigen::Quaterniond(Eigen::AngleAxisd(theta0, sim::Vec3::UnitZ()));
    }
};

// A disc (a cylinder along its local z) on a massless stem, ball-jointed to
// the world at the stem's tip (the origin), l from the disc's centre; tilted
// θ from the vertical, spin ω3 along its axis, in steady precession about +y
// at Ω, the slow root of I1 Ω² cos θ - I3 ω3 Ω + m g l = 0 (the study's §2).
struct RigidTop {
    static constexpr double m = 1.0, radius = 0.2, thickness = 0.02, l = 0.1;                  // kg, m, m, m
    static constexpr double tilt = std::numbers::pi / 6.0;                                     // rad
    static constexpr double spin = 50.0;                                                       // rad/s, ω3
    static constexpr double precession_span = 2.0;                                             // s, the rate's
    static constexpr double i3 = m * radius * radius / 2.0;                                    // kg·m²
    static constexpr double i1c = m * (3.0 * radius * radius + thickness * thickness) / 12.0;  // kg·m², at the centre
    static constexpr double i1 = i1c + m * l * l;                                              // kg·m², at the tip
    static double precession() {                                                               // rad/s
        const double c = std::cos(tilt), b = i3 * spin;
        return (b - std::sqrt(b * b - 4.0 * i1 * m * kRigidG * l * c)) / (2.0 * i1 * c);
    }
    static sim::Vec3 axis() { return sim::Vec3(std::sin(tilt), std::cos(tilt), 0.0); }  // unit
    static sim::Vec3 center() { return l * axis(); }                                    // m
    static Eigen::Quaterniond orientation() {                                           // local z onto the axis
        return Eigen::Quaterniond::FromTwoVectors(sim::Vec3::UnitZ(), axis());
    }
    static sim::Vec3 angular_velocity() {  // rad/s, world frame: ω = Ω ŷ + (ω3 - Ω cos θ) a
        const double w = precession();
        return w * sim::Vec3::UnitY() + (spin - w * std::cos(tilt)) * axis();
    }
    static sim::Vec3 velocity() { return angular_velocity().cross(center()); }  // m/s, of the centre
};

// Links 0.25 x 0.05 x 0.05 m, 1 kg, hinged about z end to end along +x, the
// first to the world at the origin, released horizontal from rest.
struct RigidChain {
    static constexpr int links = 8;
    static constexpr double m = 1.0, length = 0.25, width = 0.05;  // kg, m, m
    // J: the fall to hanging straight down, m g L (0.5 + 1.5 + ... + 7.5) = 78.48.
    static double released() { return m * kRigidG * length * (links * links / 2.0); }
    static sim::Vec3 center(int k) { return sim::Vec3(length * (k + 0.5), 0.0, 0.0); }  // m, of link k
};

// One simulator of one problem at one step h.
class RigidRun {
public:
    virtual ~RigidRun() = default;
    virtual void step() = 0;
    virtual double energy() const = 0;  // J, kinetic + m g y over the bodies
    // The pendulum: the rod's centre of mass (m); the top: its axis (unit); the chain: zero.
    virtual sim::Vec3 probe() const = 0;
    // Stopped: a non-finite state, or a body spinning past sim::kMaxBodySpin
    // (where ODE would soon assert on a NaN quaternion), the same rule for all.
    virtual bool broken() const = 0;
};

// Bullet's solvers, in the report's order: "bullet_multibody" (Featherstone's
// btMultiBody: revolute links, a spherical link for the top) and
// "bullet_sequential_impulse" (btRigidBody, btHingeConstraint or
// btPoint2PointConstraint, btSequentialImpulseConstraintSolver).
struct RigidPeer {
    std::string solver;
    std::string setting;
};
const std::vector<RigidPeer>& rigid_peers();
// Throws sim::InputError for an unknown solver or problem.
std::unique_ptr<RigidRun> bullet_run(std::string_view solver, std::string_view problem, double h);

}  // namespace scenes::report
