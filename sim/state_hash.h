// Fingerprints of exact bits: FNV-1a, 64 bits, the one hash the project uses
// (particle states, rigid bodies, and the two folded together). Two runs agree
// on a fingerprint only when they agree to the last bit: golden files keep one
// beside each checkpoint image.
#pragma once

#include "sim/particles.h"

#include <cstddef>
#include <cstdint>

namespace sim {

// FNV-1a over bytes in the order added (a double: its bytes in memory order).
class Fnv1a {
public:
    static constexpr std::uint64_t kOffset = 14695981039346656037ull;
    static constexpr std::uint64_t kPrime = 1099511628211ull;

    void add(const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i) hash_ = (hash_ ^ p[i]) * kPrime;
    }
    void add(double v) { add(&v, sizeof v); }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = kOffset;
};

// Two fingerprints folded into one (one FNV step over a 64-bit word), so that
// either changing changes the result.
constexpr std::uint64_t fold_hashes(std::uint64_t a, std::uint64_t b) { return (a ^ b) * Fnv1a::kPrime; }

// FNV-1a over t, then x and v (each as 3n doubles: all x, then all y, then
// all z; the padding between components is not hashed).
std::uint64_t state_hash(const ParticleState& state);

}  // namespace sim
