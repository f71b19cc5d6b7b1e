// Time integrators for particles: one function each, pure over state arrays
// and a force evaluation (Dynamics). Choosing one is a row of kIntegrators.
//
// Adding an integrator: write its step function in integrators.cpp, or a
// Runge-Kutta method's tableau in runge_kutta.cpp (its comment gives the
// update equations and the order), add its enumerator and
// one row to kIntegrators, and one row to the accuracy tests' table in
// tests/sim/integrators_accuracy_test.cpp.
#pragma once

#include "sim/dynamics.h"
#include "sim/vec3_array.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sim {

enum class Integrator : std::uint8_t {
    forward_euler,
    symplectic_euler,
    leapfrog,
    velocity_verlet,
    position_verlet,
    rk4,
    backward_euler,
};

// What an integrator carries from one step to the next (in StepArrays).
enum class Memory : std::uint8_t {
    none,
    acceleration,       // StepArrays::a, first-same-as-last methods
    two_accelerations,  // StepArrays::a and a_next (velocity Verlet)
    previous_position,  // StepArrays::x_prev, Störmer-Verlet
};

inline constexpr std::size_t kMaxScratch = 9;  // temporary arrays the hungriest method (RK4) needs

// The arrays one step works on: a block of particles [first, first + x.n).
// The world hands out the whole system, or, when every force is local,
// consecutive blocks small enough to stay in cache where the method makes
// several passes (same result, bit for bit; steps_in_one_pass).
struct StepArrays {
    std::size_t first = 0;  // global index of the block's first particle
    Vec3Span x;             // position, m: advanced in place
    Vec3Span v;             // velocity, m/s: advanced in place
    // Integrator memory, carried from one step to the next while the method
    // and h stay the same (memory_valid); otherwise rebuilt from (x, v).
    Vec3Span a;  // acceleration at (x, v), m/s² (Memory::acceleration and two_accelerations)
    // Memory::two_accelerations: an array where the method may leave the
    // step's new acceleration instead of writing it over `a` (velocity
    // Verlet's last kick reads the old and the new together: v is written
    // once a step, not twice); it then sets *a_next_taken, and the World
    // keeps a_next as `a` from there on (the two trade places: no copy).
    // Empty (arrays without it): the method writes over `a`.
    Vec3Span a_next;
    bool* a_next_taken = nullptr;
    Vec3Span x_prev;  // position one step back, m (Memory::previous_position only)
    bool memory_valid = false;
    Vec3Array* temporaries = nullptr;  // (the method's scratch_arrays) each of at least x.n points
    // Run the loops' AVX2 builds (sim/cpu.h: the same bits), on a block of
    // more than a few particles (wide_loops); only where the CPU has AVX2.
    bool wide = false;
    // No particle of the block is pinned (inverse mass 0): a method may leave
    // out what only a pinned particle needs (backward Euler's zero right-hand
    // side). False when unknown.
    bool none_pinned = false;
    // The watchdog's per-particle rules (sim/watchdog.h, passes), when the
    // World asks for them: a method's last pass over the block (the fused
    // pass of a uniform field, the Euler and Verlet methods' last loop, RK4's
    // few-particle step pass, backward Euler's diagonal solve) applies them
    // to each particle it leaves, adds the particles that fail to
    // watch->suspects and sets watch->counted, instead of the World's pass
    // over the block afterwards. Other paths leave it untouched, and the
    // World counts.
    struct Watch {
        double max_speed2 = 0.0;   // m²/s²
        double box = 0.0;          // m, the world box's half extent
        std::size_t suspects = 0;  // failed rules (0 exactly when every particle passes: the only use)
        bool counted = false;
    };
    Watch* watch = nullptr;
    // The force as a pair (Dynamics::pair_path), looked up once by the
    // caller for this block: a pair's step then makes no virtual call to
    // find it (on a bead on its spring the lookup was some 30 instructions
    // of about 430). nullptr: not looked up, the method asks the Dynamics.
    const PairPath* pair = nullptr;

    // Temporary k for this block, contents undefined.
    Vec3Span scratch(std::size_t k) const { return temporaries[k].span().block(0, x.n); }

    // A few particles go one at a time, at the pinned width (no vector loop
    // to set up: a one-particle step costs ~100 ns).
    static constexpr std::size_t kFewParticles = 16;
    // Whether this block's loops run their AVX2 builds.
    bool wide_loops() const { return wide && x.n > kFewParticles; }
};

// Advances the block from time t by one step h > 0.
using StepFn = void (*)(Dynamics& dynamics, const StepArrays& s, double t, double h);

struct IntegratorInfo {
    Integrator id;
    std::string_view name;       // as scene files and the command spell it
    int order;                   // global order of convergence in position
    int force_evaluations;       // per step, once memory is valid
    std::size_t scratch_arrays;  // temporaries it needs (<= kMaxScratch)
    Memory memory;               // state it keeps between steps (allocated only for it)
    bool needs_jacobians;        // implicit: solves a linear system each step
    std::string_view summary;    // one line for `plausible list` and reports
    StepFn step;
};

void forward_euler(Dynamics& dynamics, const StepArrays& s, double t, double h);
void symplectic_euler(Dynamics& dynamics, const StepArrays& s, double t, double h);
void leapfrog(Dynamics& dynamics, const StepArrays& s, double t, double h);
void velocity_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h);
void position_verlet(Dynamics& dynamics, const StepArrays& s, double t, double h);
void rk4(Dynamics& dynamics, const StepArrays& s, double t, double h);
void backward_euler(Dynamics& dynamics, const StepArrays& s, double t, double h);

// Whether `method` steps particles whose whole force is `field` in one pass
// over them: every explicit method (the fused pass, sim/fused_pass.h) and
// backward Euler where its system is diagonal (gravity and at most one
// linear drag). The World then steps the system as one block: blocks only
// pay off where a step makes several passes (RK4's stages on any other
// force), and on 10⁶ particles their dispatch cost leapfrog and velocity
// Verlet about a tenth of their one pass.
bool steps_in_one_pass(Integrator method, const UniformField& field);

inline constexpr std::array<IntegratorInfo, 7> kIntegrators{{
    {Integrator::forward_euler, "forward_euler", 1, 1, 1, Memory::none, false,
     "explicit Euler: x += h v, v += h a; gains energy on oscillators", &forward_euler},
    {Integrator::symplectic_euler, "symplectic_euler", 1, 1, 1, Memory::none, false,
     "semi-implicit Euler: v += h a, then x += h v; symplectic, the games default", &symplectic_euler},
    {Integrator::leapfrog, "leapfrog", 2, 1, 0, Memory::acceleration, false,
     "kick-drift-kick with half-step velocities; symplectic", &leapfrog},
    {Integrator::velocity_verlet, "velocity_verlet", 2, 1, 1, Memory::two_accelerations, false,
     "velocity Verlet: x += h v + h²a/2, v += h (a + a')/2; symplectic", &velocity_verlet},
    {Integrator::position_verlet, "position_verlet", 2, 1, 1, Memory::previous_position, false,
     "Störmer-Verlet: x' = 2x - x_prev + h²a, velocity from positions; symplectic", &position_verlet},
    {Integrator::rk4, "rk4", 4, 4, 9, Memory::none, false, "classic fourth-order Runge-Kutta; the accuracy reference",
     &rk4},
    {Integrator::backward_euler, "backward_euler", 1, 1, 1, Memory::none, true,
     "implicit Euler, one Newton step on the linearised forces; stable for stiff springs, loses energy",
     &backward_euler},
}};

// What backward Euler's sparse LDLᵀ costs a step on n particles linked by
// `links` (their springs: each an off-diagonal 3 x 3 block of the system),
// flops: Eigen's own symbolic analysis of that pattern (the AMD ordering the
// solver uses, then the column counts of L: Σ count² flops on the n x n
// pattern, x 27 for the 3 x 3 blocks). Exact in what it counts, machine-
// independent, and far cheaper than the factorization (no numbers: a
// 1000 x 1000 cloth's pattern analyses in about a second). The loader
// refuses a scene whose frames would take hours this way.
double backward_euler_factor_flops(std::size_t n, const std::vector<std::array<std::uint32_t, 2>>& links);

// The table is in enumerator order, so a look-up is an index.
constexpr bool integrators_in_order() {
    for (std::size_t k = 0; k < kIntegrators.size(); ++k) {
        if (static_cast<std::size_t>(kIntegrators[k].id) != k) return false;
    }
    return true;
}
static_assert(integrators_in_order(), "kIntegrators rows must follow the order of enum Integrator");
inline const IntegratorInfo& integrator_info(Integrator id) { return kIntegrators.at(static_cast<std::size_t>(id)); }
std::optional<Integrator> integrator_from_name(std::string_view name);
// "forward_euler, symplectic_euler, ..." for messages.
std::string integrator_names();

}  // namespace sim
