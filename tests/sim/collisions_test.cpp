// Particle collisions: each shape's signed distance against its closed form,
// bounce and friction against their closed forms, continuous detection, and
// particle pairs conserving momentum.
#include "sim/collisions.h"
#include "sim/error.h"
#include "sim/mass_spring.h"
#include "sim/random.h"
#include "sim/world.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

namespace sim::test {
namespace {

TEST(SurfacePoint, EachShapeMatchesItsClosedForm) {
    const SurfacePoint plane = surface_point(PlaneCollider{Vec3::UnitY(), 0.5}, Vec3(3, 2, 1));
    EXPECT_DOUBLE_EQ(plane.distance, 1.5);
    const SurfacePoint sphere = surface_point(SphereCollider{Vec3(1, 0, 0), 2.0}, Vec3(1, 0, 3));
    EXPECT_DOUBLE_EQ(sphere.distance, 1.0);
    EXPECT_EQ(sphere.normal, Vec3(0, 0, 1));
    // A box rotated 90 degrees about y: its x half-extent 2 now lies along z.
    BoxCollider box;
    box.half_extents = Vec3(2, 1, 0.5);
    box.rotation = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()).toRotationMatrix();
    EXPECT_NEAR(surface_point(box, Vec3(0, 0, 3)).distance, 1.0, 1e-12) << "m, outside the face at z = 2";
    EXPECT_NEAR(surface_point(box, Vec3(0, 0, 1.9)).distance, -0.1, 1e-12) << "m, inside near the face";
    EXPECT_NEAR(surface_point(box, Vec3(0, 2, 3)).distance, std::sqrt(2.0), 1e-12) << "m, off an edge";
    const SurfacePoint capsule = surface_point(CapsuleCollider{Vec3(0, 0, 0), Vec3(0, 4, 0), 0.5}, Vec3(2, 6, 0));
    EXPECT_NEAR(capsule.distance, std::sqrt(8.0) - 0.5, 1e-12) << "m, beyond the end cap";
    EXPECT_NEAR(surface_point(CapsuleCollider{Vec3(0, 0, 0), Vec3(0, 4, 0), 0.5}, Vec3(1, 2, 0)).distance, 0.5, 1e-12);
}

// One particle of radius r on the ground plane y = 0, no gravity unless given.
ParticleModel ball(const Vec3& x, const Vec3& v, double restitution, double friction, const Vec3& g = Vec3::Zero()) {
    ParticleModel model;
    ParticleDef p;
    p.position = x;
    p.velocity = v;
    p.radius = 0.1;
    model.particles.push_back(p);
    if (g != Vec3::Zero()) model.forces.push_back(UniformGravity{g});
    model.collisions.colliders.push_back(PlaneCollider{});
    model.collisions.restitution = restitution;
    model.collisions.friction = friction;
    return model;
}

TEST(Collisions, ABounceKeepsRestitutionTimesTheNormalSpeed) {
    World world(ball(Vec3(0, 0.15, 0), Vec3(1, -6, 0), 0.5, 0.0));
    world.step({Integrator::symplectic_euler, 0.02, 1});  // 0.12 m down: 0.07 m into the plane
    EXPECT_NEAR(world.state().x.get(0).y(), 0.1, 1e-15) << "m: pushed back to touch the plane";
    EXPECT_NEAR(world.state().v.get(0).y(), 3.0, 1e-15) << "m/s: e = 0.5 of 6 m/s";
    EXPECT_NEAR(world.state().v.get(0).x(), 1.0, 1e-15) << "m/s: no friction, tangential speed kept";
}

TEST(Collisions, CoulombFrictionStopsASlideAtVSquaredOverTwoMuG) {
    // Sliding at 4 m/s with μ = 0.5 under g = 9.81: it stops after
    // v² / (2 μ g) = 1.631 m. Tolerance: one step of travel (4 m/s x 1/240 s).
    const double mu = 0.5, g = 9.81, v0 = 4.0;
    World world(ball(Vec3(0, 0.1, 0), Vec3(v0, 0, 0), 0.0, mu, Vec3(0, -g, 0)));
    for (int i = 0; i < 480; ++i) world.step({Integrator::symplectic_euler, 1.0 / 240.0, 1});
    EXPECT_NEAR(world.state().x.get(0).x(), v0 * v0 / (2 * mu * g), v0 / 240.0) << "m";
    EXPECT_EQ(world.state().v.get(0).x(), 0.0) << "m/s: stopped, not reversed";
    EXPECT_NEAR(world.state().x.get(0).y(), 0.1, 1e-12) << "m: resting on the plane, no jitter";
}

TEST(Collisions, AFastParticleStopsAtAThinWallInsteadOfPassingThrough) {
    // 200 m/s at 1/60 s moves 3.3 m per step; the wall is 1 cm thick at x = 5 m.
    ParticleModel model;
    ParticleDef p;
    p.position = Vec3(0, 1, 0);
    p.velocity = Vec3(200, 0, 0);
    p.radius = 0.0;
    model.particles.push_back(p);
    BoxCollider wall;
    wall.center = Vec3(5, 1, 0);
    wall.half_extents = Vec3(0.005, 2, 2);
    model.collisions.colliders.push_back(wall);
    model.collisions.restitution = 0.0;
    World world(std::move(model));
    world.set_watchdog({.max_speed = 1000});
    for (int i = 0; i < 60; ++i) {
        world.step({Integrator::symplectic_euler, 1.0 / 60.0, 1});
        ASSERT_LE(world.state().x.get(0).x(), 4.995 + 1e-12) << "m: behind the wall at frame " << i + 1;
    }
}

// collide() passes over a static collider whose bounds a particle's substep
// stays clear of (ColliderBounds), and over the moving colliders where the
// particle is outside the box around all their reaches: it must never pass
// over a contact. Still
// particles (the substep a point) near the surface of turned boxes, spheres
// and capsules grown by the particle's radius: each touches exactly when it
// is inside the grown shape, computed here in the shape's own frame. A box
// grown by r reaches r √3 past its world bounds at a corner when turned
// about a skew axis; the first case sits there, 0.3 r past bounds grown by
// r alone (a reject that forgot the turn would miss it).
TEST(Collisions, TheQuickRejectNeverMissesAContact) {
    const Eigen::Matrix3d skew = Eigen::AngleAxisd(0.9, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    Collisions c;
    c.restitution = 0.0;
    // Static, or (moving) a still moving collider held within `reach` of `pivot`
    // beside a second one far off (the box around both reaches is larger).
    auto touches = [&](const Collider& collider, const Vec3& p, double r, bool moving = false,
                       const Vec3& pivot = Vec3::Zero(), double reach = 0.0) {
        c.colliders.clear();
        std::vector<MovingCollider> movers;
        if (moving) {
            movers.push_back({collider, Vec3::Zero(), Vec3::Zero(), pivot, reach});
            movers.push_back({SphereCollider{Vec3(5, 5, 5), 0.1}, Vec3::Zero(), Vec3::Zero(), Vec3(5, 5, 5), 0.1});
        } else {
            c.colliders = {collider};
        }
        Vec3Array x0(1), x(1), v(1);
        x0.set(0, p), x.set(0, p);
        const double radius[1] = {r}, inv_mass[1] = {1.0};
        CollisionScratch scratch;
        return collide(c, x0.span(), x.span(), v.span(), radius, inv_mass, 1.0 / 60.0, scratch, movers) == 1;
    };
    BoxCollider box;
    box.center = Vec3(0.3, -0.2, 0.1);
    box.half_extents = Vec3(0.5, 0.2, 0.1);
    box.rotation = skew;
    const double r = 0.05;  // m
    {
        // The grown box's corner furthest along world x.
        const Vec3 sign = skew.row(0).transpose().array().sign();
        const Vec3 corner = box.center + skew * ((box.half_extents.array() + r) * sign.array() * (1.0 - 1e-6)).matrix();
        const Vec3 extent = skew.cwiseAbs() * box.half_extents;
        ASSERT_GT(corner.x() - box.center.x(), extent.x() + 1.3 * r) << "m: the corner past bounds grown by r";
        EXPECT_TRUE(touches(box, corner, r)) << "a particle just inside a turned box's grown corner";
    }
    Random random(11);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * random.uniform(); };
    int inside = 0, outside = 0;
    for (int i = 0; i < 6000; ++i) {
        const double radius = uniform(0.0, 0.2);  // m
        Vec3 pivot = Vec3::Zero();
        double reach = 0.0;  // m, a sphere about pivot that holds the shape
        // A point in a box around the shape a little larger than its grown size.
        const Vec3 q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        Collider shape;
        bool in = false;
        double clearance = 0.0;  // m, how far inside (> 0) or outside the grown shape
        Vec3 p;
        switch (i % 3) {
            case 0: {  // the box, q scaled to 1.2 times its grown half size, in its frame
                const Vec3 local = 1.2 * (q.array() * (box.half_extents.array() + radius)).matrix();
                p = box.center + box.rotation * local;
                clearance = ((box.half_extents.array() + radius) - local.cwiseAbs().array()).minCoeff();
                shape = box;
                pivot = box.center, reach = box.half_extents.norm();
                break;
            }
            case 1: {
                const SphereCollider sphere{Vec3(-0.4, 0.5, 0.2), 0.3};
                p = sphere.center + 1.2 * (sphere.radius + radius) * q;
                clearance = sphere.radius + radius - (p - sphere.center).norm();
                shape = sphere;
                pivot = sphere.center, reach = sphere.radius;
                break;
            }
            default: {
                const CapsuleCollider capsule{Vec3(-0.3, 0.1, 0.0), Vec3(0.4, 0.6, -0.2), 0.15};
                const Vec3 mid = 0.5 * (capsule.a + capsule.b);
                p = mid + skew * Vec3(q.x() * 0.9, q.y() * 0.5, q.z() * 0.5);
                const Vec3 ab = capsule.b - capsule.a;
                const double t = std::clamp((p - capsule.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
                clearance = capsule.radius + radius - (p - (capsule.a + t * ab)).norm();
                shape = capsule;
                pivot = mid, reach = 0.5 * ab.norm() + capsule.radius;
                break;
            }
        }
        const bool moving = i % 2 == 1;
        // A moving collider is looked at only within its reach (plus r) of its
        // pivot: that leaves out the square corners of a grown box beyond it
        // (a real sphere touches a box's corner within r of it, inside the reach).
        const double within_reach = moving ? reach + radius - (p - pivot).norm() : 1.0;  // m
        if (std::abs(clearance) < 1e-9 || std::abs(within_reach) < 1e-9) continue;       // either answer, to rounding
        in = clearance > 0.0 && within_reach > 0.0;
        (in ? inside : outside) += 1;
        EXPECT_EQ(touches(shape, p, radius, moving, pivot, reach), in)
            << "case " << i << (moving ? " (moving), " : ", ") << clearance << " m inside the grown shape";
    }
    EXPECT_GT(inside, 600);
    EXPECT_GT(outside, 600);
}

TEST(Collisions, ParticlePairsExchangeVelocitiesAndConserveMomentum) {
    // Two equal particles head-on with e = 1: they swap velocities.
    ParticleModel model;
    for (double side : {-1.0, 1.0}) {
        ParticleDef p;
        p.position = Vec3(side * 0.11, 0, 0);
        p.velocity = Vec3(-side * 2.0, 0, 0);
        p.radius = 0.1;
        model.particles.push_back(p);
    }
    model.particles[1].velocity = Vec3(-1.0, 0, 0);
    model.collisions.particle_particle = true;
    model.collisions.restitution = 1.0;
    model.collisions.friction = 0.0;
    model.collisions.rest_speed = 0.0;
    World world(std::move(model));
    world.step({Integrator::symplectic_euler, 0.01, 1});
    EXPECT_NEAR(world.state().v.get(0).x(), -1.0, 1e-12) << "m/s";
    EXPECT_NEAR(world.state().v.get(1).x(), 2.0, 1e-12) << "m/s";
    const Vec3 p = world.state().v.get(0) + world.state().v.get(1);
    EXPECT_NEAR((p - Vec3(1.0, 0, 0)).norm(), 0.0, 1e-12) << "kg·m/s, momentum";
    EXPECT_GE((world.state().x.get(1) - world.state().x.get(0)).norm(), 0.2 - 1e-12) << "m: separated";
}

TEST(Collisions, ManyParticlesInAHeapNeverOverlapMuchAndAreDeterministic) {
    auto build = [] {
        ParticleModel model;
        for (int i = 0; i < 400; ++i) {
            ParticleDef p;
            p.position = Vec3((i % 20) * 0.05, 0.5 + (i / 20) * 0.05, 0.01 * (i % 3));
            p.radius = 0.02;
            model.particles.push_back(p);
        }
        model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
        model.collisions.colliders.push_back(PlaneCollider{});
        model.collisions.particle_particle = true;
        return model;
    };
    World a(build()), b(build());
    for (int i = 0; i < 120; ++i) {
        a.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
        b.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
    }
    EXPECT_EQ(a.state().x.flat(), b.state().x.flat());
    EXPECT_FALSE(a.verdict().exploded()) << a.verdict().message("heap");
    for (std::size_t i = 0; i < a.state().size(); ++i) {
        ASSERT_GE(a.state().x.get(i).y(), 0.02 - 1e-9) << "m: particle " << i << " below the ground";
    }
}

// 1000 pairs of particles of radius r into x[0, 2000), overlapping by 0.1 %
// of their reach and pointing every way, on a lattice 10 cm apart (each pair
// shifted by up to 5 cm more when `jitter`), so that no two pairs touch.
void scatter_pairs(Vec3Array& x, double r, Random& random, bool jitter) {
    for (int k = 0; k < 1000; ++k) {
        Vec3 centre = 0.1 * Vec3(k % 10, (k / 10) % 10, k / 100);  // m
        if (jitter) centre += Vec3(random.uniform(0.0, 0.05), random.uniform(0.0, 0.05), random.uniform(0.0, 0.05));
        const Vec3 half = (0.999 * r) * random.unit_vector();  // m: centres 0.999 (2 r) apart
        x.set(2 * k, centre - half);
        x.set(2 * k + 1, centre + half);
    }
}

TEST(Collisions, TheGridFindsEveryOverlapAcrossCellFaces) {
    // 1000 pairs of particles (r = 1 cm) overlapping by 0.1 % of their reach,
    // pointing every way, scattered over a lattice 10 cm apart (so the pairs
    // never touch each other): 2000 particles over 1 m make the grid coarsen
    // its cells to 4 cm, 4 r, where the pass leaves out neighbour cells
    // farther than 2 r from a particle. Many pairs straddle a cell face, in
    // every direction; each must be found.
    const double r = 0.01;  // m
    Random random(5);
    Vec3Array x0(2000), x(2000), v(2000);
    std::vector<double> radius(2000, r), inv_mass(2000, 1.0);
    scatter_pairs(x, r, random, true);
    x0 = x;
    Collisions pairs;
    pairs.particle_particle = true;
    CollisionScratch scratch;
    EXPECT_EQ(collide(pairs, x0.span(), x.span(), v.span(), radius.data(), inv_mass.data(), 0.01, scratch), 1000u);
    EXPECT_TRUE(scratch.sparse_cells.empty()) << "the dense grid, not the crowded grid's fallback";
}

// The same 1000 pairs with one particle 9 km off (inside the watchdog's
// 10 km box): the dense grid over the bounding box would coarsen to cells of
// 280 m with all 2000 in one (2e6 candidate tests, growing as the square of
// the count: 10⁵ particles, 5e9 a pass). The pass notices the crowd and
// takes the sparse grid (cells of 2 r, only the occupied ones): every pair is
// still found, and the far particle touches none.
TEST(Collisions, AFarOutlierDoesNotCrowdThePairGrid) {
    const double r = 0.01;  // m
    Random random(5);
    Vec3Array x0(2001), x(2001), v(2001);
    std::vector<double> radius(2001, r), inv_mass(2001, 1.0);
    scatter_pairs(x, r, random, false);
    x.set(2000, Vec3(9000, 9000, 9000));
    x0 = x;
    Collisions pairs;
    pairs.particle_particle = true;
    CollisionScratch scratch;
    EXPECT_EQ(collide(pairs, x0.span(), x.span(), v.span(), radius.data(), inv_mass.data(), 0.01, scratch), 1000u);
    EXPECT_EQ(scratch.sparse_cells.size(), 2001u) << "the sparse grid's cells, one per entry";
    EXPECT_EQ(x.get(2000), Vec3(9000, 9000, 9000)) << "m: the far particle touches none";
    for (int k = 0; k < 1000; ++k) {
        EXPECT_NEAR((x.get(2 * k + 1) - x.get(2 * k)).norm(), 2.0 * r, 1e-12) << "m: pair " << k << " pushed apart";
    }
}

// Radii far below the particles' spread: cells of 2 r = 2e-20 m over 1 m
// would be 5e19 along x, more than an int64 holds (the conversion was
// undefined, then the grid asked for a vector of that many cells). The grid
// coarsens in double instead, and the pair still collides as two spheres:
// equal masses, so each moves half the overlap, to centres 2 r apart.
TEST(Collisions, RadiiOf1e20MetreOverAMetreStillFindTheOverlap) {
    const double r = 1e-20;  // m
    Vec3Array x(3), v(3);
    x.set(0, Vec3(0, 0, 0));
    x.set(1, Vec3(1.5 * r, 0, 0));  // overlapping by 0.5 r
    x.set(2, Vec3(1, 0, 0));        // a metre away: the grid spans 1 m
    const Vec3Array x0 = x;
    std::vector<double> radius(3, r), inv_mass(3, 1.0);
    Collisions pairs;
    pairs.particle_particle = true;
    CollisionScratch scratch;
    EXPECT_EQ(collide(pairs, x0.span(), x.span(), v.span(), radius.data(), inv_mass.data(), 0.01, scratch), 1u);
    EXPECT_NEAR(x.get(0).x(), -0.25 * r, 1e-6 * r) << "m: half the 0.5 r overlap";
    EXPECT_NEAR(x.get(1).x(), 1.75 * r, 1e-6 * r) << "m: the other half";
    EXPECT_EQ(x.get(2), Vec3(1, 0, 0)) << "m: far away, untouched";
    EXPECT_LE(scratch.cell_start.size(), 16u * 3u + 64u + 2u) << "cells: at most 16 a particle (+64)";
}

// A particle whose position is no longer finite (a blow-up the watchdog
// names after this substep) is left out of the grid: an infinite extent
// would make infinitely many cells (undefined conversions, then a vector of
// 2^64 entries). The others still collide.
TEST(Collisions, AParticleThatBlewUpIsLeftOutOfThePairGrid) {
    for (const double bad : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
        Vec3Array x(3), v(3);
        x.set(0, Vec3(0, 0, 0));
        x.set(1, Vec3(0.15, 0, 0));
        x.set(2, Vec3(bad, 0, 0));
        const Vec3Array x0 = x;
        std::vector<double> radius(3, 0.1), inv_mass(3, 1.0);
        Collisions pairs;
        pairs.particle_particle = true;
        CollisionScratch scratch;
        EXPECT_EQ(collide(pairs, x0.span(), x.span(), v.span(), radius.data(), inv_mass.data(), 0.01, scratch), 1u)
            << "with a particle at x = " << bad;
        EXPECT_NEAR(x.get(1).x() - x.get(0).x(), 0.2, 1e-12) << "m: pushed to 2 r apart";
    }
}

// Cloth self-collision is particle collision among the cloth's own nodes:
// with a node radius under half the link length, linked neighbours never
// touch, and only folds of the cloth meet. A cloth folded in half on the
// ground keeps two layers; without particle collisions the top layer falls
// through the bottom one onto the ground.
double top_layer_height(bool self_collision) {
    ParticleModel model;
    ClothDef cloth;
    cloth.nx = cloth.ny = 12;
    cloth.corner = Vec3(-0.55, 0.045, -0.55);
    cloth.u = Vec3(1.1, 0, 0);  // links of 0.1 m
    cloth.v = Vec3(0, 0, 1.1);
    cloth.radius = 0.045;  // m: 2r = 0.09 < 0.1, so neighbours do not collide, and the holes are small
    cloth.pins = ClothDef::Pins::none;
    cloth.bend = 0.0;  // inextensible bend links (i, i + 2) would forbid the fold itself
    cloth.links.kind = LinkSettings::Kind::constraints;
    const BodyRange body = add_cloth(model, cloth);
    model.forces.push_back(UniformGravity{Vec3(0, -9.81, 0)});
    model.collisions.colliders.push_back(PlaneCollider{});
    model.collisions.particle_particle = self_collision;
    model.collisions.restitution = 0.0;
    model.collisions.friction = 0.5;
    model.constraints.iterations = 4;
    World world(std::move(model));
    // Fold rows 6..11 back over rows 0..5, 0.12 m up: row 6 lies above row 5, row 11 above row 0.
    for (int j = 6; j < 12; ++j) {
        for (int i = 0; i < 12; ++i) {
            const Vec3 below = world.state().x.get(body.at(i, 11 - j));
            world.edit_state().x.set(body.at(i, j), below + Vec3(0, 0.12, 0));
        }
    }
    for (int k = 0; k < 120; ++k) world.step({Integrator::symplectic_euler, 1.0 / 60.0, 4});
    EXPECT_FALSE(world.verdict().exploded()) << world.verdict().message("folded cloth");
    double lowest = 1e9;  // the lowest node of the top layer away from the fold
    for (int j = 8; j < 12; ++j) {
        for (int i = 2; i < 10; ++i) lowest = std::min(lowest, world.state().x.get(body.at(i, j)).y());
    }
    return lowest;
}

TEST(Collisions, ClothSelfCollisionKeepsAFoldedClothInTwoLayers) {
    const double with = top_layer_height(true), without = top_layer_height(false);
    std::printf("[ measured ] folded cloth, top layer's lowest node: %.4f m with self-collision, %.4f m without\n",
                with, without);
    // The bottom layer's centres are at r = 0.045 m; a top node resting on it
    // is up to 2r higher, less where it settles into a hole of the grid.
    EXPECT_GT(with, 0.045 + 1.5 * 0.045) << "m: a second layer, on the first";
    EXPECT_LT(without, 0.045 + 0.5 * 0.045) << "m: without it, through to the ground";
}

TEST(Collisions, ValidationNamesTheCollider) {
    Collisions c;
    c.colliders.push_back(PlaneCollider{});
    c.colliders.push_back(SphereCollider{Vec3::Zero(), 0.0});
    try {
        validate(c);
        FAIL() << "accepted a sphere of radius 0";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "collisions.colliders[1].radius must be > 0 and finite, in m (got 0)");
    }
    c.colliders[1] = PlaneCollider{Vec3(0, 2, 0), 0.0};
    EXPECT_THROW(validate(c), InputError);
    c.colliders.pop_back();
    c.restitution = 1.5;
    EXPECT_THROW(validate(c), InputError);
}

}  // namespace
}  // namespace sim::test
