// The planned spring pass (sim/spring_plan.h): the plan (pass 1's order of
// springs in runs and fans, pass 2's blocks of particles) and its kernels,
// built for SSE and, chosen at run time, AVX2, with the reference loop's bits.
#include "sim/spring_plan.h"

#include "sim/cpu.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <utility>

namespace sim {

namespace {

// Shorter runs of springs, and of particles with one pattern, cost more in
// per-run overhead than their contiguous loads save: they go the gathered way.
constexpr std::uint32_t kMinRun = 8;

// Each particle's ends in list order (the order the reference loop adds them
// in), as places in pass 1's order.
void plan_ends(const Springs& springs, const std::vector<std::uint32_t>& place, std::size_t particle_count,
               SpringPlan& plan) {
    const std::size_t m = springs.list.size();
    plan.first.assign(particle_count + 1, 0);
    for (const Spring& s : springs.list) {
        ++plan.first[s.i + 1];
        ++plan.first[s.j + 1];
    }
    for (std::size_t p = 0; p < particle_count; ++p) plan.first[p + 1] += plan.first[p];
    plan.spring.resize(2 * m);
    plan.sign.resize(2 * m);
    std::vector<std::uint32_t> next(plan.first.begin(), plan.first.end() - 1);
    for (std::size_t s = 0; s < m; ++s) {
        const std::uint32_t a = next[springs.list[s].i]++, b = next[springs.list[s].j]++;
        plan.spring[a] = plan.spring[b] = place[s];
        plan.sign[a] = 1.0;
        plan.sign[b] = -1.0;
    }
}

// Particles p and p + d (d > 0) have the same pattern of ends, shifted by d.
bool same_pattern(const SpringPlan& plan, std::uint32_t p, std::uint32_t d) {
    const std::uint32_t a = plan.first[p], b = plan.first[p + d];
    const std::uint32_t degree = plan.first[p + 1] - a;
    if (plan.first[p + d + 1] - b != degree) return false;
    for (std::uint32_t e = 0; e < degree; ++e) {
        if (plan.sign[a + e] != plan.sign[b + e] || plan.spring[b + e] != plan.spring[a + e] + d) return false;
    }
    return true;
}

// The formula springs [a, b) of pass 1 need (see SpringPlan::Kind).
SpringPlan::Kind kind_of(const SpringPlan& plan, std::size_t a, std::size_t b) {
    bool stretch = true, linear = true;
    for (std::size_t q = a; q < b; ++q) {
        stretch = stretch && plan.rest[q] != 0.0;
        linear = linear && plan.rest[q] == 0.0 && plan.c[q] == 0.0;
    }
    return stretch ? SpringPlan::Kind::stretch : linear ? SpringPlan::Kind::linear : SpringPlan::Kind::mixed;
}

// `list`, stably sorted by key(spring).
template <class Key>
std::vector<std::uint32_t> sorted_by(const Springs& springs, std::vector<std::uint32_t> list, Key key) {
    std::stable_sort(list.begin(), list.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key(springs.list[a]) < key(springs.list[b]); });
    return list;
}

// Cuts `sorted` into stretches where each spring follows the one before (j
// one further on, and i one further on too or, in a fan, the same): those
// of kMinRun springs or more become pass 1's next runs, the others go to
// `left`.
void cut_runs(const Springs& springs, const std::vector<std::uint32_t>& sorted, bool fan, SpringPlan& plan,
              std::vector<std::uint32_t>& left) {
    auto follows = [&](std::size_t b) {
        const Spring &s = springs.list[sorted[b]], &before = springs.list[sorted[b - 1]];
        return s.i == before.i + (fan ? 0 : 1) && s.j == before.j + 1;
    };
    for (std::size_t a = 0; a < sorted.size();) {
        std::size_t b = a + 1;
        while (b < sorted.size() && follows(b)) ++b;
        if (b - a >= kMinRun) {
            const Spring& s = springs.list[sorted[a]];
            plan.runs.push_back(
                {static_cast<std::uint32_t>(plan.order.size()), static_cast<std::uint32_t>(b - a), s.i, s.j, fan});
            plan.order.insert(plan.order.end(), sorted.begin() + a, sorted.begin() + b);
        } else {
            left.insert(left.end(), sorted.begin() + a, sorted.begin() + b);
        }
        a = b;
    }
}

}  // namespace

SpringPlan plan_springs(const Springs& springs, std::size_t particle_count) {
    SpringPlan plan;
    const std::size_t m = springs.list.size();
    for (const Spring& s : springs.list) {
        if (s.i >= particle_count || s.j >= particle_count) return {};  // not for this system
    }
    plan.springs = m;
    // A few springs go the reference loop's way: the passes' setup would
    // cost more than they save (a tenth of a one-spring step, measured).
    plan.few = m < kMinRun;
    plan.wide = avx2_available();

    // Pass 1's order: fans first (by (i, j), cut where i changes or j skips),
    // then the other springs by (j - i, i), cut into runs where i and j both
    // advance by one; springs of short runs go to the end. (Springs with the
    // same key keep their list order through both stable sorts.)
    std::vector<std::uint32_t> all(m), rest, loose;
    for (std::uint32_t s = 0; s < m; ++s) all[s] = s;
    cut_runs(springs, sorted_by(springs, all, [](const Spring& s) { return std::pair(s.i, s.j); }), true, plan, rest);
    auto distance = [](const Spring& s) {
        return std::pair<std::int64_t, std::uint32_t>(std::int64_t{s.j} - std::int64_t{s.i}, s.i);
    };
    cut_runs(springs, sorted_by(springs, rest, distance), false, plan, loose);
    plan.loose = static_cast<std::uint32_t>(plan.order.size());
    plan.order.insert(plan.order.end(), loose.begin(), loose.end());
    std::vector<std::uint32_t> place(m);
    for (std::uint32_t q = 0; q < m; ++q) place[plan.order[q]] = q;
    for (const std::uint32_t s : plan.order) {
        plan.k.push_back(springs.list[s].k);
        plan.c.push_back(springs.list[s].c);
        plan.rest.push_back(springs.list[s].rest);
    }
    for (const std::uint32_t s : loose) {
        plan.li.push_back(springs.list[s].i);
        plan.lj.push_back(springs.list[s].j);
    }
    for (SpringPlan::Run& r : plan.runs) r.kind = kind_of(plan, r.q, r.q + r.count);
    plan.loose_kind = kind_of(plan, plan.loose, m);

    // Pass 2: blocks of particles with one pattern, the rest one by one.
    plan_ends(springs, place, particle_count, plan);
    std::vector<bool> bead(particle_count, false);  // in a direct fan (see Run::direct): not in pass 2
    auto alone = [&](std::uint32_t p) { return plan.first[p + 1] - plan.first[p] == 1; };  // one spring
    for (SpringPlan::Run& r : plan.runs) {
        r.direct = r.fan && r.kind == SpringPlan::Kind::linear;
        for (std::uint32_t t = 0; t < r.count && r.direct; ++t) r.direct = alone(r.j + t);
        for (std::uint32_t t = 0; t < r.count && r.direct; ++t) bead[r.j + t] = true;
        const auto k0 = std::bit_cast<std::uint64_t>(plan.k[r.q]);
        r.same_k = r.direct && std::all_of(plan.k.begin() + r.q, plan.k.begin() + r.q + r.count,
                                           [k0](double k) { return std::bit_cast<std::uint64_t>(k) == k0; });
    }
    for (std::uint32_t p = 0; p < particle_count;) {
        if (bead[p]) {
            ++p;
            continue;
        }
        std::uint32_t count = 1;
        while (p + count < particle_count && !bead[p + count] && same_pattern(plan, p, count)) ++count;
        const std::uint32_t degree = plan.first[p + 1] - plan.first[p];
        if (degree > 0 && count >= kMinRun) {
            plan.blocks.push_back({p, count, degree, static_cast<std::uint32_t>(plan.base.size())});
            for (std::uint32_t e = plan.first[p]; e < plan.first[p + 1]; ++e) {
                plan.base.push_back(plan.spring[e]);
                plan.base_sign.push_back(plan.sign[e]);
            }
        } else if (degree > 0) {
            for (std::uint32_t r = p; r < p + count; ++r) plan.singles.push_back(r);
        } else if (!plan.bare.empty() && plan.bare.back().p + plan.bare.back().count == p) {
            plan.bare.back().count += count;
        } else {
            plan.bare.push_back({p, count});
        }
        p += count;
    }
    plan.gx.resize(m);
    plan.gy.resize(m);
    plan.gz.resize(m);
    return plan;
}

namespace {

// The kernels of the fast pass, each compiled twice: for the pinned
// instruction set (x86-64-v2, SSE: two doubles a register) and, called only
// where the CPU has it, for AVX2 (four). Square roots, divisions, products
// and sums are correctly rounded at any width, and -ffp-contract=off forbids
// fusing a multiply-add (AVX2 machines have FMA): both builds give the
// reference loop's bits (tests/sim/forces_test.cpp runs both). Plain
// pointers only (through a struct GCC gives up vectorising).
//
// yes ? a : b, as bits: a select the vectoriser takes. (With ?: GCC moves
// the arithmetic that only one side uses into a branch, since it may trap
// under -ftrapping-math, and then gives up on the loop's control flow.)
[[gnu::always_inline]] inline double pick(bool yes, double a, double b) {
    const std::uint64_t mask = std::uint64_t{0} - static_cast<std::uint64_t>(yes);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) | (std::bit_cast<std::uint64_t>(b) & ~mask));
}

// How pass 1 finds a spring's particles: a run (i0 + t, j0 + t), a fan (i0,
// j0 + t), both loaded as contiguous vectors (i0 of a fan once), or loose
// (si[t], sj[t]), gathered through the indices.
enum class Path { run, fan, loose };

// Pass 1: the force on each spring's first particle, spring_force's
// operations in its order, for `count` springs whose parameters and outputs
// are contiguous. Returns the number of springs of rest length > 0 and
// length 0 (a count: a bool here stops the vectoriser). By kKind:
//   stretch: d = x_j - x_i,  n = d / |d|,  g = (k (|d| - ℓ) + c (v_j - v_i) · n) n;
//   linear:  g = k d (rest length 0, no damper: spring_force's other branch,
//            no length needed);
//   mixed:   a spring of rest length 0 gets k d, plus c ((v_j - v_i) · n) n
//            where c != 0 and |d| > 0, the others the stretch formula. Every
//            lane computes both and keeps the one its spring takes (selects,
//            no branch, so the loop stays vectorised); the value kept was
//            computed with the reference loop's operations in its order, so
//            it has its bits. A rest-0 spring of length 0 is no fallback:
//            k d needs no direction.
template <Path kPath, SpringPlan::Kind kKind>
[[gnu::always_inline]] inline std::size_t spring_forces(
    std::size_t count, std::size_t i0, std::size_t j0, const std::uint32_t* __restrict si,
    const std::uint32_t* __restrict sj, const double* __restrict k, const double* __restrict c,
    const double* __restrict rest, const double* __restrict x, const double* __restrict y, const double* __restrict z,
    const double* __restrict vx, const double* __restrict vy, const double* __restrict vz, double* __restrict gx,
    double* __restrict gy, double* __restrict gz) {
    using Kind = SpringPlan::Kind;
    std::size_t zero_length = 0;
    for (std::size_t t = 0; t < count; ++t) {
        const std::size_t i = kPath == Path::run ? i0 + t : kPath == Path::fan ? i0 : si[t];
        const std::size_t j = kPath == Path::loose ? sj[t] : j0 + t;
        const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
        if constexpr (kKind == Kind::linear) {
            gx[t] = k[t] * dx, gy[t] = k[t] * dy, gz[t] = k[t] * dz;
            continue;
        }
        const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double nx = dx / length, ny = dy / length, nz = dz / length;
        const double damp = c[t] * ((vx[j] - vx[i]) * nx + (vy[j] - vy[i]) * ny + (vz[j] - vz[i]) * nz);
        const double magnitude = k[t] * (length - rest[t]) + damp;
        double ax = magnitude * nx, ay = magnitude * ny, az = magnitude * nz;
        if constexpr (kKind == Kind::mixed) {
            const bool linear = rest[t] == 0.0;
            const bool damped = (c[t] != 0.0) & (length > 0.0);
            const double lx = k[t] * dx, ly = k[t] * dy, lz = k[t] * dz;
            const double dlx = lx + damp * nx, dly = ly + damp * ny, dlz = lz + damp * nz;
            const double zx = pick(damped, dlx, lx), zy = pick(damped, dly, ly), zz = pick(damped, dlz, lz);
            ax = pick(linear, zx, ax), ay = pick(linear, zy, ay), az = pick(linear, zz, az);
            zero_length += static_cast<std::size_t>((length == 0.0) & !linear);
        } else {
            zero_length += length == 0.0;
        }
        gx[t] = ax, gy[t] = ay, gz[t] = az;
    }
    return zero_length;
}

// Pass 2 over a block, one coordinate: particle t's sum f[t] + s_0 g[base_0 + t]
// + s_1 g[base_1 + t] + ..., left to right (the reference loop's order; s = ±1
// is exact and f + (-g) is f - g). Eight particles side by side, their sums
// held in registers while the ends go by. kFromZero: the sums start at +0,
// not f (which holds nothing yet); kScale: each is stored times inv_m[t] (an
// acceleration): the zero pass's, this pass's and M⁻¹'s operations, one pass.
template <bool kFromZero, bool kScale>
[[gnu::always_inline]] inline void block_sums(std::size_t count, std::size_t degree,
                                              const std::uint32_t* __restrict base, const double* __restrict sign,
                                              const double* __restrict g, const double* __restrict inv_m,
                                              double* __restrict f) {
    constexpr std::size_t kLanes = 8;
    std::size_t t = 0;
    for (; t + kLanes <= count; t += kLanes) {
        double sum[kLanes];
        for (std::size_t l = 0; l < kLanes; ++l) sum[l] = kFromZero ? 0.0 : f[t + l];
        for (std::size_t e = 0; e < degree; ++e) {
            const double* __restrict ge = g + base[e] + t;
            const double s = sign[e];
            for (std::size_t l = 0; l < kLanes; ++l) sum[l] += s * ge[l];
        }
        for (std::size_t l = 0; l < kLanes; ++l) f[t + l] = kScale ? sum[l] * inv_m[t + l] : sum[l];
    }
    for (; t < count; ++t) {
        double sum = kFromZero ? 0.0 : f[t];
        for (std::size_t e = 0; e < degree; ++e) sum += sign[e] * g[base[e] + t];
        f[t] = kScale ? sum * inv_m[t] : sum;
    }
}

// A direct fan (SpringPlan::Run::direct) whose hub's sum is left out: each
// bead's spring force g = k (x_j - x_hub) (spring_forces' linear kind) and
// at once its sum, (f or +0) + (-1) g, times inv_m where kScale (block_sums'
// operations on a block of degree 1). Linear springs need no direction: no
// length of 0 to fall back on, so this may write f before the pass is sure
// to finish. kShared: every spring's k is k[0] and every bead's inverse mass
// inv_m[j0] (Run::same_k, same_inv_mass), each read once: two streams fewer
// in a loop bound by its streams, the same values so the same bits.
template <bool kShared, bool kFromZero, bool kScale>
[[gnu::always_inline]] inline void direct_fan(std::size_t count, std::size_t hub, std::size_t j0,
                                              const double* __restrict k, const double* __restrict x,
                                              const double* __restrict y, const double* __restrict z,
                                              const double* __restrict inv_m, double* __restrict fx,
                                              double* __restrict fy, double* __restrict fz) {
    const double hx = x[hub], hy = y[hub], hz = z[hub];
    for (std::size_t t = 0; t < count; ++t) {
        const std::size_t j = j0 + t;
        const double kt = kShared ? k[0] : k[t], w = kShared ? inv_m[j0] : inv_m[j];
        const double gx = kt * (x[j] - hx), gy = kt * (y[j] - hy), gz = kt * (z[j] - hz);
        const double sx = (kFromZero ? 0.0 : fx[j]) + -1.0 * gx, sy = (kFromZero ? 0.0 : fy[j]) + -1.0 * gy,
                     sz = (kFromZero ? 0.0 : fz[j]) + -1.0 * gz;
        fx[j] = kScale ? sx * w : sx, fy[j] = kScale ? sy * w : sy, fz[j] = kScale ? sz * w : sz;
    }
}

// Particles [0, count) whose sums pass 2 leaves out (no springs, or pinned
// and skipped), finished as block_sums would with no ends.
template <bool kFromZero, bool kScale>
[[gnu::always_inline]] inline void finish_unsummed(std::size_t count, const double* __restrict inv_m,
                                                   double* __restrict f) {
    for (std::size_t t = 0; t < count; ++t) {
        const double sum = kFromZero ? 0.0 : f[t];
        f[t] = kScale ? sum * inv_m[t] : sum;
    }
}

// The kernels of one instruction set; pass 1's by path and kind, pass 2's
// by finish (a direct fan's also by whether its k and inverse mass are shared).
struct SpringKernels {
    using Forces = std::size_t (*)(std::size_t, std::size_t, std::size_t, const std::uint32_t*, const std::uint32_t*,
                                   const double*, const double*, const double*, const double*, const double*,
                                   const double*, const double*, const double*, const double*, double*, double*,
                                   double*);  // spring_forces<kPath, kKind>
    using Block = void (*)(std::size_t, std::size_t, const std::uint32_t*, const double*, const double*, const double*,
                           double*);                                 // block_sums<kFromZero, kScale>
    using Unsummed = void (*)(std::size_t, const double*, double*);  // finish_unsummed<kFromZero, kScale>
    using Direct = void (*)(std::size_t, std::size_t, std::size_t, const double*, const double*, const double*,
                            const double*, const double*, double*, double*,
                            double*);  // direct_fan<kShared, kFromZero, kScale>
    Forces forces[3][3];               // [Path][SpringPlan::Kind]
    Block blocks[2][2];                // [kFromZero][kScale]
    Unsummed unsummed[2][2];           // [kFromZero][kScale]
    Direct direct[2][2][2];            // [kShared][kFromZero][kScale]

    Forces pass1(Path path, SpringPlan::Kind kind) const {
        return forces[static_cast<int>(path)][static_cast<int>(kind)];
    }
    Block block(SpringFinish finish) const { return blocks[finish.from_zero][finish.to_acceleration]; }
    Unsummed finish(SpringFinish finish) const { return unsummed[finish.from_zero][finish.to_acceleration]; }
    Direct fan(bool shared, SpringFinish finish) const {
        return direct[shared][finish.from_zero][finish.to_acceleration];
    }
};

// Every kernel of one instruction set, in SpringKernels' order:
// F<kPath, kKind>::call, B and U<kFromZero, kScale>::call (block_sums,
// finish_unsummed) and D<kShared, kFromZero, kScale>::call (direct_fan) are
// that set's instantiations.
template <template <Path, SpringPlan::Kind> class F, template <bool, bool> class B, template <bool, bool> class U,
          template <bool, bool, bool> class D>
constexpr SpringKernels kernels_of() {
    using K = SpringPlan::Kind;
    return {{{&F<Path::run, K::stretch>::call, &F<Path::run, K::mixed>::call, &F<Path::run, K::linear>::call},
             {&F<Path::fan, K::stretch>::call, &F<Path::fan, K::mixed>::call, &F<Path::fan, K::linear>::call},
             {&F<Path::loose, K::stretch>::call, &F<Path::loose, K::mixed>::call, &F<Path::loose, K::linear>::call}},
            {{&B<false, false>::call, &B<false, true>::call}, {&B<true, false>::call, &B<true, true>::call}},
            {{&U<false, false>::call, &U<false, true>::call}, {&U<true, false>::call, &U<true, true>::call}},
            {{{&D<false, false, false>::call, &D<false, false, true>::call},
              {&D<false, true, false>::call, &D<false, true, true>::call}},
             {{&D<true, false, false>::call, &D<true, false, true>::call},
              {&D<true, true, false>::call, &D<true, true, true>::call}}}};
}

template <Path kPath, SpringPlan::Kind kKind>
struct ForcesBase {
    template <typename... A>
    static std::size_t call(A... a) {
        return spring_forces<kPath, kKind>(a...);
    }
};
template <bool kFromZero, bool kScale>
struct BlockBase {
    template <typename... A>
    static void call(A... a) {
        block_sums<kFromZero, kScale>(a...);
    }
};
template <bool kFromZero, bool kScale>
struct UnsummedBase {
    template <typename... A>
    static void call(A... a) {
        finish_unsummed<kFromZero, kScale>(a...);
    }
};
template <bool kShared, bool kFromZero, bool kScale>
struct DirectBase {
    template <typename... A>
    static void call(A... a) {
        direct_fan<kShared, kFromZero, kScale>(a...);
    }
};
constexpr SpringKernels kBaseKernels = kernels_of<ForcesBase, BlockBase, UnsummedBase, DirectBase>();

#if defined(__x86_64__) && defined(__GNUC__)
template <Path kPath, SpringPlan::Kind kKind>
struct ForcesAvx2 {
    template <typename... A>
    [[gnu::target("avx2")]] static std::size_t call(A... a) {
        return spring_forces<kPath, kKind>(a...);
    }
};
template <bool kFromZero, bool kScale>
struct BlockAvx2 {
    template <typename... A>
    [[gnu::target("avx2")]] static void call(A... a) {
        block_sums<kFromZero, kScale>(a...);
    }
};
template <bool kFromZero, bool kScale>
struct UnsummedAvx2 {
    template <typename... A>
    [[gnu::target("avx2")]] static void call(A... a) {
        finish_unsummed<kFromZero, kScale>(a...);
    }
};
template <bool kShared, bool kFromZero, bool kScale>
struct DirectAvx2 {
    template <typename... A>
    [[gnu::target("avx2")]] static void call(A... a) {
        direct_fan<kShared, kFromZero, kScale>(a...);
    }
};
constexpr SpringKernels kWideKernels = kernels_of<ForcesAvx2, BlockAvx2, UnsummedAvx2, DirectAvx2>();
#else
constexpr SpringKernels kWideKernels = kBaseKernels;
#endif

// The reference loop with `finish` (accumulate's fallbacks): the zero pass,
// the loop, the multiply by the inverse mass, one after another (the zero
// and the multiply are finish_unsummed's: +0, and f · (1/m)).
void reference_pass(const Springs& springs, const SpringKernels& kernels, const ForceInput& in, const Vec3Span& f,
                    SpringFinish finish) {
    if (finish.from_zero) {
        for (int axis = 0; axis < 3; ++axis) kernels.finish({.from_zero = true})(f.n, in.inv_mass, f.c[axis]);
    }
    accumulate(springs, in, f);
    if (finish.to_acceleration) {
        for (int axis = 0; axis < 3; ++axis) kernels.finish({.to_acceleration = true})(f.n, in.inv_mass, f.c[axis]);
    }
}

// Each direct fan's same_inv_mass, read again where in.masses is not the
// stamp they were read at (none, where it is 0: it promises nothing).
void read_bead_masses(SpringPlan& plan, const ForceInput& in) {
    if (in.masses == plan.masses) return;
    for (SpringPlan::Run& r : plan.runs) {
        r.same_inv_mass = false;
        if (!r.direct || in.masses == 0) continue;
        const double* w = in.inv_mass + r.j;
        const auto w0 = std::bit_cast<std::uint64_t>(w[0]);
        r.same_inv_mass = std::all_of(w, w + r.count, [w0](double b) { return std::bit_cast<std::uint64_t>(b) == w0; });
    }
    plan.masses = in.masses;
}

// The fast pass itself (accumulate's, below: out of line, so that the few
// springs that go the reference loop's way do not pay for its registers).
[[gnu::noinline]] bool planned_pass(const Springs& springs, SpringPlan& plan, const ForceInput& in, const Vec3Span& f,
                                    bool skip_pinned, SpringFinish finish) {
    const std::size_t m = springs.list.size();
    // Plastic rest lengths are re-read. (One stays >= rest0 (1 - max_strain)
    // > 0, and one of 0 never creeps, so the kinds hold; the upgrade of a
    // stretch to mixed is a guard.)
    bool zero_rest = false;
    if (springs.plasticity.enabled()) {
        for (std::size_t q = 0; q < m; ++q) {
            plan.rest[q] = springs.list[plan.order[q]].rest;
            zero_rest = zero_rest || plan.rest[q] == 0.0;
        }
    }
    auto kind = [zero_rest](SpringPlan::Kind k) {
        return zero_rest && k == SpringPlan::Kind::stretch ? SpringPlan::Kind::mixed : k;
    };
    const SpringKernels& kernels = plan.wide ? kWideKernels : kBaseKernels;
    const double *x = in.x.c[0], *y = in.x.c[1], *z = in.x.c[2];
    const double *vx = in.v.c[0], *vy = in.v.c[1], *vz = in.v.c[2];
    double *gx = plan.gx.data(), *gy = plan.gy.data(), *gz = plan.gz.data();
    std::size_t zero_length = 0;
    // A direct fan's hub left out: its beads are finished below, without g.
    auto straight = [&](const SpringPlan::Run& r) { return r.direct && skip_pinned && in.inv_mass[r.i] == 0.0; };
    for (const SpringPlan::Run& r : plan.runs) {
        if (straight(r)) continue;
        zero_length += kernels.pass1(r.fan ? Path::fan : Path::run, kind(r.kind))(
            r.count, r.i, r.j, nullptr, nullptr, &plan.k[r.q], &plan.c[r.q], &plan.rest[r.q], x, y, z, vx, vy, vz,
            gx + r.q, gy + r.q, gz + r.q);
    }
    const std::size_t q = plan.loose;
    zero_length += kernels.pass1(Path::loose, kind(plan.loose_kind))(
        m - q, 0, 0, plan.li.data(), plan.lj.data(), plan.k.data() + q, plan.c.data() + q, plan.rest.data() + q, x, y,
        z, vx, vy, vz, gx + q, gy + q, gz + q);
    // Two particles on top of each other, on a spring of rest length > 0: no
    // direction, a force the reference loop leaves out (0 / 0 above). Rare
    // enough to redo the pass its way.
    if (zero_length > 0) {
        reference_pass(springs, kernels, in, f, finish);
        return false;
    }
    const double* g[3] = {gx, gy, gz};
    const SpringKernels::Block block = kernels.block(finish);
    for (const SpringPlan::Block& b : plan.blocks) {
        for (int axis = 0; axis < 3; ++axis) {
            block(b.count, b.degree, &plan.base[b.ends], &plan.base_sign[b.ends], g[axis], in.inv_mass + b.p,
                  f.c[axis] + b.p);
        }
    }
    // The direct fans' beads: a block of degree 1 each, on g, or straight
    // from the positions.
    constexpr double kBeadSign = -1.0;  // each bead is its spring's second particle
    read_bead_masses(plan, in);
    for (const SpringPlan::Run& r : plan.runs) {
        if (straight(r)) {
            const bool shared = r.same_k && (r.same_inv_mass || !finish.to_acceleration);
            kernels.fan(shared, finish)(r.count, r.i, r.j, &plan.k[r.q], x, y, z, in.inv_mass, f.c[0], f.c[1], f.c[2]);
        } else if (r.direct) {
            for (int axis = 0; axis < 3; ++axis) {
                block(r.count, 1, &r.q, &kBeadSign, g[axis], in.inv_mass + r.j, f.c[axis] + r.j);
            }
        }
    }
    const bool finished = finish.from_zero || finish.to_acceleration;  // else f is left as it came where nothing adds
    const SpringKernels::Unsummed unsummed = kernels.finish(finish);
    for (const std::uint32_t p : plan.singles) {
        // A pinned anchor shared by many springs (a thousand beads on one
        // hook) is one long chain of dependent additions: most of the pass,
        // for a force that moves nothing. See the declaration for why
        // leaving it out is safe.
        if (skip_pinned && in.inv_mass[p] == 0.0) {
            if (finished) {
                for (int axis = 0; axis < 3; ++axis) unsummed(1, in.inv_mass + p, f.c[axis] + p);
            }
            continue;
        }
        double ax = finish.from_zero ? 0.0 : f.c[0][p], ay = finish.from_zero ? 0.0 : f.c[1][p],
               az = finish.from_zero ? 0.0 : f.c[2][p];
        for (std::uint32_t e = plan.first[p]; e < plan.first[p + 1]; ++e) {
            const std::uint32_t s = plan.spring[e];
            ax += plan.sign[e] * gx[s], ay += plan.sign[e] * gy[s], az += plan.sign[e] * gz[s];
        }
        if (finish.to_acceleration) ax *= in.inv_mass[p], ay *= in.inv_mass[p], az *= in.inv_mass[p];
        f.c[0][p] = ax, f.c[1][p] = ay, f.c[2][p] = az;
    }
    if (finished) {
        for (const SpringPlan::Bare& b : plan.bare) {
            for (int axis = 0; axis < 3; ++axis) unsummed(b.count, in.inv_mass + b.p, f.c[axis] + b.p);
        }
    }
    return true;
}

}  // namespace

bool accumulate(const Springs& springs, SpringPlan& plan, const ForceInput& in, const Vec3Span& f, bool skip_pinned,
                SpringFinish finish) {
    const std::size_t m = springs.list.size();
    if (plan.few || plan.springs != m || in.first != 0 || plan.first.size() != in.x.n + 1) {
        reference_pass(springs, plan.wide ? kWideKernels : kBaseKernels, in, f, finish);
        return false;
    }
    return planned_pass(springs, plan, in, f, skip_pinned, finish);
}

}  // namespace sim
