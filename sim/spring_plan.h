// The spring pass laid out for speed: a SpringPlan orders a spring list so
// that its forces load as vectors, and the planned pass gives the reference
// loop's bits (sim/spring.h, accumulate) faster on large systems. Kept apart
// so that spring.h reads as the lecture's formula.
#pragma once

#include "sim/spring.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sim {

// A spring list laid out for the fast force pass below. Pass 1 computes each
// spring's force in its own order: springs sorted by (j - i, i), so that a
// cloth's or a lattice's springs fall into runs where both particles advance
// by one per spring (their coordinates load as contiguous vectors, not one
// by one through indices), and a fan's (one particle, a hook, joined to a
// row of others) into runs where only j advances; springs outside a long run
// come last and are gathered through their indices. Pass 2 sums each
// particle's springs in list order (the reference loop's additions, so its
// bits); particles in a row with the same pattern (the same count of
// springs, the same signs, and each spring one further on in pass 1's order
// than the neighbour's) are summed side by side, as vectors. The plan copies
// k, c and rest: built once per generator (ParticleForces keeps one); the
// rest lengths of plastic springs are re-read on every pass. It checks only
// the list's length: build a new plan after changing any spring otherwise
// (nothing in sim/ does).
struct SpringPlan {
    // Which of spring_force's formulas a stretch of pass 1 needs: every
    // spring of rest length > 0 (k (|d| - ℓ) + damper, along d̂); any rest
    // length (each spring's own formula, chosen per spring); or every one of
    // rest length 0 without a damper (k d: no square root, no division).
    enum class Kind : std::uint8_t { stretch, mixed, linear };
    struct Run {
        std::uint32_t q = 0;      // first spring of the run, in pass 1's order
        std::uint32_t count = 0;  // springs q + t join particles i + t (i, a fan) and j + t, t < count
        std::uint32_t i = 0, j = 0;
        bool fan = false;
        Kind kind = Kind::stretch;
        // A fan of linear springs whose beads j + t have no other spring (a
        // swarm of particles each on a spring to one fixed point, the
        // report's batch of oscillators): pass 2 leaves the beads out, and
        // where the hub's own sum is not wanted (pinned, skip_pinned) pass 1
        // finishes each bead's sum as it computes its spring's force,
        // without the scratch g (the same operations: a block of degree 1).
        bool direct = false;
        // A direct fan whose springs all have the same stiffness (the same
        // bits; a fact of the list, set with the plan), and whose beads all
        // had the same inverse mass when last looked at (see masses below):
        // the pass reads each once, not once a bead.
        bool same_k = false;
        bool same_inv_mass = false;
    };
    struct Block {
        std::uint32_t p = 0;       // first particle of the block
        std::uint32_t count = 0;   // particles p .. p + count - 1
        std::uint32_t degree = 0;  // springs at each particle
        std::uint32_t ends = 0;    // end e of particle p + t is spring base[ends + e] + t, times sign[ends + e]
    };
    struct Bare {
        std::uint32_t p = 0, count = 0;  // particles p .. p + count - 1, without springs
    };
    std::size_t springs = 0;             // size of the list the plan was built for
    std::vector<std::uint32_t> order;    // (springs) list index of the spring at each place in pass 1's order
    std::vector<double> k, c, rest;      // (springs) their parameters in that order, N/m, N·s/m, m
    std::vector<Run> runs;               // springs [0, loose) of pass 1, in runs
    std::uint32_t loose = 0;             // springs [loose, springs) are gathered through li, lj
    std::vector<std::uint32_t> li, lj;   // (springs - loose) their particles
    Kind loose_kind = Kind::stretch;     // of springs [loose, springs)
    std::vector<Block> blocks;           // pass 2, particles summed side by side
    std::vector<std::uint32_t> base;     // (ends of the blocks) see Block
    std::vector<double> base_sign;       // (ends of the blocks) +1 or -1
    std::vector<Bare> bare;              // pass 2 adds nothing there (an acceleration is finished there too)
    std::vector<std::uint32_t> singles;  // pass 2, particles summed one at a time through first, spring, sign:
    std::vector<std::uint32_t> first;    // (particles + 1) particle p's ends are [first[p], first[p + 1])
    std::vector<std::uint32_t>
        spring;                // (2 x springs) the spring of each end (pass 1's order), list order at each particle
    std::vector<double> sign;  // (2 x springs) +1 at a spring's first particle, -1 at its second
    bool few = false;          // fewer springs than a run: the reference loop's (accumulate takes it)
    bool wide = false;         // the AVX2 build of the passes (the same bits), where the CPU has it
    std::uint64_t masses = 0;  // ForceInput::masses when the runs' same_inv_mass were read (0: never)
    std::vector<double> gx, gy, gz;  // (springs) scratch: force on each spring's first particle, N
};
SpringPlan plan_springs(const Springs& springs, std::size_t particle_count);

// The same bits as accumulate(springs, in, f), faster on large systems.
// Falls back to the reference loop for a few springs (plan.few), a plan
// that does not fit (a list of another length, a block of the system) and
// when a spring of rest length > 0 has zero length. Returns true when the
// fast pass ran.
//
// skip_pinned: leave the single (unblocked) pinned particles' sums out, their
// f as it came in. For an acceleration, where a pinned particle's is
// f · 0 anyway, so that every free particle keeps its bits. A NaN or an
// infinite spring force used to make the pinned end's acceleration NaN as
// well; skipped, it stays finite, but the free particle at the spring's
// other end carries the same non-finite force and the watchdog names it (a
// spring between two pinned particles moves nothing). Not for net forces
// (force arrows show pinned particles too).
//
// finish: what the pass leaves in f. A force (the default: f + the springs'
// force), or, as the last generator of an acceleration, a = M⁻¹ (f + the
// springs' force) with in.inv_mass, and, from_zero, f not set yet (a = M⁻¹
// (+0 + the springs' force): no generator before). The operations of a zero
// pass, this pass and a multiply by the inverse mass, per particle, so their
// bits; one pass over f instead of three. Every particle is finished, those
// without springs and the pinned ones skipped included; the fallbacks too.
struct SpringFinish {
    bool from_zero = false;        // f holds nothing yet: the sums start at +0
    bool to_acceleration = false;  // multiply each sum by in.inv_mass
};
bool accumulate(const Springs& springs, SpringPlan& plan, const ForceInput& in, const Vec3Span& f,
                bool skip_pinned = false, SpringFinish finish = {});

}  // namespace sim
