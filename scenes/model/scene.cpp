// SceneDef's own questions about itself (what scene.h declares beside the
// data): which systems it builds.
#include "scenes/model/scene.h"

namespace scenes {

std::vector<std::string> SceneDef::systems() const {
    std::vector<std::string> out;
    if (!model.particles.empty()) out.push_back("particles");
    bool springs = false, plastic = false;
    for (const sim::ForceDef& f : model.forces) {
        if (const auto* s = std::get_if<sim::Springs>(&f)) {
            springs = true;
            plastic = plastic || s->plasticity.enabled();
        }
    }
    if (springs) out.push_back("springs");
    if (!model.constraints.empty()) out.push_back("constraints");
    // Particles collide with the colliders, each other and the rigid bodies
    // (bodies meet the colliders inside "rigid").
    if (!model.particles.empty() && (!model.collisions.empty() || !model.rigid.empty())) out.push_back("collisions");
    if (plastic) out.push_back("plasticity");
    if (!model.emitters.empty()) out.push_back("emitters");
    if (!model.rigid.empty()) out.push_back("rigid");
    if (watchdog.enabled) out.push_back("watchdog");
    return out;
}

}  // namespace scenes
