// The loader's soft-body reader: [[soft_bodies]], a box lattice of nx by ny by
// nz particles with springs or constraints, plastic when yield_strain > 0
// (sim::add_lattice builds it). Its nodes are drawn as its surface mesh.
#include "scenes/model/scene_builder.h"

#include <cstdlib>

namespace scenes::loader {

void read_soft_bodies(SceneBuilder& b, const Section& top) {
    const auto softs = top.entries("soft_bodies", 1'000);
    for (std::size_t k = 0; k < softs.size(); ++k) {
        const Section& s = softs[k];
        s.only(keys::soft_body);
        sim::LatticeDef d;
        d.corner = s.vec3("corner", d.corner, "m");
        d.size = s.lengths("size", d.size, "must have three sizes > 0, in m");
        d.nx = static_cast<int>(s.integer("nx", d.nx, 2, 256));
        d.ny = static_cast<int>(s.integer("ny", d.ny, 2, 256));
        d.nz = static_cast<int>(s.integer("nz", d.nz, 2, 256));
        d.mass = s.positive("mass", d.mass, kHuge, "kg");
        d.radius = s.number("radius", d.radius, 0.0, 100.0, "m");
        d.velocity = s.vec3("velocity", d.velocity, "m/s");
        d.links = link_keys(s, 1000.0);
        d.plasticity.yield_strain = s.number("yield_strain", 0.0, 0.0, 0.99, "(a strain)");
        d.plasticity.creep = s.number("creep", d.plasticity.yield_strain > 0 ? 10.0 : 0.0, 0.0, 1e6, "1/s");
        d.plasticity.max_strain = s.number("max_strain", d.plasticity.max_strain, 0.0, 0.99, "(a strain)");
        const Color color = s.color("color", palette(b.scene.bodies.size()));
        // sim::add_lattice's links: each of the 13 forward neighbour offsets
        // (di, dj, dk) links (nx - |di|) (ny - |dj|) (nz - |dk|) pairs.
        std::size_t links = 0;
        for (int dk = -1; dk <= 1; ++dk) {
            for (int dj = -1; dj <= 1; ++dj) {
                for (int di = -1; di <= 1; ++di) {
                    if (!(dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0))))) continue;
                    links +=
                        static_cast<std::size_t>((d.nx - std::abs(di)) * (d.ny - std::abs(dj)) * (d.nz - std::abs(dk)));
                }
            }
        }
        refuse_links_ahead(b, s, links, static_cast<std::size_t>(d.nx * d.ny * d.nz));
        const auto range = build_body(s, [&] { return sim::add_lattice(b.scene.model, d); });
        add_body(b, s, BodyLook::Kind::soft_body, range, s.string("name", "soft_body" + std::to_string(k), 64), color,
                 false, d.radius);
    }
}

}  // namespace scenes::loader
