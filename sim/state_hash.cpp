#include "sim/state_hash.h"

#include <vector>

namespace sim {

std::uint64_t state_hash(const ParticleState& state) {
    Fnv1a hash;
    hash.add(state.t);
    const std::vector<double>& x = state.x.raw();
    const std::vector<double>& v = state.v.raw();
    hash.add(x.data(), x.size() * sizeof(double));
    hash.add(v.data(), v.size() * sizeof(double));
    return hash.value();
}

}  // namespace sim
