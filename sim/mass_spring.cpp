#include "sim/mass_spring.h"

#include "sim/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sim {

namespace {

constexpr int kMaxNodesPerSide = 4096;
constexpr std::size_t kMaxNodes = 1'000'000;

void check_count(int n, int lo, const std::string& name) {
    if (n < lo || n > kMaxNodesPerSide) {
        throw InputError(name + " must be within " + std::to_string(lo) + " .. " + std::to_string(kMaxNodesPerSide) +
                         " (got " + std::to_string(n) + ")");
    }
}

void check_links(const LinkSettings& l, const std::string& body) {
    require_nonnegative(l.stiffness, body + ".stiffness", "N/m");
    require_nonnegative(l.damping, body + ".damping", "N·s/m");
    require_nonnegative(l.compliance, body + ".compliance", "m/N");
}

// Appends one link a-b at its current distance, with the stiffness scaled by
// `factor` (a spring's k times it, a constraint's compliance divided by it).
class Linker {
public:
    Linker(ParticleModel& model, const LinkSettings& settings, BodyRange& body, const Plasticity& plasticity = {})
        : model_(model), settings_(settings), body_(body) {
        springs_.plasticity = plasticity;
    }
    void link(std::uint32_t a, std::uint32_t b, double factor = 1.0) {
        const double rest = (model_.particles[a].position - model_.particles[b].position).norm();
        if (settings_.kind == LinkSettings::Kind::springs) {
            springs_.list.push_back({a, b, rest, settings_.stiffness * factor, settings_.damping * factor});
        } else {
            model_.constraints.distance.push_back({a, b, rest, settings_.compliance / factor});
        }
        body_.links.push_back({a, b});
    }
    // Adds the body's springs as one generator (its own plasticity).
    void finish() {
        if (!springs_.list.empty()) model_.forces.push_back(std::move(springs_));
    }

private:
    ParticleModel& model_;
    const LinkSettings& settings_;
    BodyRange& body_;
    Springs springs_;
};

void add_nodes(ParticleModel& model, std::size_t count) {
    if (model.particles.size() + count > kMaxNodes) {
        throw InputError("a body of " + std::to_string(count) + " nodes makes more than " + std::to_string(kMaxNodes) +
                         " particles");
    }
}

}  // namespace

BodyRange add_rope(ParticleModel& model, const RopeDef& rope) {
    check_count(rope.segments, 1, "rope.segments");
    require_positive(rope.mass, "rope.mass", "kg");
    require_nonnegative(rope.radius, "rope.radius", "m");
    check_links(rope.links, "rope");
    if (!rope.start.allFinite() || !rope.end.allFinite() || (rope.end - rope.start).norm() == 0.0) {
        throw InputError("rope.start and rope.end must be finite and apart, in m");
    }
    BodyRange body;
    body.first = static_cast<std::uint32_t>(model.particles.size());
    body.nx = rope.segments + 1;
    body.count = static_cast<std::uint32_t>(body.nx);
    add_nodes(model, body.count);
    for (int i = 0; i < body.nx; ++i) {
        ParticleDef p;
        p.position = rope.start + (rope.end - rope.start) * (static_cast<double>(i) / rope.segments);
        p.mass = rope.mass / body.nx;
        p.radius = rope.radius;
        p.pinned = (i == 0 && rope.pin_start) || (i == body.nx - 1 && rope.pin_end);
        model.particles.push_back(p);
    }
    Linker linker(model, rope.links, body);
    for (int i = 0; i + 1 < body.nx; ++i) linker.link(body.at(i), body.at(i + 1));
    linker.finish();
    if (rope.links.kind == LinkSettings::Kind::constraints && rope.links.tethers) {
        // The rope is built straight: a node's distance along it to a pin is its rest reach.
        const double segment = (rope.end - rope.start).norm() / rope.segments;
        for (int i = 0; i < body.nx; ++i) {
            if (rope.pin_start && i > 0) {
                model.constraints.tethers.push_back({body.at(i), body.at(0), segment * i});
            }
            if (rope.pin_end && i < body.nx - 1) {
                model.constraints.tethers.push_back({body.at(i), body.at(body.nx - 1), segment * (body.nx - 1 - i)});
            }
        }
    }
    return body;
}

BodyRange add_cloth(ParticleModel& model, const ClothDef& cloth) {
    check_count(cloth.nx, 2, "cloth.nx");
    check_count(cloth.ny, 2, "cloth.ny");
    require_positive(cloth.mass, "cloth.mass", "kg");
    require_nonnegative(cloth.radius, "cloth.radius", "m");
    require_nonnegative(cloth.shear, "cloth.shear", "(a factor)");
    require_nonnegative(cloth.bend, "cloth.bend", "(a factor)");
    check_links(cloth.links, "cloth");
    if (!cloth.corner.allFinite() || !cloth.u.allFinite() || !cloth.v.allFinite() ||
        cloth.u.cross(cloth.v).norm() == 0.0) {
        throw InputError("cloth.u and cloth.v must be finite, non-zero and not parallel, in m");
    }
    BodyRange body;
    body.first = static_cast<std::uint32_t>(model.particles.size());
    body.nx = cloth.nx;
    body.ny = cloth.ny;
    body.count = static_cast<std::uint32_t>(cloth.nx * cloth.ny);
    add_nodes(model, body.count);
    for (int j = 0; j < cloth.ny; ++j) {
        for (int i = 0; i < cloth.nx; ++i) {
            ParticleDef p;
            const double s = static_cast<double>(i) / (cloth.nx - 1), t = static_cast<double>(j) / (cloth.ny - 1);
            p.position = cloth.corner + s * cloth.u + t * cloth.v;
            p.mass = cloth.mass / body.count;
            p.radius = cloth.radius;
            const bool edge = j == 0;
            const bool corner = edge && (i == 0 || i == cloth.nx - 1);
            p.pinned = cloth.pins == ClothDef::Pins::all || (cloth.pins == ClothDef::Pins::edge && edge) ||
                       (cloth.pins == ClothDef::Pins::corners && corner);
            model.particles.push_back(p);
        }
    }
    Linker linker(model, cloth.links, body);
    for (int j = 0; j < cloth.ny; ++j) {
        for (int i = 0; i < cloth.nx; ++i) {
            if (i + 1 < cloth.nx) linker.link(body.at(i, j), body.at(i + 1, j));
            if (j + 1 < cloth.ny) linker.link(body.at(i, j), body.at(i, j + 1));
        }
    }
    if (cloth.shear > 0.0) {
        for (int j = 0; j + 1 < cloth.ny; ++j) {
            for (int i = 0; i + 1 < cloth.nx; ++i) {
                linker.link(body.at(i, j), body.at(i + 1, j + 1), cloth.shear);
                linker.link(body.at(i + 1, j), body.at(i, j + 1), cloth.shear);
            }
        }
    }
    if (cloth.bend > 0.0) {
        for (int j = 0; j < cloth.ny; ++j) {
            for (int i = 0; i < cloth.nx; ++i) {
                if (i + 2 < cloth.nx) linker.link(body.at(i, j), body.at(i + 2, j), cloth.bend);
                if (j + 2 < cloth.ny) linker.link(body.at(i, j), body.at(i, j + 2), cloth.bend);
            }
        }
    }
    linker.finish();
    if (cloth.links.kind == LinkSettings::Kind::constraints && cloth.links.tethers &&
        cloth.pins != ClothDef::Pins::all && cloth.pins != ClothDef::Pins::none) {
        // The cloth is built flat, so a straight line is its geodesic. A few
        // pins: tie each node to every one; many (an edge): to the nearest.
        std::vector<std::uint32_t> pins;
        for (std::uint32_t p = body.first; p < body.first + body.count; ++p) {
            if (model.particles[p].pinned) pins.push_back(p);
        }
        for (std::uint32_t p = body.first; p < body.first + body.count; ++p) {
            if (model.particles[p].pinned) continue;
            const Vec3 at = model.particles[p].position;
            auto reach = [&](std::uint32_t pin) { return (model.particles[pin].position - at).norm(); };
            if (pins.size() <= 4) {
                for (std::uint32_t pin : pins) model.constraints.tethers.push_back({p, pin, reach(pin)});
            } else {
                const auto nearest =
                    *std::min_element(pins.begin(), pins.end(), [&](auto a, auto b) { return reach(a) < reach(b); });
                model.constraints.tethers.push_back({p, nearest, reach(nearest)});
            }
        }
    }
    for (int j = 0; j + 1 < cloth.ny; ++j) {
        for (int i = 0; i + 1 < cloth.nx; ++i) {
            body.surface.push_back({body.at(i, j), body.at(i + 1, j), body.at(i + 1, j + 1)});
            body.surface.push_back({body.at(i, j), body.at(i + 1, j + 1), body.at(i, j + 1)});
        }
    }
    return body;
}

BodyRange add_lattice(ParticleModel& model, const LatticeDef& def) {
    check_count(def.nx, 2, "soft_body.nx");
    check_count(def.ny, 2, "soft_body.ny");
    check_count(def.nz, 2, "soft_body.nz");
    require_positive(def.mass, "soft_body.mass", "kg");
    require_nonnegative(def.radius, "soft_body.radius", "m");
    check_links(def.links, "soft_body");
    for (int k = 0; k < 3; ++k) require_positive(def.size[k], "soft_body.size", "m");
    if (!def.corner.allFinite() || !def.velocity.allFinite()) {
        throw InputError("soft_body.corner and soft_body.velocity must be finite");
    }
    BodyRange body;
    body.first = static_cast<std::uint32_t>(model.particles.size());
    body.nx = def.nx;
    body.ny = def.ny;
    body.nz = def.nz;
    const std::size_t count = static_cast<std::size_t>(def.nx) * def.ny * def.nz;
    add_nodes(model, count);
    body.count = static_cast<std::uint32_t>(count);
    for (int k = 0; k < def.nz; ++k) {
        for (int j = 0; j < def.ny; ++j) {
            for (int i = 0; i < def.nx; ++i) {
                ParticleDef p;
                const Vec3 f(static_cast<double>(i) / (def.nx - 1), static_cast<double>(j) / (def.ny - 1),
                             static_cast<double>(k) / (def.nz - 1));
                p.position = def.corner + def.size.cwiseProduct(f);
                p.velocity = def.velocity;
                p.mass = def.mass / static_cast<double>(count);
                p.radius = def.radius;
                model.particles.push_back(p);
            }
        }
    }
    Linker linker(model, def.links, body, def.plasticity);
    // Each of the 13 "forward" neighbour offsets once: all 26 neighbours, no pair twice.
    for (int k = 0; k < def.nz; ++k) {
        for (int j = 0; j < def.ny; ++j) {
            for (int i = 0; i < def.nx; ++i) {
                for (int dk = -1; dk <= 1; ++dk) {
                    for (int dj = -1; dj <= 1; ++dj) {
                        for (int di = -1; di <= 1; ++di) {
                            const bool forward = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
                            const int a = i + di, b = j + dj, c = k + dk;
                            if (!forward || a < 0 || b < 0 || c < 0 || a >= def.nx || b >= def.ny || c >= def.nz) {
                                continue;
                            }
                            linker.link(body.at(i, j, k), body.at(a, b, c));
                        }
                    }
                }
            }
        }
    }
    linker.finish();
    // The six faces, two triangles per cell, counter-clockwise from outside.
    auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
        body.surface.push_back({a, b, c});
        body.surface.push_back({a, c, d});
    };
    for (int j = 0; j + 1 < def.ny; ++j) {
        for (int i = 0; i + 1 < def.nx; ++i) {
            const int z1 = def.nz - 1;
            quad(body.at(i, j, 0), body.at(i, j + 1, 0), body.at(i + 1, j + 1, 0), body.at(i + 1, j, 0));      // -z
            quad(body.at(i, j, z1), body.at(i + 1, j, z1), body.at(i + 1, j + 1, z1), body.at(i, j + 1, z1));  // +z
        }
    }
    for (int k = 0; k + 1 < def.nz; ++k) {
        for (int i = 0; i + 1 < def.nx; ++i) {
            const int y1 = def.ny - 1;
            quad(body.at(i, 0, k), body.at(i + 1, 0, k), body.at(i + 1, 0, k + 1), body.at(i, 0, k + 1));      // -y
            quad(body.at(i, y1, k), body.at(i, y1, k + 1), body.at(i + 1, y1, k + 1), body.at(i + 1, y1, k));  // +y
        }
    }
    for (int k = 0; k + 1 < def.nz; ++k) {
        for (int j = 0; j + 1 < def.ny; ++j) {
            const int x1 = def.nx - 1;
            quad(body.at(0, j, k), body.at(0, j, k + 1), body.at(0, j + 1, k + 1), body.at(0, j + 1, k));      // -x
            quad(body.at(x1, j, k), body.at(x1, j + 1, k), body.at(x1, j + 1, k + 1), body.at(x1, j, k + 1));  // +x
        }
    }
    return body;
}

double max_link_strain(const ParticleModel& model, const BodyRange& body, ConstVec3Span x) {
    double worst = 0.0;
    for (const auto& [a, b] : body.links) {
        const double rest = (model.particles[a].position - model.particles[b].position).norm();
        if (rest <= 0.0) continue;
        worst = std::max(worst, std::abs((x.get(a) - x.get(b)).norm() - rest) / rest);
    }
    return worst;
}

}  // namespace sim
