// SceneDef's own questions about itself (what scene.h declares beside the
// data): which systems it builds.
#include "scenes/model/scene.h"

namespace scenes {

std::vector<std::string> SceneDef::systems() const { return sim::systems_of(model, watchdog).names(); }

}  // namespace scenes
