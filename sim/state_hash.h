// A 64-bit fingerprint of a particle state's exact bits (FNV-1a over t, x and
// v). Two runs agree on it only when they agree to the last bit: golden files
// keep it beside each checkpoint image.
#pragma once

#include "sim/particles.h"

#include <cstdint>

namespace sim {

std::uint64_t state_hash(const ParticleState& state);

}  // namespace sim
