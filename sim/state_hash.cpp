#include "sim/state_hash.h"

#include <vector>

namespace sim {

std::uint64_t state_hash(const ParticleState& state) {
    Fnv1a hash;
    hash.add(state.t);
    // x's components one after the other, then v's: the bytes of 3n doubles
    // each, as when they lay end to end in memory.
    for (const ConstVec3Span a : {state.x.span(), state.v.span()}) {
        for (const double* c : a.c) hash.add(c, a.n * sizeof(double));
    }
    return hash.value();
}

}  // namespace sim
