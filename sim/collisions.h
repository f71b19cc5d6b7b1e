// Collisions for particles: static planes, spheres, boxes and capsules, and
// particles against each other through a spatial hash grid.
//
// Each particle is a sphere of its own radius. After the integrator (and the
// constraints) moved a particle from x0 to x1 in a substep:
//  1. Continuous detection against planes and boxes: the segment x0 -> x1 is
//     cast against the shape grown by the radius, so a fast particle that
//     would jump over a thin wall in one step stops at its surface instead
//     (a 1 cm wall at 200 m/s and 1/60 s: 3.3 m per step). Spheres and
//     capsules are resolved at x1 (they are thick enough in the scenes).
//  2. A particle inside a shape is moved to its surface along the normal.
//  3. The velocity's normal part bounces with the restitution e (none below
//     rest_speed, so resting contact does not jitter), and Coulomb friction
//     takes up to μ times the normal velocity change from the tangential part
//     (and stops it, not reverses it).
// Particle pairs (free particles only: a pinned particle is no obstacle; use
// a collider for that): found on a grid of cells twice the largest radius
// over the free particles' box, each particle tested against its own cell
// and the 13 "forward" neighbour cells (each pair once; a cell farther from
// the particle than the largest reach is skipped) on a copy of the positions
// sorted by cell (the pass reads memory in order). The overlapping pairs are
// listed first, then resolved in that order: positions pushed apart in
// proportion to inverse mass, then the same restitution and friction on the
// relative velocity. The grid is rebuilt every substep by counting sort and
// pairs are visited in cell order, so the result is the same bits on every
// run.
#pragma once

#include "sim/vec3_array.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <variant>
#include <vector>

namespace sim {

// The half-space below a plane is solid: free where normal · x >= offset.
struct PlaneCollider {
    Vec3 normal = Vec3::UnitY();  // unit, pointing out of the solid
    double offset = 0.0;          // m
};

struct SphereCollider {
    Vec3 center = Vec3::Zero();  // m
    double radius = 1.0;         // m (> 0)
};

// An oriented box: rotation maps box axes to world axes.
struct BoxCollider {
    Vec3 center = Vec3::Zero();                              // m
    Vec3 half_extents = Vec3(0.5, 0.5, 0.5);                 // m (each > 0)
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // orthonormal, det +1
};

// All points within radius of the segment a-b.
struct CapsuleCollider {
    Vec3 a = Vec3::Zero();   // m
    Vec3 b = Vec3::UnitY();  // m
    double radius = 0.25;    // m (> 0)
};

using Collider = std::variant<PlaneCollider, SphereCollider, BoxCollider, CapsuleCollider>;

struct Collisions {
    std::vector<Collider> colliders;
    double restitution = 0.3;        // 0 (no bounce) .. 1 (elastic)
    double friction = 0.4;           // Coulomb μ (>= 0)
    double rest_speed = 0.05;        // m/s: normal speeds below it do not bounce
    bool particle_particle = false;  // particles collide with each other (spatial hash grid)

    bool empty() const { return colliders.empty() && !particle_particle; }
};

// Throws InputError naming the first bad field, e.g.
// "collisions.colliders[2].radius must be > 0 and finite, in m (got 0)".
void validate(const Collisions& collisions);

// Where a point is with respect to a collider: signed distance to its surface
// (negative inside), m, and the outward unit normal at the nearest surface point.
struct SurfacePoint {
    double distance = 0.0;
    Vec3 normal = Vec3::UnitY();
};
SurfacePoint surface_point(const Collider& collider, const Vec3& p);

// A cell of the particle grid: its index along each axis.
struct GridCell {
    std::int32_t x = 0, y = 0, z = 0;
};

// A box in world axes around a static collider, m (a plane's is all space),
// widened by far more than the rounding of the exact tests: a particle of
// radius r whose substep stays outside it, the box grown by r times `grow`
// on each axis (what the collider grown by r adds there), cannot touch it.
struct ColliderBounds {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // m
    Vec3 grow = Vec3::Ones();                   // (m/m) the growth on each axis per metre of radius
};

// Scratch and counters of the collision pass (state that changes every step;
// not part of a scene's description).
struct CollisionScratch {
    std::vector<std::uint32_t> cell_start;            // (cells + 2) counting-sort offsets, cell k's first entry at [k]
    std::vector<std::uint32_t> cell_entries;          // particle indices sorted by cell
    std::vector<std::int32_t> cell_of;                // cell of each particle (-1: not in the grid)
    std::vector<GridCell> cell_xyz;                   // cell coordinates of each particle in the grid
    std::vector<double> sorted;                       // (4 x entries) x, y, z, radius in entry order, m
    std::vector<std::array<std::uint32_t, 2>> pairs;  // overlapping pairs found, as entry indices
    std::vector<std::array<double, 3>> sparse_cells;  // a crowded grid's fallback: cell (x, y, z) of each entry
    std::size_t contacts = 0;                         // contacts resolved in the last pass
    std::vector<ColliderBounds> collider_bounds;      // one per static collider (a quick reject)
};

// A collider that moves rigidly (a rigid body's part), for one-way coupling:
// particles are pushed out of it and bounce off its moving surface, it feels
// nothing. Its surface moves at velocity + angular_velocity × (p - pivot).
struct MovingCollider {
    Collider shape;                        // where it is now (a sphere, box or capsule)
    Vec3 velocity = Vec3::Zero();          // m/s, of the pivot
    Vec3 angular_velocity = Vec3::Zero();  // rad/s
    Vec3 pivot = Vec3::Zero();             // m, the body's centre of mass
    double reach = 0.0;                    // m, a sphere about pivot that holds the shape (a quick reject)
};

// Resolves every contact of the particles after a substep of h: x0 are the
// positions before the substep, x and v the positions and velocities after
// it (changed in place), radius and inv_mass per particle (inverse mass 0:
// pinned, never moved), and `moving` the moving colliders (no continuous
// detection: resolved at x). Returns the number of contacts.
std::size_t collide(const Collisions& collisions, ConstVec3Span x0, Vec3Span x, Vec3Span v, const double* radius,
                    const double* inv_mass, double h, CollisionScratch& scratch,
                    const std::vector<MovingCollider>& moving = {});

}  // namespace sim
