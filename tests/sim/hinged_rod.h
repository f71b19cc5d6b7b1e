// The hinged rod the rigid accuracy tests swing (through RigidWorld and
// through articulated_step), with its periods in closed form.
#pragma once

#include "sim/analytic.h"

#include <cmath>
#include <numbers>

namespace sim::test {

// A 1 kg box rod 0.1 x 1.0 x 0.1 m hinged about z at its top end (the origin),
// released from rest at θ0 from hanging straight down. As a physical pendulum
// it swings as a simple one of length I / (m d): T = 4 √(I / m g d) K(sin(θ0 / 2)).
struct Rod {
    static constexpr double m = 1.0, length = 1.0, width = 0.1;  // kg, m, m
    static constexpr double d = 0.5;                             // m, hinge to centre of mass
    static constexpr double inertia = m * (length * length + width * width) / 12.0 + m * d * d;  // kg·m², at the hinge
    static constexpr double g = 9.81;                                                            // m/s²
    static double small_period() { return 2.0 * std::numbers::pi * std::sqrt(inertia / (m * g * d)); }       // s
    static double period(double theta0) { return analytic::pendulum_period(inertia / (m * d), g, theta0); }  // s
};

}  // namespace sim::test
