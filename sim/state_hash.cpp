#include "sim/state_hash.h"

#include <cstring>
#include <vector>

namespace sim {

namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

void mix(std::uint64_t& hash, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
        hash = (hash ^ p[i]) * kFnvPrime;
    }
}

}  // namespace

std::uint64_t state_hash(const ParticleState& state) {
    std::uint64_t hash = kFnvOffset;
    mix(hash, &state.t, sizeof state.t);
    const std::vector<double>& x = state.x.raw();
    const std::vector<double>& v = state.v.raw();
    mix(hash, x.data(), x.size() * sizeof(double));
    mix(hash, v.data(), v.size() * sizeof(double));
    return hash;
}

}  // namespace sim
