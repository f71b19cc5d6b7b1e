// Closed-form solutions: the independent predictions that tests, ghosts and
// the report compare the integrators with. Nothing here steps anything.
#pragma once

#include "sim/vec3_array.h"

namespace sim::analytic {

struct PointState {
    Vec3 x;  // position, m
    Vec3 v;  // velocity, m/s
};

// Ballistic shot without friction: constant acceleration g.
//   x(t) = x0 + v0 t + ½ g t²,   v(t) = v0 + g t
PointState ballistic(const Vec3& x0, const Vec3& v0, const Vec3& g, double t);

// Mass m on a zero-rest-length spring of stiffness k to the origin, with a
// linear damper c:  m x'' + c x' + k x = 0 (each component independently).
// Underdamped (ζ < 1), critically damped (ζ = 1) and overdamped (ζ > 1)
// branches, with ω0 = sqrt(k/m) and ζ = c / (2 sqrt(k m)); c = 0 is the
// undamped oscillator x0 cos ω0 t + (v0/ω0) sin ω0 t.
struct Oscillator {
    double mass = 1.0;       // kg
    double stiffness = 1.0;  // N/m
    double damping = 0.0;    // N·s/m
};
PointState oscillator(const Oscillator& o, const Vec3& x0, const Vec3& v0, double t);

// Two-body Kepler problem, relative coordinates: r'' = -μ r / |r|³ with
// μ = G (m1 + m2) (or G M about a pinned mass M). Bound (elliptic) orbits only:
// throws std::domain_error when the energy is >= 0 or r0 = 0. The time is
// mapped to the eccentric-anomaly change ΔE through Kepler's equation,
//   n t = ΔE + (σ0/√a)(1 - cos ΔE) - (1 - r0/a) sin ΔE,  n = sqrt(μ/a³),
//   σ0 = r0·v0/√μ,
// solved by Newton's method (safeguarded by bisection: the right side grows
// monotonically), then positions by the Lagrange f and g coefficients.
PointState kepler(double mu, const Vec3& r0, const Vec3& v0, double t);

// Eccentricity and semi-major axis of the bound orbit through (r0, v0).
struct OrbitElements {
    double a;       // semi-major axis, m
    double e;       // eccentricity
    double period;  // s
};
OrbitElements orbit_elements(double mu, const Vec3& r0, const Vec3& v0);

// Simple pendulum of length L under gravity g in the small-angle limit:
//   θ(t) = θ0 cos ωt + (θ̇0/ω) sin ωt,  ω = sqrt(g/L)
struct Angle {
    double theta;  // rad
    double omega;  // rad/s
};
Angle small_angle_pendulum(double length, double g, double theta0, double theta_dot0, double t);

// Exact period of a pendulum released at rest from amplitude θ0 (any angle
// below π): T = 4 sqrt(L/g) K(sin(θ0/2)), K the complete elliptic integral of
// the first kind, computed by the arithmetic-geometric mean.
double pendulum_period(double length, double g, double theta0);

}  // namespace sim::analytic
