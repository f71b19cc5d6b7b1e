// --set KEY=VALUE overrides, applied to the parsed file before any reader sees
// it, so that an override goes through the same checks as the file (and its
// errors say "--set KEY=VALUE"). Its own file because it edits the TOML tree,
// which no section reader does.
#pragma once

#include "scenes/model/scene.h"
#include "scenes/model/toml_section.h"

#include <toml++/toml.h>

#include <vector>

namespace scenes::loader {

// Applies each override in turn (the last one of a key wins) and marks the new
// nodes in `reader`; then, when --set frames=N shortens the run, drops the
// file's checkpoints beyond N.
void apply_overrides(toml::table& root, const std::vector<Override>& overrides, Reader& reader);

}  // namespace scenes::loader
