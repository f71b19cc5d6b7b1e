// What RigidWorld's step adds to ODE's solver: the gyroscopic term by RK4
// (RigidSettings::gyroscopic_rk4) and positional stabilisation of the joints
// (RigidSettings::position_iterations).
#include "sim/error.h"
#include "sim/rigid_impl.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>

namespace sim {

using rigid_detail::to_vec;

// ω over h by RK4 on Euler's torque-free equations in the body frame,
// I ω̇ = -ω × I ω (see RigidSettings::gyroscopic_rk4): one step while |ω| h <=
// 2.5 (every spin the shipped scenes reach), else steps of |ω| h <= 0.25: past
// RK4's limit (~2.8) ω grew to overflow. kMaxBodySpin bounds their number.
void RigidWorld::Impl::gyroscopic(double h) {
    for (Slot& s : slots) {
        if (s.body == nullptr || !dBodyIsEnabled(s.body)) continue;
        const dReal* q = dBodyGetQuaternion(s.body);
        const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
        Vec3 w = R.transpose() * to_vec(dBodyGetAngularVel(s.body));
        auto f = [&](const Vec3& x) -> Vec3 { return -(s.inv_inertia * x.cross(s.inertia * x)); };
        const double turn = w.norm() * h;  // rad
        const int n = turn <= 2.5 ? 1 : static_cast<int>(std::min(1e6, std::ceil(turn / 0.25)));
        const double hs = h / n;
        for (int i = 0; i < n; ++i) {
            const Vec3 k1 = f(w);
            const Vec3 k2 = f(w + 0.5 * hs * k1);
            const Vec3 k3 = f(w + 0.5 * hs * k2);
            const Vec3 k4 = f(w + hs * k3);
            w += hs / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        w = R * w;
        dBodySetAngularVel(s.body, w.x(), w.y(), w.z());
    }
}

// Position iterations (RigidSettings::position_iterations): for each
// joint, the anchor gap beyond the slop, C = |p2 - p1| - slop along n, is
// closed by a positional impulse λ = C / (w1 + w2), with each body's
// generalised inverse mass
// w = 1/m + (r × n)ᵀ I⁻¹ (r × n) (r: from its centre of mass to its
// anchor): x += λ n / m, and a rotation I⁻¹ (r × λ n) applied to its
// quaternion. A body asleep or the static world does not move.
void RigidWorld::Impl::stabilize() {
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
            const double length = gap.norm();
            const double c = length - settings.position_slop;  // m, the part closed here
            if (c <= 0.0) continue;
            const Vec3 n = gap / length;
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

}  // namespace sim
