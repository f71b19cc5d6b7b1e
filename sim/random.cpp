#include "sim/random.h"

#include <cmath>
#include <numbers>

namespace sim {

namespace {

constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

std::uint64_t SplitMix64::next() {
    state_ += 0x9E3779B97F4A7C15ull;  // 2^64 / golden ratio, odd: a full-period Weyl sequence
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

Random::Random(std::uint64_t seed) {
    SplitMix64 expand(seed);
    for (auto& word : s_) {
        word = expand.next();
    }
}

std::uint64_t Random::next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
}

double Random::uniform() {
    constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;  // 2^-53
    return static_cast<double>(next_u64() >> 11) * kTwoToMinus53;
}

double Random::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

std::uint64_t Random::below(std::uint64_t n) {
    // Rejection (the OpenBSD arc4random_uniform method): drop the lowest
    // 2^64 mod n outputs, so the rest is a whole number of copies of [0, n).
    const std::uint64_t threshold = (0 - n) % n;  // 2^64 mod n, in 64-bit arithmetic
    for (;;) {
        const std::uint64_t x = next_u64();
        if (x >= threshold) {
            return x % n;
        }
    }
}

double Random::normal() {
    if (has_spare_) {
        has_spare_ = false;
        return spare_;
    }
    // Box-Muller: for u1 in (0, 1] and u2 in [0, 1), r = sqrt(-2 ln u1) and
    // theta = 2 pi u2 give two independent standard normals r cos, r sin.
    const double u1 = 1.0 - uniform();  // (0, 1]: ln never sees 0
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double theta = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(theta);
    has_spare_ = true;
    return r * std::cos(theta);
}

Vec3 Random::unit_vector() {
    for (;;) {
        const Vec3 g(normal(), normal(), normal());
        const double n = g.norm();
        if (n > 1e-12) {  // a zero draw has no direction; astronomically rare
            return g / n;
        }
    }
}

void Random::restore(const Snapshot& snap) {
    s_ = snap.s;
    has_spare_ = snap.has_spare;
    spare_ = snap.spare;
}

}  // namespace sim
