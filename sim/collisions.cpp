#include "sim/collisions.h"

#include "sim/error.h"
#include "sim/overloaded.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <tuple>

namespace sim {

namespace {

void finite(const Vec3& v, const std::string& name, const char* unit) {
    if (!v.allFinite()) {
        throw InputError(name + " must be finite, in " + unit + " (got [" + format_value(v.x()) + ", " +
                         format_value(v.y()) + ", " + format_value(v.z()) + "])");
    }
}

// The nearest point to p on the segment a-b.
Vec3 closest_on_segment(const Vec3& a, const Vec3& b, const Vec3& p) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return a + t * ab;
}

SurfacePoint round_surface(const Vec3& center, double radius, const Vec3& p) {
    const Vec3 r = p - center;
    const double len = r.norm();
    // At the very centre every direction is as near: push up (Y is up).
    return {len - radius, len > 0.0 ? Vec3(r / len) : Vec3(Vec3::UnitY())};
}

SurfacePoint box_surface(const BoxCollider& box, const Vec3& half, const Vec3& p) {
    const Vec3 q = box.rotation.transpose() * (p - box.center);  // box frame
    const Vec3 excess = q.cwiseAbs() - half;                     // > 0 outside along that axis
    const auto sign = [&](int k) { return q[k] < 0.0 ? -1.0 : 1.0; };
    if ((excess.array() > 0.0).any()) {
        const Vec3 out = excess.cwiseMax(0.0);
        const double d = out.norm();
        Vec3 n_local;
        for (int k = 0; k < 3; ++k) n_local[k] = sign(k) * out[k] / d;
        return {d, box.rotation * n_local};
    }
    int k = 0;  // inside: leave through the nearest face
    excess.maxCoeff(&k);
    Vec3 n_local = Vec3::Zero();
    n_local[k] = sign(k);
    return {excess[k], box.rotation * n_local};
}

// Bounce and friction of a velocity against a surface of outward normal n.
void respond(Vec3& v, const Vec3& n, const Collisions& c) {
    const double vn = v.dot(n);
    if (vn >= 0.0) return;  // already leaving
    Vec3 vt = v - vn * n;
    const double new_vn = -vn < c.rest_speed ? 0.0 : -c.restitution * vn;
    const double dvn = new_vn - vn;  // > 0: the normal velocity change the contact made
    const double vt_len = vt.norm();
    const double reduce = c.friction * dvn;  // Coulomb: tangential change at most μ times the normal one
    vt = vt_len <= reduce ? Vec3(Vec3::Zero()) : Vec3(vt * (1.0 - reduce / vt_len));
    v = vt + new_vn * n;
}

// The first parameter t in [0, 1] where the segment p0 + t (p1 - p0) enters
// the box grown by r (slab method in the box frame), with the entry face's
// outward normal; none (t < 0) when p0 is inside or the segment misses.
struct Hit {
    double t = -1.0;
    Vec3 normal = Vec3::Zero();
};
Hit cast_box(const BoxCollider& box, double r, const Vec3& p0, const Vec3& p1) {
    const Vec3 half = box.half_extents + Vec3::Constant(r);
    const Vec3 a = box.rotation.transpose() * (p0 - box.center);
    const Vec3 b = box.rotation.transpose() * (p1 - box.center);
    if ((a.cwiseAbs() - half).maxCoeff() <= 0.0) return {};  // starts inside: not a crossing
    const Vec3 d = b - a;
    double t_enter = 0.0, t_exit = 1.0;
    int axis = -1;
    double axis_sign = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-300) {
            if (std::abs(a[k]) > half[k]) return {};  // parallel and outside this slab
            continue;
        }
        double t0 = (-half[k] - a[k]) / d[k];
        double t1 = (half[k] - a[k]) / d[k];
        double face = -1.0;  // entering through the -k face when moving +k
        if (t0 > t1) {
            std::swap(t0, t1);
            face = 1.0;
        }
        if (t0 > t_enter) {
            t_enter = t0;
            axis = k;
            axis_sign = face;
        }
        t_exit = std::min(t_exit, t1);
        if (t_enter > t_exit) return {};
    }
    if (axis < 0) return {};
    Vec3 n_local = Vec3::Zero();
    n_local[axis] = axis_sign;
    return {t_enter, box.rotation * n_local};
}

// A static collider's ColliderBounds.
ColliderBounds collider_bounds(const Collider& collider) {
    const auto widened = [](const Vec3& lo, const Vec3& hi, const Vec3& grow) {
        const double margin = 1e-9 * (1.0 + std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));  // m
        return ColliderBounds{lo.array() - margin, hi.array() + margin, grow};
    };
    return std::visit(Overloaded{
                          [&](const PlaneCollider&) {
                              const double inf = std::numeric_limits<double>::infinity();
                              return ColliderBounds{Vec3::Constant(-inf), Vec3::Constant(inf)};
                          },
                          [&](const SphereCollider& b) {
                              return widened(b.center.array() - b.radius, b.center.array() + b.radius, Vec3::Ones());
                          },
                          [&](const BoxCollider& b) {
                              // The box grown by r is grown by r along each of its own axes: in
                              // world axes by r times each row's sum of |rotation| (1 to √3).
                              const Eigen::Matrix3d turn = b.rotation.cwiseAbs();
                              const Vec3 extent = turn * b.half_extents;  // the rotated box's half size
                              return widened(b.center - extent, b.center + extent, turn * Vec3::Ones());
                          },
                          [&](const CapsuleCollider& b) {
                              return widened(b.a.cwiseMin(b.b).array() - b.radius, b.a.cwiseMax(b.b).array() + b.radius,
                                             Vec3::Ones());
                          },
                      },
                      collider);
}

// A particle's substep from x0 to x as the quick rejects see it: the box in
// world axes around the two, and a slack above the rounding of positions
// that large, m.
struct Sweep {
    Vec3 lo, hi;  // m
    double slack;
};
inline Sweep sweep(const Vec3& x0, const Vec3& x) {
    return {x0.cwiseMin(x), x0.cwiseMax(x), 1e-9 * (1.0 + std::max(x0.cwiseAbs().maxCoeff(), x.cwiseAbs().maxCoeff()))};
}

// Whether a particle of radius r on `sweep` stays outside the bounds on some
// axis. NaN never does: it goes to the exact test.
inline bool outside_bounds(const ColliderBounds& bounds, const Sweep& sweep, double r) {
    for (int k = 0; k < 3; ++k) {
        const double reach = r * bounds.grow[k] + sweep.slack;
        if (sweep.lo[k] - reach > bounds.hi[k] || sweep.hi[k] + reach < bounds.lo[k]) return true;
    }
    return false;
}

// The box in world axes around every moving collider's reach (its quick
// reject's sphere), widened as collider_bounds widens: a particle outside
// it, grown by its radius, is outside every one of those spheres. Empty
// (lo > hi) without moving colliders.
ColliderBounds moving_bounds(const std::vector<MovingCollider>& moving) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const MovingCollider& m : moving) {
        lo = lo.cwiseMin(m.pivot - Vec3::Constant(m.reach));
        hi = hi.cwiseMax(m.pivot + Vec3::Constant(m.reach));
    }
    if (moving.empty() || !lo.allFinite() || !hi.allFinite()) return {lo, hi};  // (a NaN pivot: never outside)
    const double margin = 1e-9 * (1.0 + std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));  // m
    return {lo.array() - margin, hi.array() + margin};
}

// One particle against a plane: collide_static's plane case written out, so
// that the common ground plane costs a dot product per particle and not two
// dispatches on the collider's type.
inline bool collide_plane(const PlaneCollider& plane, const Collisions& c, Vec3& x, Vec3& v, double r) {
    double distance = plane.normal.dot(x) - plane.offset;  // as surface_point
    distance -= r;
    if (distance >= 0.0) return false;
    x -= distance * plane.normal;
    respond(v, plane.normal, c);
    return true;
}

// One particle against one static collider.
bool collide_static(const Collider& collider, const Collisions& c, const Vec3& x0, Vec3& x, Vec3& v, double r) {
    if (const auto* box = std::get_if<BoxCollider>(&collider)) {
        const Hit hit = cast_box(*box, r, x0, x);
        if (hit.t >= 0.0) {
            x = x0 + hit.t * (x - x0);
            respond(v, hit.normal, c);
            return true;
        }
    }
    SurfacePoint s;
    if (const auto* box = std::get_if<BoxCollider>(&collider)) {
        // The grown box (corners square, not rounded): consistent with the cast.
        s = box_surface(*box, box->half_extents + Vec3::Constant(r), x);
    } else {
        s = surface_point(collider, x);
        s.distance -= r;
    }
    if (s.distance >= 0.0) return false;
    x -= s.distance * s.normal;
    respond(v, s.normal, c);
    return true;
}

// The broad phase's grid: dense, over the free particles' bounding box.
struct PairGrid {
    Vec3 lo, hi;         // m, the free particles' bounding box
    double r_max = 0.0;  // m, their largest radius
    double cell = 0.0;   // m, a cell's side
    std::int64_t nx = 0, ny = 0, nz = 0;
    std::size_t cells = 0;

    // The cell along one axis of a coordinate p (m), clamped into the grid.
    // The quotient is clamped as a double before it becomes an integer: a
    // coordinate beyond the grid (or a quotient of infinities, NaN) cannot
    // overflow the conversion.
    std::int32_t axis(double p, double origin, std::int64_t count) const {
        const double q = (p - origin) / cell;
        const double last = static_cast<double>(count - 1);
        return static_cast<std::int32_t>(q < last ? std::max(q, 0.0) : last);
    }
};

// A particle the grid holds: free, of some size, and somewhere (a position
// that is not finite has already blown up: the watchdog names it after this
// substep, and it must not stretch the grid to infinity first).
inline bool in_grid(ConstVec3Span x, const double* radius, const double* inv_mass, std::size_t i) {
    return inv_mass[i] != 0.0 && radius[i] > 0.0 && std::isfinite(x.c[0][i]) && std::isfinite(x.c[1][i]) &&
           std::isfinite(x.c[2][i]);
}

// Cells along an axis of the given extent (m): floor(extent / cell) + 1, in
// double. A tiny radius (1e-20 m) over a metre is 5e19 cells, more than an
// int64 holds: the count stays a double until the coarsening below has made
// it small. An infinite extent (particles beyond ±9e307 m) over an infinite
// cell is NaN: one cell.
double cells_along(double extent, double cell) {
    const double q = extent / cell;
    return std::isnan(q) ? 1.0 : std::floor(q) + 1.0;
}

// Only free particles enter the grid: pinned ones (and an emitter's parked
// ones, all in one place) are not obstacles to each other or to anyone.
// Cells of 2 r_max (a particle's neighbours are in the cells around its
// own), coarsened while the grid would have more than 16 cells per particle
// (a far outlier, or radii far smaller than the spread: the doubling ends
// within about 2100 rounds, at the latest when the cell is infinite and the
// grid one cell). Cells are numbered x fastest, so the three cells of a row
// dx = -1, 0, 1 are one range of the sorted entries. None: fewer than two
// free particles.
std::optional<PairGrid> pair_grid(ConstVec3Span x, const double* radius, const double* inv_mass) {
    PairGrid g;
    g.lo = Vec3::Constant(std::numeric_limits<double>::max());
    g.hi = -g.lo;
    std::size_t free = 0;
    for (std::size_t i = 0; i < x.n; ++i) {
        if (!in_grid(x, radius, inv_mass, i)) continue;
        g.r_max = std::max(g.r_max, radius[i]);
        const Vec3 p = x.get(i);
        g.lo = g.lo.cwiseMin(p);
        g.hi = g.hi.cwiseMax(p);
        ++free;
    }
    if (free < 2) return std::nullopt;
    g.cell = 2.0 * g.r_max;
    const double most = 16.0 * static_cast<double>(free) + 64.0;  // cells
    double nx = 0.0, ny = 0.0, nz = 0.0;
    for (;;) {
        nx = cells_along(g.hi.x() - g.lo.x(), g.cell);
        ny = cells_along(g.hi.y() - g.lo.y(), g.cell);
        nz = cells_along(g.hi.z() - g.lo.z(), g.cell);
        if (nx * ny * nz <= most) break;
        g.cell *= 2.0;
    }
    // Each count is now at most `most` (about 16 cells a particle): exact in
    // an int64, and the cell ids within an int32 for up to 1e8 particles.
    g.nx = static_cast<std::int64_t>(nx);
    g.ny = static_cast<std::int64_t>(ny);
    g.nz = static_cast<std::int64_t>(nz);
    g.cells = static_cast<std::size_t>(g.nx * g.ny * g.nz);
    return g;
}

// Each entry's position and radius side by side, in entry order (x, y, z, r),
// so that the candidate scans read one cache line per entry.
void gather_sorted(ConstVec3Span x, const double* radius, std::uint32_t entries, CollisionScratch& s) {
    s.sorted.resize(4 * static_cast<std::size_t>(entries));
    for (std::uint32_t e = 0; e < entries; ++e) {
        const std::uint32_t i = s.cell_entries[e];
        s.sorted[4 * e + 0] = x.c[0][i];
        s.sorted[4 * e + 1] = x.c[1][i];
        s.sorted[4 * e + 2] = x.c[2][i];
        s.sorted[4 * e + 3] = radius[i];
    }
}

// Counting sort of the free particles by cell. The counts go two slots up
// (cell_start[id + 2]), so that after the prefix sum cell_start[id + 1] is
// cell id's first entry, and filling the entries through it moves it on to
// the next cell's first: cell_start[id] ends as the first entry of cell id,
// with no second array of cursors. Then positions and radii in entry order
// (s.sorted): the candidate tests read them in sequence. Returns the number
// of entries.
std::uint32_t sort_into_cells(const PairGrid& g, ConstVec3Span x, const double* radius, const double* inv_mass,
                              CollisionScratch& s) {
    const std::size_t n = x.n;
    s.cell_start.assign(g.cells + 2, 0);
    s.cell_of.resize(n);
    s.cell_xyz.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!in_grid(x, radius, inv_mass, i)) {
            s.cell_of[i] = -1;
            continue;
        }
        const GridCell c{g.axis(x.c[0][i], g.lo.x(), g.nx), g.axis(x.c[1][i], g.lo.y(), g.ny),
                         g.axis(x.c[2][i], g.lo.z(), g.nz)};
        s.cell_xyz[i] = c;
        s.cell_of[i] = static_cast<std::int32_t>((c.z * g.ny + c.y) * g.nx + c.x);
        ++s.cell_start[static_cast<std::size_t>(s.cell_of[i]) + 2];
    }
    for (std::size_t k = 1; k < g.cells + 2; ++k) s.cell_start[k] += s.cell_start[k - 1];
    s.cell_entries.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (s.cell_of[i] >= 0)
            s.cell_entries[s.cell_start[static_cast<std::size_t>(s.cell_of[i]) + 1]++] = static_cast<std::uint32_t>(i);
    }
    const auto entries = static_cast<std::uint32_t>(s.cell_start[g.cells]);
    gather_sorted(x, radius, entries, s);
    return entries;
}

// A crowded grid: the dense grid spans the free particles' bounding box and
// coarsens until it has about 16 cells a particle, so one far particle (a
// droplet flung 9 km off, still inside the watchdog's box) stretches it until
// the others share a few cells, and the tests grow as the square of a cell's
// count (10⁵ particles in one cell: 5e9 tests a pass, seconds a substep).
// find_pairs gives up past kCrowded candidates an entry (plus a floor for
// small scenes) and the pass takes the sparse grid below instead. The shipped
// scenes test at most a few an entry (the fountain: about seven).
constexpr double kCrowded = 64.0;
constexpr double kCrowdedFloor = 4096.0;

// Entry ei against entries [begin, end) into s.pairs from `found`; returns
// the new count. Every candidate is written and the count moves on only for
// an overlap: no branch to mispredict on a test that is mostly false (about
// one candidate in seven overlaps in the fountain). Room for the whole range first.
inline std::size_t scan_candidates(CollisionScratch& s, std::uint32_t ei, std::uint32_t begin, std::uint32_t end,
                                   std::size_t found) {
    if (begin >= end) return found;
    if (s.pairs.size() < found + (end - begin)) s.pairs.resize(2 * (found + (end - begin)));
    std::array<std::uint32_t, 2>* out = s.pairs.data();
    const double* pi = &s.sorted[4 * static_cast<std::size_t>(ei)];
    for (std::uint32_t ej = begin; ej < end; ++ej) {
        const double* pj = &s.sorted[4 * static_cast<std::size_t>(ej)];
        const double dx = pi[0] - pj[0], dy = pi[1] - pj[1], dz = pi[2] - pj[2];
        const double reach = pi[3] + pj[3];
        out[found] = {ei, ej};
        found += dx * dx + dy * dy + dz * dz < reach * reach;
    }
    return found;
}

// Overlapping pairs into s.pairs, as entry indices (ei < ej), on the
// positions as they were at the start of the pass; returns how many. Each
// entry against: the rest of its own cell and the next one in its row (one
// range), the row above (dy = 1), and the three rows in front (dz = 1, dy =
// -1 .. 1), each row dx = -1 .. 1: the 13 forward neighbour cells, so every
// pair is found once, in the order (ei, ej). None when the grid is crowded
// (kCrowded).
//
// A neighbour cell across a face of the entry's cell that is farther from it
// than the largest reach 2 r_max holds nothing it overlaps: that cell is left
// out of its range (dropping only candidates that would fail the test, so the
// same pairs in the same order). Cells are often coarser than 2 r_max (see
// pair_grid), and this skips most of the 13. The faces lo + k cell computed
// here and the cell indices of the particles differ by rounding, a few ulp of
// the coordinates: `slack`, a millionfold that, keeps the skipping on the
// safe side.
std::optional<std::size_t> find_pairs(const PairGrid& g, std::uint32_t entries, CollisionScratch& s) {
    const double reach_max = 2.0 * g.r_max;  // m, the largest r_i + r_j
    const double slack = 1e-9 * std::max({g.lo.cwiseAbs().maxCoeff(), g.hi.cwiseAbs().maxCoeff(), g.cell});  // m
    auto near_low = [&](double p, double origin, std::int64_t k) {
        return p - (origin + k * g.cell) < reach_max + slack;
    };
    auto near_high = [&](double p, double origin, std::int64_t k) {
        return (origin + (k + 1) * g.cell) - p < reach_max + slack;
    };
    const double* sorted = s.sorted.data();
    const std::uint32_t* cell_start = s.cell_start.data();
    std::size_t found = 0;
    double tested = 0.0;  // candidates tested so far
    const double most_tested = kCrowded * entries + kCrowdedFloor;
    for (std::uint32_t ei = 0; ei < entries; ++ei) {
        if (tested > most_tested) return std::nullopt;
        const double* pi = &sorted[4 * static_cast<std::size_t>(ei)];
        const GridCell c = s.cell_xyz[s.cell_entries[ei]];
        const std::int64_t cx = c.x, cy = c.y, cz = c.z;
        // The cells of a row to scan: dx = -1 and dx = 1 when near those faces.
        const std::int64_t x_first = cx > 0 && near_low(pi[0], g.lo.x(), cx) ? cx - 1 : cx;
        const std::int64_t x_last = cx + 1 < g.nx && near_high(pi[0], g.lo.x(), cx) ? cx + 1 : cx;
        auto scan = [&](std::uint32_t begin, std::uint32_t end) {
            tested += end > begin ? end - begin : 0;
            found = scan_candidates(s, ei, begin, end, found);
        };
        auto row = [&](std::int64_t y, std::int64_t z) {
            if (y < 0 || y >= g.ny || z >= g.nz) return;
            const std::int64_t base = (z * g.ny + y) * g.nx;
            scan(cell_start[static_cast<std::size_t>(base + x_first)],
                 cell_start[static_cast<std::size_t>(base + x_last + 1)]);
        };
        const std::int64_t id = (cz * g.ny + cy) * g.nx + cx;
        scan(ei + 1, cell_start[static_cast<std::size_t>(id + 1 + (x_last - cx))]);
        if (near_high(pi[1], g.lo.y(), cy)) row(cy + 1, cz);
        if (near_high(pi[2], g.lo.z(), cz)) {
            if (near_low(pi[1], g.lo.y(), cy)) row(cy - 1, cz + 1);
            row(cy, cz + 1);
            if (near_high(pi[1], g.lo.y(), cy)) row(cy + 1, cz + 1);
        }
    }
    return found;
}

// The crowded grid's fallback: a sparse grid of cells of 2 r_max holding
// only the occupied ones, as the entries sorted by cell (z, y, x, then by
// particle); a neighbour row is a binary search. O(n log n) however far apart
// the particles are. The cell coordinates stay doubles, floor((p - lo) /
// cell): exact below 2^53 cells; beyond (a particle 2^53 diameters from the
// lowest, where positions are no finer than a diameter) two touching
// particles may land in cells two apart and be missed. Its pairs come in
// another order than the dense grid's, so only a crowded pass takes it.
std::uint32_t sort_sparse(const PairGrid& g, ConstVec3Span x, const double* radius, const double* inv_mass,
                          CollisionScratch& s) {
    const double cell = 2.0 * g.r_max;
    auto key = [&](double p, double origin) {
        return std::floor(std::min((p - origin) / cell, std::numeric_limits<double>::max()));
    };
    s.cell_entries.clear();
    s.sparse_cells.resize(x.n);
    for (std::uint32_t i = 0; i < x.n; ++i) {
        if (!in_grid(x, radius, inv_mass, i)) continue;
        s.sparse_cells[i] = {key(x.c[0][i], g.lo.x()), key(x.c[1][i], g.lo.y()), key(x.c[2][i], g.lo.z())};
        s.cell_entries.push_back(i);
    }
    const auto& cells = s.sparse_cells;
    std::sort(s.cell_entries.begin(), s.cell_entries.end(), [&](std::uint32_t a, std::uint32_t b) {
        return std::tie(cells[a][2], cells[a][1], cells[a][0], a) < std::tie(cells[b][2], cells[b][1], cells[b][0], b);
    });
    const auto entries = static_cast<std::uint32_t>(s.cell_entries.size());
    gather_sorted(x, radius, entries, s);
    // The cells in entry order, for the searches.
    std::vector<std::array<double, 3>> by_entry(entries);
    for (std::uint32_t e = 0; e < entries; ++e) by_entry[e] = cells[s.cell_entries[e]];
    s.sparse_cells = std::move(by_entry);
    return entries;
}

// The pairs of the sparse grid, each entry against the same 13 forward
// neighbour cells as find_pairs: its own row up to the next cell (one range),
// the row above, the three rows in front. A row whose coordinate ± 1 rounds
// back to the entry's own (beyond 2^53 cells) is its own row, scanned once.
std::size_t find_pairs_sparse(std::uint32_t entries, CollisionScratch& s) {
    const auto& cells = s.sparse_cells;  // (x, y, z) in entry order
    auto order = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    };
    const auto begin = cells.begin(), end = cells.begin() + entries;
    auto first = [&](const std::array<double, 3>& c) {
        return static_cast<std::uint32_t>(std::lower_bound(begin, end, c, order) - begin);
    };
    auto after = [&](const std::array<double, 3>& c) {
        return static_cast<std::uint32_t>(std::upper_bound(begin, end, c, order) - begin);
    };
    std::size_t found = 0;
    for (std::uint32_t ei = 0; ei < entries; ++ei) {
        const double cx = cells[ei][0], cy = cells[ei][1], cz = cells[ei][2];
        auto row = [&](double y, double z) {
            found = scan_candidates(s, ei, first({cx - 1.0, y, z}), after({cx + 1.0, y, z}), found);
        };
        found = scan_candidates(s, ei, ei + 1, after({cx + 1.0, cy, cz}), found);
        if (cy + 1.0 != cy) row(cy + 1.0, cz);
        if (cz + 1.0 == cz) continue;
        if (cy - 1.0 != cy) row(cy - 1.0, cz + 1.0);
        row(cy, cz + 1.0);
        if (cy + 1.0 != cy) row(cy + 1.0, cz + 1.0);
    }
    return found;
}

// The first `found` pairs of s.pairs resolved in the order found, on the
// live arrays: a pair may already have been pushed apart by an earlier one
// of this pass. Returns the contacts resolved.
std::size_t resolve_pairs(const Collisions& c, Vec3Span x, Vec3Span v, const double* radius, const double* inv_mass,
                          const CollisionScratch& s, std::size_t found) {
    std::size_t contacts = 0;
    for (std::size_t k = 0; k < found; ++k) {
        const auto [ei, ej] = s.pairs[k];
        const std::uint32_t i = s.cell_entries[ei], j = s.cell_entries[ej];
        const double wi = inv_mass[i], wj = inv_mass[j];
        const Vec3 d = x.get(i) - x.get(j);
        const double reach = radius[i] + radius[j];
        const double dist2 = d.squaredNorm();
        if (dist2 >= reach * reach) continue;  // separated by an earlier pair of this pass
        const double dist = std::sqrt(dist2);
        // Coincident centres (closer than 1e-12 of their reach, relative so
        // that radii of 1e-20 m keep their direction): none; separate them along +Y.
        const Vec3 nrm = dist > 1e-12 * reach ? Vec3(d / dist) : Vec3(Vec3::UnitY());
        const double depth = reach - dist;
        x.add(i, (depth * wi / (wi + wj)) * nrm);
        x.add(j, (-depth * wj / (wi + wj)) * nrm);
        // Relative velocity: restitution along the normal, Coulomb across it.
        const Vec3 vrel = v.get(i) - v.get(j);
        const double vn = vrel.dot(nrm);
        if (vn < 0.0) {
            const double new_vn = -vn < c.rest_speed ? 0.0 : -c.restitution * vn;
            const double jn = (new_vn - vn) / (wi + wj);  // normal impulse per unit mass sum
            Vec3 impulse = jn * nrm;
            const Vec3 vt = vrel - vn * nrm;
            const double vt_len = vt.norm();
            if (vt_len > 0.0) {
                const double jt = std::min(c.friction * jn, vt_len / (wi + wj));
                impulse -= (jt / vt_len) * vt;
            }
            v.add(i, wi * impulse);
            v.add(j, -wj * impulse);
        }
        ++contacts;
    }
    return contacts;
}

// Particle against particle: a grid broad phase, then the overlapping pairs
// resolved one by one.
std::size_t collide_pairs(const Collisions& c, Vec3Span x, Vec3Span v, const double* radius, const double* inv_mass,
                          CollisionScratch& s) {
    const std::optional<PairGrid> grid = pair_grid(x, radius, inv_mass);
    if (!grid) return 0;
    std::uint32_t entries = sort_into_cells(*grid, x, radius, inv_mass, s);
    std::optional<std::size_t> found = find_pairs(*grid, entries, s);
    if (!found) {
        entries = sort_sparse(*grid, x, radius, inv_mass, s);
        found = find_pairs_sparse(entries, s);
    }
    return resolve_pairs(c, x, v, radius, inv_mass, s, *found);
}

}  // namespace

void validate(const Collisions& c) {
    if (!(c.restitution >= 0.0 && c.restitution <= 1.0)) {
        throw InputError("collisions.restitution must be within 0 .. 1 (got " + format_value(c.restitution) + ")");
    }
    if (!(c.friction >= 0.0) || !std::isfinite(c.friction)) {
        throw InputError("collisions.friction must be >= 0 and finite (got " + format_value(c.friction) + ")");
    }
    if (!(c.rest_speed >= 0.0) || !std::isfinite(c.rest_speed)) {
        throw InputError("collisions.rest_speed must be >= 0 and finite, in m/s (got " + format_value(c.rest_speed) +
                         ")");
    }
    for (std::size_t k = 0; k < c.colliders.size(); ++k) {
        const std::string name = "collisions.colliders[" + std::to_string(k) + "]";
        std::visit(
            Overloaded{
                [&](const PlaneCollider& p) {
                    finite(p.normal, name + ".normal", "(a direction)");
                    if (std::abs(p.normal.norm() - 1.0) > 1e-9) {
                        throw InputError(name + ".normal must be a unit vector (got length " +
                                         format_value(p.normal.norm()) + ")");
                    }
                    if (!std::isfinite(p.offset)) {
                        throw InputError(name + ".offset must be finite, in m (got " + format_value(p.offset) + ")");
                    }
                },
                [&](const SphereCollider& s) {
                    finite(s.center, name + ".center", "m");
                    require_positive(s.radius, name + ".radius", "m");
                },
                [&](const BoxCollider& b) {
                    finite(b.center, name + ".center", "m");
                    for (int i = 0; i < 3; ++i) require_positive(b.half_extents[i], name + ".half_extents", "m");
                    if (!b.rotation.allFinite() ||
                        (b.rotation.transpose() * b.rotation - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
                        b.rotation.determinant() < 0.0) {
                        throw InputError(name + ".rotation must be a rotation (orthonormal, det +1)");
                    }
                },
                [&](const CapsuleCollider& cap) {
                    finite(cap.a, name + ".a", "m");
                    finite(cap.b, name + ".b", "m");
                    require_positive(cap.radius, name + ".radius", "m");
                },
            },
            c.colliders[k]);
    }
}

SurfacePoint surface_point(const Collider& collider, const Vec3& p) {
    return std::visit(Overloaded{
                          [&](const PlaneCollider& plane) {
                              return SurfacePoint{plane.normal.dot(p) - plane.offset, plane.normal};
                          },
                          [&](const SphereCollider& s) { return round_surface(s.center, s.radius, p); },
                          [&](const BoxCollider& b) { return box_surface(b, b.half_extents, p); },
                          [&](const CapsuleCollider& cap) {
                              return round_surface(closest_on_segment(cap.a, cap.b, p), cap.radius, p);
                          },
                      },
                      collider);
}

std::size_t collide(const Collisions& c, ConstVec3Span x0, Vec3Span x, Vec3Span v, const double* radius,
                    const double* inv_mass, double /*h*/, CollisionScratch& scratch,
                    const std::vector<MovingCollider>& moving) {
    std::size_t contacts = 0;
    if (c.particle_particle) contacts += collide_pairs(c, x, v, radius, inv_mass, scratch);
    if (!c.colliders.empty() || !moving.empty()) {
        scratch.collider_bounds.resize(c.colliders.size());
        for (std::size_t k = 0; k < c.colliders.size(); ++k)
            scratch.collider_bounds[k] = collider_bounds(c.colliders[k]);
        const ColliderBounds all_moving = moving_bounds(moving);
        const bool moving_bounded = all_moving.lo.allFinite() && all_moving.hi.allFinite();
        for (std::size_t i = 0; i < x.n; ++i) {
            if (inv_mass[i] == 0.0) continue;
            Vec3 p = x.get(i), vel = v.get(i);
            const Vec3 start = x0.get(i);
            Sweep swept = sweep(start, p);  // again wherever a contact moves p
            bool touched = false;
            for (std::size_t k = 0; k < c.colliders.size(); ++k) {
                const Collider& collider = c.colliders[k];
                const auto* plane = std::get_if<PlaneCollider>(&collider);
                bool touch = false;
                if (plane) {
                    touch = collide_plane(*plane, c, p, vel, radius[i]);
                } else if (!outside_bounds(scratch.collider_bounds[k], swept, radius[i])) {
                    touch = collide_static(collider, c, start, p, vel, radius[i]);
                }
                if (touch) swept = sweep(start, p), touched = true;
            }
            // Outside the box around every moving collider's reach, p is outside each one's.
            const bool near_moving = !moving_bounded || !outside_bounds(all_moving, sweep(p, p), radius[i]);
            for (std::size_t k = 0; near_moving && k < moving.size(); ++k) {
                const MovingCollider& m = moving[k];
                const double reach = m.reach + radius[i];
                if ((p - m.pivot).squaredNorm() >= reach * reach) continue;
                // In the collider's frame the surface is still: respond to the relative velocity.
                const Vec3 surface = m.velocity + m.angular_velocity.cross(p - m.pivot);
                Vec3 relative = vel - surface;
                if (collide_static(m.shape, c, p, p, relative, radius[i])) {
                    vel = relative + surface;
                    touched = true;
                }
            }
            if (touched) {
                x.set(i, p);
                v.set(i, vel);
                ++contacts;
            }
        }
    }
    scratch.contacts = contacts;
    return contacts;
}

}  // namespace sim
