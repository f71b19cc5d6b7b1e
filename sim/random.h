// The project's one random number generator: deterministic on every platform
// and compiler, because it is ours. The C library's generator and the
// standard library's engines and distributions are not used anywhere (a ctest
// greps for them): their sequences differ between implementations, and
// the same scene must give the same bits everywhere (docs/design.md rule 5).
//
// Generator: xoshiro256** (Blackman and Vigna, 2018), a 256-bit state with a
// period of 2^256 - 1, seeded by expanding a 64-bit seed with SplitMix64 (the
// seeding the authors recommend: it never yields the all-zero state).
// Distributions are written out here (uniform from the top 53 bits; normal by
// Box-Muller; unit vectors by normalising three normals), so each draw
// consumes a fixed number of 64-bit outputs.
#pragma once

#include "sim/vec3_array.h"

#include <array>
#include <cstdint>

namespace sim {

// SplitMix64 (Steele, Lea and Flood, 2014): one 64-bit word of state, a
// Weyl sequence mixed by two multiply-xorshift rounds.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next();

private:
    std::uint64_t state_;
};

class Random {
public:
    explicit Random(std::uint64_t seed = 0);

    std::uint64_t next_u64();  // uniform over all 2^64 values
    // Uniform in [0, 1): the top 53 bits times 2^-53, so every value is a
    // multiple of 2^-53 and 1 is never returned.
    double uniform();
    double uniform(double lo, double hi);  // uniform in [lo, hi)
    // Uniform integer in [0, n) for n >= 1, unbiased (rejection).
    std::uint64_t below(std::uint64_t n);
    // Standard normal (mean 0, variance 1) by the Box-Muller transform; the
    // second value of each pair is kept for the next call.
    double normal();
    double normal(double mean, double sigma) { return mean + sigma * normal(); }
    // A direction uniform over the unit sphere: three normals, normalised
    // (the Gaussian is rotationally symmetric).
    Vec3 unit_vector();

    // The generator's whole state, for save/restore (rewind, replay).
    struct Snapshot {
        std::array<std::uint64_t, 4> s{};
        bool has_spare = false;
        double spare = 0.0;
    };
    Snapshot snapshot() const { return {s_, has_spare_, spare_}; }
    void restore(const Snapshot& snap);

private:
    std::array<std::uint64_t, 4> s_{};
    bool has_spare_ = false;
    double spare_ = 0.0;
};

}  // namespace sim
