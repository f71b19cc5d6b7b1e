// Builders of mass-spring bodies: ropes, cloth, and soft (elastic or plastic)
// bodies from a 3D lattice. A builder appends particles and index records to
// a ParticleModel and returns where they went; the model stays the only
// description (nothing here is kept by the world).
//
// Every link of a body is either a Hooke spring (a force: stiff ones need
// small steps or backward Euler) or an XPBD distance constraint (a position
// projection: stiff at any step), chosen by LinkSettings::kind: the lecture's
// "k -> infinity" question, answered two ways from one scene switch.
#pragma once

#include "sim/world.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sim {

struct LinkSettings {
    enum class Kind { springs, constraints };
    Kind kind = Kind::springs;
    double stiffness = 1000.0;  // N/m (springs)
    double damping = 0.0;       // N·s/m along each spring (springs)
    double compliance = 0.0;    // m/N (constraints; 0 is inextensible)
    // Constraints only: tie every node to its pins by a tether (see Tether in
    // constraints.h) at its rest distance, so that a hanging rope or cloth
    // cannot stretch however heavy its load or few the iterations.
    bool tethers = true;
};

// A rope of `segments` links from start to end, its mass spread evenly over
// its segments + 1 nodes.
struct RopeDef {
    Vec3 start = Vec3(0, 2, 0);  // m
    Vec3 end = Vec3(2, 2, 0);    // m
    int segments = 20;           // >= 1
    double mass = 1.0;           // kg, the whole rope
    double radius = 0.02;        // m, each node's collision sphere
    bool pin_start = true;
    bool pin_end = false;
    LinkSettings links;
};

// A cloth of nx x ny nodes spanning corner + s u + t v for s, t in [0, 1]:
// structural links to the 4 neighbours, shear links across each quad's two
// diagonals, bend links to the nodes two away (each kind optional, with its
// stiffness as a factor of links.stiffness, or of its inverse compliance).
struct ClothDef {
    Vec3 corner = Vec3(-1, 2, 0);  // m
    Vec3 u = Vec3(2, 0, 0);        // m, the first side (nx nodes along it)
    Vec3 v = Vec3(0, 0, 2);        // m, the second side (ny nodes along it)
    int nx = 16, ny = 16;          // nodes per side, >= 2
    double mass = 1.0;             // kg, the whole cloth
    double radius = 0.01;          // m, each node's collision sphere
    double shear = 0.5;            // shear links' stiffness factor (0: none)
    double bend = 0.1;             // bend links' stiffness factor (0: none)
    enum class Pins { none, corners, edge, all };
    Pins pins = Pins::none;  // corners: the two at t = 0; edge: the whole t = 0 side
    LinkSettings links;
};

// A box of nx x ny x nz nodes from `corner` spanning `size`, every node linked
// to its 26 lattice neighbours (edges, face and body diagonals: the diagonals
// keep the cells from shearing flat). Plasticity > 0 makes it plastic.
struct LatticeDef {
    Vec3 corner = Vec3(-0.5, 1, -0.5);  // m
    Vec3 size = Vec3(1, 1, 1);          // m
    int nx = 4, ny = 4, nz = 4;         // nodes per axis, >= 2
    double mass = 1.0;                  // kg, the whole body
    double radius = 0.05;               // m, each node's collision sphere
    Vec3 velocity = Vec3::Zero();       // m/s, initial, every node
    LinkSettings links;
    Plasticity plasticity;  // springs only
};

using SurfaceTriangle = std::array<std::uint32_t, 3>;  // particle indices, counter-clockwise seen from outside

// Where a builder put a body: particles [first, first + count), its grid, the
// links for drawing, and its outer surface (cloth: both faces are the sheet).
struct BodyRange {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    int nx = 0, ny = 1, nz = 1;                       // grid of nodes (a rope: nx = nodes)
    std::vector<std::array<std::uint32_t, 2>> links;  // every link, as particle pairs
    std::vector<SurfaceTriangle> surface;

    std::uint32_t at(int i, int j = 0, int k = 0) const {
        return first + static_cast<std::uint32_t>((k * ny + j) * nx + i);
    }
};

// Each throws InputError naming the field ("rope.segments must be ...").
BodyRange add_rope(ParticleModel& model, const RopeDef& rope);
BodyRange add_cloth(ParticleModel& model, const ClothDef& cloth);
BodyRange add_lattice(ParticleModel& model, const LatticeDef& body);

// The largest |length - rest| / rest over a body's links in a state (strain
// of 0.1 is 10%), measured against the rest lengths the model was built with.
double max_link_strain(const ParticleModel& model, const BodyRange& body, ConstVec3Span x);

}  // namespace sim
