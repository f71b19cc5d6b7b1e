// Bullet (Debian's libbullet-dev, single precision) as a peer on the rigid
// problems: its Featherstone btMultiBody in a btMultiBodyDynamicsWorld, and
// btRigidBody with btSequentialImpulseConstraintSolver in a
// btDiscreteDynamicsWorld. Set up as Bullet's examples do, with what a
// closed form needs: no sleeping, no collisions (none of the problems has
// any), multibody damping 0, and one stepSimulation(h, 0) = one step of h.
#include "scenes/report/report_rigid.h"

#include "sim/error.h"
#include "sim/rigid.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <array>

namespace scenes::report {
namespace {

btVector3 to_bt(const sim::Vec3& v) {
    return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()), static_cast<btScalar>(v.z()));
}
btQuaternion to_bt(const Eigen::Quaterniond& q) {
    return btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()), static_cast<btScalar>(q.z()),
                        static_cast<btScalar>(q.w()));
}
sim::Vec3 from_bt(const btVector3& v) { return sim::Vec3(v.x(), v.y(), v.z()); }

// The principal moments at the centre of mass, kg·m²: a box of full
// extents `size`, and the top's disc (about its local z).
sim::Vec3 bullet_box_inertia(double m, const sim::Vec3& size) {
    const sim::Vec3 s2 = size.cwiseProduct(size);
    return m / 12.0 * sim::Vec3(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
}
sim::Vec3 bullet_disc_inertia() { return sim::Vec3(RigidTop::i1c, RigidTop::i1c, RigidTop::i3); }

// What every Bullet world is built on, as its examples build it.
struct BulletBase {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
};

// --- btRigidBody and the sequential impulse solver ---------------------------------------------

class BulletClassic final : public RigidRun, BulletBase {
public:
    BulletClassic(std::string_view problem, double h) : problem_(problem), h_(h) {
        world_.setGravity(btVector3(0, static_cast<btScalar>(-kRigidG), 0));
        if (problem == "pendulum") {
            const sim::Vec3 size(RigidPendulum::width, RigidPendulum::length, RigidPendulum::width);
            btRigidBody& rod = add(std::make_unique<btBoxShape>(to_bt(0.5 * size)), RigidPendulum::m,
                                   bullet_box_inertia(RigidPendulum::m, size), RigidPendulum::center(),
                                   RigidPendulum::orientation(), sim::Vec3::Zero(), sim::Vec3::Zero());
            // The hinge at the rod's top end, d up its local y.
            join(std::make_unique<btHingeConstraint>(rod, btVector3(0, static_cast<btScalar>(RigidPendulum::d), 0),
                                                     btVector3(0, 0, 1)));
        } else if (problem == "top") {
            btRigidBody& disc = add(std::make_unique<btCylinderShapeZ>(to_bt(
                                        sim::Vec3(RigidTop::radius, RigidTop::radius, 0.5 * RigidTop::thickness))),
                                    RigidTop::m, bullet_disc_inertia(), RigidTop::center(), RigidTop::orientation(),
                                    RigidTop::velocity(), RigidTop::angular_velocity());
            join(std::make_unique<btPoint2PointConstraint>(disc, btVector3(0, 0, static_cast<btScalar>(-RigidTop::l))));
        } else if (problem == "chain") {
            const sim::Vec3 size(RigidChain::length, RigidChain::width, RigidChain::width);
            const btVector3 half(static_cast<btScalar>(0.5 * RigidChain::length), 0, 0), z(0, 0, 1);
            btRigidBody* before = nullptr;
            for (int k = 0; k < RigidChain::links; ++k) {
                btRigidBody& link = add(std::make_unique<btBoxShape>(to_bt(0.5 * size)), RigidChain::m,
                                        bullet_box_inertia(RigidChain::m, size), RigidChain::center(k),
                                        Eigen::Quaterniond::Identity(), sim::Vec3::Zero(), sim::Vec3::Zero());
                if (before == nullptr) {
                    join(std::make_unique<btHingeConstraint>(link, -half, z));
                } else {
                    join(std::make_unique<btHingeConstraint>(*before, link, half, -half, z, z));
                }
                before = &link;
            }
        } else {
            throw sim::InputError("report: Bullet does not know the rigid problem '" + std::string(problem) + "'");
        }
    }
    ~BulletClassic() override {
        for (const auto& c : joints_) world_.removeConstraint(c.get());
        for (const auto& b : bodies_) world_.removeRigidBody(b.get());
    }
    BulletClassic(const BulletClassic&) = delete;
    BulletClassic& operator=(const BulletClassic&) = delete;

    void step() override { world_.stepSimulation(static_cast<btScalar>(h_), 0); }

    double energy() const override {
        double e = 0.0;
        for (const auto& b : bodies_) {
            const double m = 1.0 / b->getInvMass();
            const btMatrix3x3& r = b->getWorldTransform().getBasis();
            const sim::Vec3 w = from_bt(b->getAngularVelocity() * r);  // body frame (rᵀ ω)
            const sim::Vec3 inertia = from_bt(b->getInvInertiaDiagLocal()).cwiseInverse();
            e += 0.5 * m * from_bt(b->getLinearVelocity()).squaredNorm() + 0.5 * w.dot(inertia.cwiseProduct(w)) +
                 m * kRigidG * b->getCenterOfMassPosition().y();
        }
        return e;
    }

    sim::Vec3 probe() const override {
        if (problem_ == "pendulum") return from_bt(bodies_[0]->getCenterOfMassPosition());
        if (problem_ == "top") return from_bt(bodies_[0]->getWorldTransform().getBasis() * btVector3(0, 0, 1));
        return sim::Vec3::Zero();
    }

    bool broken() const override {
        for (const auto& b : bodies_) {
            if (!from_bt(b->getCenterOfMassPosition()).allFinite() ||
                !(from_bt(b->getAngularVelocity()).norm() <= sim::kMaxBodySpin)) {
                return true;
            }
        }
        return false;
    }

private:
    btRigidBody& add(std::unique_ptr<btCollisionShape> shape, double m, const sim::Vec3& inertia, const sim::Vec3& x,
                     const Eigen::Quaterniond& q, const sim::Vec3& v, const sim::Vec3& w) {
        btRigidBody::btRigidBodyConstructionInfo info(static_cast<btScalar>(m), nullptr, shape.get(), to_bt(inertia));
        info.m_startWorldTransform = btTransform(to_bt(q), to_bt(x));
        auto body = std::make_unique<btRigidBody>(info);
        body->setLinearVelocity(to_bt(v));
        body->setAngularVelocity(to_bt(w));
        body->setActivationState(DISABLE_DEACTIVATION);
        world_.addRigidBody(body.get(), btBroadphaseProxy::DefaultFilter, 0);  // collides with nothing
        shapes_.push_back(std::move(shape));
        bodies_.push_back(std::move(body));
        return *bodies_.back();
    }
    void join(std::unique_ptr<btTypedConstraint> c) {
        world_.addConstraint(c.get(), true);
        joints_.push_back(std::move(c));
    }

    std::string problem_;
    double h_;  // s
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_{&dispatcher, &broadphase, &solver_, &config};
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<std::unique_ptr<btTypedConstraint>> joints_;
};

// --- Featherstone's btMultiBody ----------------------------------------------------------------

class BulletMultiBody final : public RigidRun, BulletBase {
public:
    BulletMultiBody(std::string_view problem, double h) : problem_(problem), h_(h) {
        world_.setGravity(btVector3(0, static_cast<btScalar>(-kRigidG), 0));
        const btQuaternion none = btQuaternion::getIdentity();
        const btVector3 zero(0, 0, 0), z(0, 0, 1);
        if (problem == "pendulum") {
            make(1);
            const sim::Vec3 size(RigidPendulum::width, RigidPendulum::length, RigidPendulum::width);
            // The link hangs from the pivot at the origin: its centre d down its y at q = 0.
            body_->setupRevolute(0, static_cast<btScalar>(RigidPendulum::m),
                                 to_bt(bullet_box_inertia(RigidPendulum::m, size)), -1, none, z, zero,
                                 btVector3(0, static_cast<btScalar>(-RigidPendulum::d), 0), true);
            masses_ = {RigidPendulum::m};
            finish();
            body_->setJointPos(0, static_cast<btScalar>(RigidPendulum::theta0));
        } else if (problem == "top") {
            make(1);
            body_->setupSpherical(0, static_cast<btScalar>(RigidTop::m), to_bt(bullet_disc_inertia()), -1, none, zero,
                                  btVector3(0, 0, static_cast<btScalar>(RigidTop::l)), true);
            masses_ = {RigidTop::m};
            finish();
            // The joint's position is the link's orientation; its velocity the
            // angular velocity in the link's frame.
            const Eigen::Quaterniond q = RigidTop::orientation();
            const sim::Vec3 w = q.conjugate() * RigidTop::angular_velocity();
            const std::array<double, 4> pos = {q.x(), q.y(), q.z(), q.w()};
            const std::array<double, 3> vel = {w.x(), w.y(), w.z()};
            body_->setJointPosMultiDof(0, pos.data());
            body_->setJointVelMultiDof(0, vel.data());
        } else if (problem == "chain") {
            make(RigidChain::links);
            const sim::Vec3 size(RigidChain::length, RigidChain::width, RigidChain::width);
            const btVector3 half(static_cast<btScalar>(0.5 * RigidChain::length), 0, 0);
            for (int k = 0; k < RigidChain::links; ++k) {
                body_->setupRevolute(k, static_cast<btScalar>(RigidChain::m),
                                     to_bt(bullet_box_inertia(RigidChain::m, size)), k - 1, none, z,
                                     k == 0 ? zero : half, half, true);
                masses_.push_back(RigidChain::m);
            }
            finish();
        } else {
            throw sim::InputError("report: Bullet does not know the rigid problem '" + std::string(problem) + "'");
        }
    }
    ~BulletMultiBody() override { world_.removeMultiBody(body_.get()); }
    BulletMultiBody(const BulletMultiBody&) = delete;
    BulletMultiBody& operator=(const BulletMultiBody&) = delete;

    void step() override { world_.stepSimulation(static_cast<btScalar>(h_), 0); }

    // Each link's velocities in its own frame (compTreeLinkVelocities), where
    // its inertia is diagonal; the heights from its centre in the world.
    double energy() const override {
        const int n = body_->getNumLinks();
        std::vector<btVector3> omega(static_cast<std::size_t>(n + 1)), vel(static_cast<std::size_t>(n + 1));
        body_->compTreeLinkVelocities(omega.data(), vel.data());
        double e = 0.0;
        for (int k = 0; k < n; ++k) {
            const double m = masses_[static_cast<std::size_t>(k)];
            const sim::Vec3 w = from_bt(omega[static_cast<std::size_t>(k + 1)]);
            const sim::Vec3 inertia = from_bt(body_->getLink(k).m_inertiaLocal);
            e += 0.5 * m * from_bt(vel[static_cast<std::size_t>(k + 1)]).squaredNorm() +
                 0.5 * w.dot(inertia.cwiseProduct(w)) + m * kRigidG * body_->localPosToWorld(k, btVector3(0, 0, 0)).y();
        }
        return e;
    }

    sim::Vec3 probe() const override {
        if (problem_ == "pendulum") return from_bt(body_->localPosToWorld(0, btVector3(0, 0, 0)));
        if (problem_ == "top") return from_bt(body_->localDirToWorld(0, btVector3(0, 0, 1)));
        return sim::Vec3::Zero();
    }

    bool broken() const override {
        const int n = body_->getNumLinks();
        std::vector<btVector3> omega(static_cast<std::size_t>(n + 1)), vel(static_cast<std::size_t>(n + 1));
        body_->compTreeLinkVelocities(omega.data(), vel.data());
        for (int k = 0; k < n; ++k) {
            if (!from_bt(body_->localPosToWorld(k, btVector3(0, 0, 0))).allFinite() ||
                !(from_bt(omega[static_cast<std::size_t>(k + 1)]).norm() <= sim::kMaxBodySpin)) {
                return true;
            }
        }
        return false;
    }

private:
    // A fixed base at the origin with `links` links; no sleeping.
    void make(int links) {
        body_ = std::make_unique<btMultiBody>(links, 0.0f, btVector3(0, 0, 0), true, false);
        body_->setBasePos(btVector3(0, 0, 0));
        body_->setWorldToBaseRot(btQuaternion::getIdentity());
    }
    // Bullet's default damping (0.04 a link) drains the energy a closed form
    // keeps; its clamp of joint rates (100 rad/s), reached by the whipping
    // chain, adds energy: the limit is ours instead, kMaxBodySpin.
    void finish() {
        body_->setLinearDamping(0);
        body_->setAngularDamping(0);
        body_->setMaxCoordinateVelocity(static_cast<btScalar>(sim::kMaxBodySpin));
        body_->setCanSleep(false);
        body_->finalizeMultiDof();
        world_.addMultiBody(body_.get());
    }

    std::string problem_;
    double h_;                    // s
    std::vector<double> masses_;  // kg, per link
    btMultiBodyConstraintSolver solver_;
    btMultiBodyDynamicsWorld world_{&dispatcher, &broadphase, &solver_, &config};
    std::unique_ptr<btMultiBody> body_;
};

}  // namespace

const std::vector<RigidPeer>& rigid_peers() {
    static const std::vector<RigidPeer> list = {{"bullet_multibody", "Featherstone"},
                                                {"bullet_sequential_impulse", "10 iterations"}};
    return list;
}

std::unique_ptr<RigidRun> bullet_run(std::string_view solver, std::string_view problem, double h) {
    if (solver == "bullet_multibody") return std::make_unique<BulletMultiBody>(problem, h);
    if (solver == "bullet_sequential_impulse") return std::make_unique<BulletClassic>(problem, h);
    throw sim::InputError("report: no rigid peer '" + std::string(solver) + "'");
}

}  // namespace scenes::report
