// Wind: pressure on the area exposed to the wind (the lecture: "depends on
// the area exposed in the wind direction").
//
// A surface triangle with unit normal n, area A and mean velocity v_avg sees
// the relative wind u = w(t) - v_avg; the air pushes along n with
//   F = ½ ρ C_d A (u · n) |u · n| n,
// a third on each corner (A |u·n| / |u| is the area the wind sees, and the
// force of a flat plate is normal to it). A lone particle of radius r is a
// sphere of cross-section π r²: F = ½ ρ C_d π r² |u| u.
//
// Gusts: w(t) = velocity + g(t), with a random gust g_k (each component
// normal, standard deviation gust_strength) at the keys t_k = k gust_period,
// eased between keys by smoothstep (C¹). g_k is three normal() draws of the
// project PRNG Random(seed ^ (0x9E3779B97F4A7C15 (k + 1))) (the golden-ratio
// constant spreads consecutive keys over the seed space; k + 1 so that key 0
// does not reuse the bare seed): w is a pure function of time with no state,
// so a rewound or replayed run sees the same wind, bit for bit.
#pragma once

#include "sim/force.h"

#include <array>
#include <cstdint>
#include <vector>

namespace sim {

struct Wind {
    Vec3 velocity = Vec3(3, 0, 0);                        // m/s, the mean wind
    double air_density = 1.2;                             // kg/m³ (>= 0)
    double drag_coefficient = 1.0;                        // C_d, dimensionless (>= 0)
    std::vector<std::array<std::uint32_t, 3>> triangles;  // surfaces it presses on, as BodyRange::surface
    std::vector<std::uint32_t> particles;                 // lone particles it blows on
    double radius = 0.05;                                 // m, those particles' radius
    double gust_strength = 0.0;                           // m/s, standard deviation of each gust component
    double gust_period = 1.0;                             // s, time between gust keys (> 0)
    std::uint64_t seed = 1;
};

// The wind velocity at time t (mean plus gust), m/s. Exactly `velocity` when
// gust_strength is 0.
Vec3 wind_at(const Wind& wind, double t);

void validate(const Wind& wind, std::size_t particle_count);
// Triangles couple their corners; lone particles feel only their own velocity.
inline bool is_local(const Wind& wind) { return wind.triangles.empty(); }
void accumulate(const Wind& wind, const ForceInput& in, Vec3Span f);
inline double potential_energy(const Wind&, const ForceInput&) { return 0.0; }  // driven
// None: implicit methods take the wind explicitly (it is soft, and its
// velocity dependence is weak next to the springs').
inline void accumulate_jacobians(const Wind&, const ForceInput&, Jacobians&) {}

}  // namespace sim
