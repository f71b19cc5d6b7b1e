// What the section readers share: particle names and references, the palette
// (see scene_builder.h).
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

Color palette(std::size_t i) {
    static const Color colors[] = {{0.90f, 0.33f, 0.12f, 1}, {0.16f, 0.42f, 0.80f, 1}, {0.20f, 0.62f, 0.30f, 1},
                                   {0.78f, 0.22f, 0.52f, 1}, {0.95f, 0.70f, 0.15f, 1}, {0.35f, 0.30f, 0.70f, 1}};
    return colors[i % std::size(colors)];
}

void SceneBuilder::add_name(const Section& s, const std::string& name, std::size_t index) {
    if (name.empty()) return;
    if (!particle_index.emplace(name, index).second) s.fail("name", "must be unique: " + quote(name) + " is taken");
}

std::size_t SceneBuilder::new_particles(const Section& s, long long fallback) const {
    const long long count = s.integer("count", fallback, 1, static_cast<long long>(kMaxParticles));
    if (scene.model.particles.size() + static_cast<std::size_t>(count) > kMaxParticles) {
        s.fail("count", "makes more than " + std::to_string(kMaxParticles) + " particles in the scene");
    }
    return static_cast<std::size_t>(count);
}

std::size_t SceneBuilder::particle_at(const toml::node& n, const std::string& where) const {
    if (auto name = n.value<std::string>(); name && n.is_string()) {
        if (auto it = particle_index.find(*name); it != particle_index.end()) return it->second;
        r.fail(&n, where + " names no particle (got " + quote(*name) + ")");
    }
    if (n.is_integer()) {
        const long long i = *n.value<long long>();
        if (i >= 0 && static_cast<std::size_t>(i) < scene.model.particles.size()) return static_cast<std::size_t>(i);
        r.fail(&n, where + " must be a particle index within 0 .. " + std::to_string(scene.model.particles.size() - 1) +
                       " (got " + std::to_string(i) + ")");
    }
    r.fail(&n, where + " must be a particle name or index (got " + describe(n) + ")");
}

std::size_t SceneBuilder::particle_ref(const Section& s, std::string_view key) const {
    const toml::node* n = s.node(key);
    if (n == nullptr) s.fail(key, "is required: a particle name or index");
    return particle_at(*n, s.key_path(key));
}

std::vector<std::uint32_t> SceneBuilder::particle_list(const Section& s, std::string_view key) const {
    std::vector<std::uint32_t> out;
    const toml::node* n = s.node(key);
    if (n == nullptr) return out;
    const toml::array* a = n->as_array();
    if (a == nullptr) s.fail(key, "must be an array of particle names or indices (got " + describe(*n) + ")");
    for (std::size_t k = 0; k < a->size(); ++k) {
        out.push_back(
            static_cast<std::uint32_t>(particle_at(*a->get(k), s.key_path(key) + "[" + std::to_string(k) + "]")));
    }
    return out;
}

}  // namespace scenes::loader
