// Sections: 1. maximal state from the joints (compose); 2. the
// articulated-body algorithm; 3. validation; 4. the step (generalized
// coordinates in, RK4 on the rotation group, maximal state out).
#include "sim/articulated.h"

#include "sim/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace sim {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;  // spatial: (angular; linear)
using Mat6 = Eigen::Matrix<double, 6, 6>;
// A joint's free motions (6 x 1 hinge, 6 x 3 ball) and the small matrices beside them.
using Motion = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 3>;
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;

std::string link_name(std::size_t i) { return "articulated.links[" + std::to_string(i) + "]"; }

Mat3 skew(const Vec3& a) {  // skew(a) b = a × b
    Mat3 m;
    m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return m;
}

// The unit quaternion of the rotation vector phi (rad): angle |phi| about phi.
Eigen::Quaterniond rotation_exp(const Vec3& phi) {
    const double angle = phi.norm();
    // sin(angle / 2) / angle; its series ½ - angle²/48 where the next term is below rounding.
    const double s = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(0.5 * angle) / angle;
    return {std::cos(0.5 * angle), s * phi.x(), s * phi.y(), s * phi.z()};
}

// --- 1. Maximal state from the joints ---------------------------------------

// One link's maximal state and the joint geometry the algorithm reuses.
struct Body {
    Eigen::Quaterniond q;  // body to world
    Mat3 R;                // body to world
    Vec3 x, v, w;          // m, m/s, rad/s: centre of mass, its velocity, angular velocity (world)
    Vec3 to_joint;         // m, world axes: centre of mass to the joint, R anchor_in_child
    Vec3 from_parent;      // m, world axes: parent's centre of mass (the world origin for a root) to the joint
};

// Root down: a child's orientation is its parent's times q_rel, its position
// puts the two anchors on one point (x = x_p + R_p a_p - R a_c), and its
// velocities are that equation's derivative (w_rel in the child frame).
void compose(const std::vector<ArticulatedLink>& links, const std::vector<Eigen::Quaterniond>& q_rel,
             const std::vector<Vec3>& w_rel, std::vector<Body>& bodies) {
    for (std::size_t i = 0; i < links.size(); ++i) {
        const ArticulatedLink& link = links[i];
        Body& b = bodies[i];
        if (link.parent < 0) {
            b.q = q_rel[i];
            b.R = b.q.toRotationMatrix();
            b.to_joint = b.R * link.anchor_in_child;
            b.from_parent = link.anchor_in_parent;
            b.x = link.anchor_in_parent - b.to_joint;
            b.w = b.R * w_rel[i];
            b.v = -b.w.cross(b.to_joint);
        } else {
            const Body& p = bodies[static_cast<std::size_t>(link.parent)];
            b.q = (p.q * q_rel[i]).normalized();
            b.R = b.q.toRotationMatrix();
            b.to_joint = b.R * link.anchor_in_child;
            b.from_parent = p.R * link.anchor_in_parent;
            b.x = p.x + b.from_parent - b.to_joint;
            b.w = p.w + b.R * w_rel[i];
            b.v = p.v + p.w.cross(b.from_parent) - b.w.cross(b.to_joint);
        }
    }
}

// --- 2. The articulated-body algorithm --------------------------------------
// Spatial vectors (angular; linear) about each centre of mass, world axes: a
// body's inertia is diag(I, m), its bias wrench (ω × I ω; -m g); a joint gives
// a = X a_p + S u̇ + ζ. X, S, ζ derived: docs/studies/rigid-closed-forms.md §8.

struct Scratch {
    std::vector<Mat6> inertia;  // articulated inertia, kg and kg·m² blocks
    std::vector<Vec6> bias;     // articulated bias wrench, N·m and N
    std::vector<Motion> S;
    std::vector<Motion> U;     // inertia S
    std::vector<Small> D_inv;  // (Sᵀ inertia S)⁻¹
    std::vector<SmallVec> u;   // -Sᵀ bias
    std::vector<Vec6> zeta;    // velocity-product acceleration
    std::vector<Vec6> a;       // acceleration
    void resize(std::size_t n) {
        inertia.resize(n), bias.resize(n), S.resize(n), U.resize(n), D_inv.resize(n), u.resize(n);
        zeta.resize(n), a.resize(n);
    }
};

// X(r): (ω; v) at the parent's centre of mass to (ω; v + ω × r) at the child's, r = x - x_p.
Mat6 motion_transform(const Vec3& r) {
    Mat6 X = Mat6::Identity();
    X.block<3, 3>(3, 0) = -skew(r);
    return X;
}

// Each joint's relative angular acceleration ẇ_rel (child frame) under gravity.
void joint_accelerations(const std::vector<ArticulatedLink>& links, const std::vector<Body>& bodies,
                         const Vec3& gravity, Scratch& s, std::vector<Vec3>& dw_rel) {
    const std::size_t n = links.size();
    // Outward: each body's own inertia, bias, free motions and ζ.
    for (std::size_t i = 0; i < n; ++i) {
        const ArticulatedLink& link = links[i];
        const Body& b = bodies[i];
        const Mat3 I = b.R * link.inertia * b.R.transpose();
        s.inertia[i].setZero();
        s.inertia[i].block<3, 3>(0, 0) = I;
        s.inertia[i].block<3, 3>(3, 3) = link.mass * Mat3::Identity();
        s.bias[i] << b.w.cross(I * b.w), -link.mass * gravity;
        if (link.joint == ArticulatedJointType::ball) {
            s.S[i].resize(6, 3);
            s.S[i].topRows<3>() = b.R;
        } else {
            s.S[i].resize(6, 1);
            s.S[i].topRows<3>() = b.R * link.axis_in_child;
        }
        s.S[i].bottomRows<3>() = skew(b.to_joint) * s.S[i].topRows<3>();
        const Vec3 w_p = link.parent < 0 ? Vec3::Zero() : bodies[static_cast<std::size_t>(link.parent)].w;
        const Vec3 w_rel = b.w - w_p;
        const Vec3 turn = w_p.cross(w_rel);
        s.zeta[i] << turn,
            w_p.cross(w_p.cross(b.from_parent)) - turn.cross(b.to_joint) - b.w.cross(b.w.cross(b.to_joint));
    }
    // Inward: fold each child's articulated inertia, less what its joint lets go, into its parent.
    for (std::size_t i = n; i-- > 0;) {
        s.U[i] = s.inertia[i] * s.S[i];
        s.D_inv[i] = (s.S[i].transpose() * s.U[i]).inverse();
        s.u[i] = -s.S[i].transpose() * s.bias[i];
        const int parent = links[i].parent;
        if (parent < 0) continue;
        const auto p = static_cast<std::size_t>(parent);
        const Mat6 Ia = s.inertia[i] - s.U[i] * s.D_inv[i] * s.U[i].transpose();
        const Vec6 pa = s.bias[i] + Ia * s.zeta[i] + s.U[i] * (s.D_inv[i] * s.u[i]);
        const Mat6 X = motion_transform(bodies[i].x - bodies[p].x);
        s.inertia[p] += X.transpose() * Ia * X;
        s.bias[p] += X.transpose() * pa;
    }
    // Outward: accelerations, from the world at rest.
    for (std::size_t i = 0; i < n; ++i) {
        const int parent = links[i].parent;
        Vec6 a = s.zeta[i];
        if (parent >= 0) {
            const auto p = static_cast<std::size_t>(parent);
            a += motion_transform(bodies[i].x - bodies[p].x) * s.a[p];
        }
        const SmallVec du = s.D_inv[i] * (s.u[i] - s.U[i].transpose() * a);
        s.a[i] = a + s.S[i] * du;
        dw_rel[i] = links[i].joint == ArticulatedJointType::ball ? Vec3(du) : Vec3(du(0) * links[i].axis_in_child);
    }
}

void require_finite(const Vec3& v, const std::string& name, const char* unit) {
    if (!v.allFinite()) throw InputError(name + " must be finite, in " + unit);
}

}  // namespace

// --- 3. Validation -----------------------------------------------------------

void validate(const std::vector<ArticulatedLink>& links) {
    for (std::size_t i = 0; i < links.size(); ++i) {
        const ArticulatedLink& link = links[i];
        const std::string name = link_name(i);
        if (link.parent < -1 || link.parent >= static_cast<int>(i)) {
            throw InputError(name + ".parent must be -1 (the world) or a lower link's index (got " +
                             std::to_string(link.parent) + ")");
        }
        require_positive(link.mass, name + ".mass", "kg");
        require_finite(link.anchor_in_parent, name + ".anchor_in_parent", "m");
        require_finite(link.anchor_in_child, name + ".anchor_in_child", "m");
        if (link.joint == ArticulatedJointType::hinge &&
            (!link.axis_in_child.allFinite() || std::abs(link.axis_in_child.norm() - 1.0) > 1e-6)) {
            throw InputError(name + ".axis_in_child must be a unit vector");
        }
        const Eigen::Matrix3d& I = link.inertia;
        if (!I.allFinite() || (I - I.transpose()).cwiseAbs().maxCoeff() > 1e-9 * I.cwiseAbs().maxCoeff() ||
            I.llt().info() != Eigen::Success) {
            throw InputError(name + ".inertia must be finite, symmetric and positive definite, in kg·m²");
        }
    }
}

// --- 4. The step ------------------------------------------------------------
// Generalized coordinates: each joint's rotation q_rel = q_p⁻¹ q and spin w_rel = Rᵀ (ω - ω_p).
// RK4 on (δ, w_rel), q_rel = q_rel0 exp(δ), δ' = dexp⁻¹_δ(w) = w + ½ δ × w + (1/12) δ × (δ × w):
// fourth order, and q_rel stays a rotation (Munthe-Kaas).

namespace {

struct Joints {
    std::vector<Eigen::Quaterniond> q;  // parent to child
    std::vector<Vec3> w;                // rad/s, child frame
};

// Scratch of one step, sized once.
struct Work {
    std::vector<Body> bodies;
    Scratch scratch;
    std::vector<Eigen::Quaterniond> q;
    std::vector<Vec3> delta, w, k_delta, k_w, sum_delta, sum_w;
    explicit Work(std::size_t n) : bodies(n), q(n), delta(n), w(n), k_delta(n), k_w(n), sum_delta(n), sum_w(n) {
        scratch.resize(n);
    }
};

// No joint turns more than this in one RK4 step: past it RK4 loses energy
// fast (a falling chain's tip whips round at ω h near 1 rad at 1/120 s). The
// caps bound a step's cost. docs/studies/rigid-closed-forms.md §8.
constexpr double kMaxJointTurn = 0.3;  // rad
constexpr double kMaxSubsteps = 64.0;  // the step split evenly by the joints' spins at its start
constexpr int kMaxHalvings = 4;        // of a substep that turned a joint too far

// Classic RK4: stage k starts from y0 + h c[k] K[k-1]; the weights b sum the four.
constexpr std::array<double, 4> kRk4C = {0.0, 0.5, 0.5, 1.0};
constexpr std::array<double, 4> kRk4B = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};

// One RK4 step's increments over h, left in m.sum_delta and m.sum_w (times h).
void rk4_increments(const std::vector<ArticulatedLink>& links, const Vec3& gravity, double h, const Joints& y,
                    Work& m) {
    const std::size_t n = links.size();
    for (std::size_t i = 0; i < n; ++i) {
        m.delta[i].setZero(), m.sum_delta[i].setZero(), m.sum_w[i].setZero();
        m.w[i] = y.w[i];
    }
    for (std::size_t k = 0; k < kRk4B.size(); ++k) {
        for (std::size_t i = 0; i < n; ++i) {
            if (k > 0) {
                m.delta[i] = h * kRk4C[k] * m.k_delta[i];
                m.w[i] = y.w[i] + h * kRk4C[k] * m.k_w[i];
            }
            m.q[i] = y.q[i] * rotation_exp(m.delta[i]);
            const Vec3 turn = m.delta[i].cross(m.w[i]);
            m.k_delta[i] = m.w[i] + 0.5 * turn + m.delta[i].cross(turn) / 12.0;
        }
        compose(links, m.q, m.w, m.bodies);
        joint_accelerations(links, m.bodies, gravity, m.scratch, m.k_w);
        for (std::size_t i = 0; i < n; ++i) {
            m.sum_delta[i] += kRk4B[k] * m.k_delta[i];
            m.sum_w[i] += kRk4B[k] * m.k_w[i];
        }
    }
}

// Advances y by h: one RK4 step, or two of h/2 (each again split if need be)
// where that step would turn a joint by more than kMaxJointTurn.
void advance(const std::vector<ArticulatedLink>& links, const Vec3& gravity, double h, Joints& y, Work& m,
             int halvings) {
    rk4_increments(links, gravity, h, y, m);
    bool too_far = false;
    for (std::size_t i = 0; i < links.size(); ++i) too_far |= h * m.sum_delta[i].norm() > kMaxJointTurn;
    if (too_far && halvings < kMaxHalvings) {
        advance(links, gravity, 0.5 * h, y, m, halvings + 1);
        advance(links, gravity, 0.5 * h, y, m, halvings + 1);
        return;
    }
    for (std::size_t i = 0; i < links.size(); ++i) {
        y.q[i] = (y.q[i] * rotation_exp(h * m.sum_delta[i])).normalized();
        y.w[i] += h * m.sum_w[i];
    }
}

void validate_step(const std::vector<ArticulatedLink>& links, const std::vector<LinkState>& state, const Vec3& gravity,
                   double h) {
    validate(links);
    require_positive(h, "articulated step", "s");
    require_finite(gravity, "articulated gravity", "m/s²");
    if (state.size() != links.size()) {
        throw InputError("articulated state must have one entry per link (" + std::to_string(links.size()) + ", got " +
                         std::to_string(state.size()) + ")");
    }
    for (std::size_t i = 0; i < state.size(); ++i) {
        const LinkState& s = state[i];
        const std::string name = "articulated.state[" + std::to_string(i) + "]";
        require_finite(s.position, name + ".position", "m");
        require_finite(s.velocity, name + ".velocity", "m/s");
        require_finite(s.angular_velocity, name + ".angular_velocity", "rad/s");
        if (!s.orientation.coeffs().allFinite() || std::abs(s.orientation.norm() - 1.0) > 1e-6)
            throw InputError(name + ".orientation must be a unit quaternion");
    }
}

}  // namespace

void articulated_step(const std::vector<ArticulatedLink>& links, std::vector<LinkState>& state, const Vec3& gravity,
                      double h) {
    validate_step(links, state, gravity, h);
    const std::size_t n = links.size();

    // Generalized coordinates from the maximal state (position and linear velocity are not read).
    Joints y{std::vector<Eigen::Quaterniond>(n), std::vector<Vec3>(n)};
    double fastest = 0.0;  // rad/s, of the joints' relative spins
    for (std::size_t i = 0; i < n; ++i) {
        const ArticulatedLink& link = links[i];
        const Eigen::Quaterniond qc = state[i].orientation.normalized();
        Eigen::Quaterniond qp = Eigen::Quaterniond::Identity();
        Vec3 wp = Vec3::Zero();
        if (link.parent >= 0) {
            const LinkState& p = state[static_cast<std::size_t>(link.parent)];
            qp = p.orientation.normalized();
            wp = p.angular_velocity;
        }
        y.q[i] = (qp.conjugate() * qc).normalized();
        y.w[i] = qc.conjugate() * (state[i].angular_velocity - wp);
        if (link.joint == ArticulatedJointType::hinge) y.w[i] = link.axis_in_child.dot(y.w[i]) * link.axis_in_child;
        fastest = std::max(fastest, y.w[i].norm());
    }

    const int substeps = static_cast<int>(std::clamp(std::ceil(fastest * h / kMaxJointTurn), 1.0, kMaxSubsteps));
    Work work(n);
    for (int k = 0; k < substeps; ++k) advance(links, gravity, h / substeps, y, work, 0);

    // Maximal state out, every joint exact.
    compose(links, y.q, y.w, work.bodies);
    for (std::size_t i = 0; i < n; ++i) {
        const Body& b = work.bodies[i];
        state[i] = {b.x, b.q, b.v, b.w};
    }
}

}  // namespace sim
