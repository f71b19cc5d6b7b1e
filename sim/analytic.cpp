#include "sim/analytic.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sim::analytic {

PointState ballistic(const Vec3& x0, const Vec3& v0, const Vec3& g, double t) {
    return {x0 + v0 * t + 0.5 * g * t * t, v0 + g * t};
}

PointState oscillator(const Oscillator& o, const Vec3& x0, const Vec3& v0, double t) {
    const double w0 = std::sqrt(o.stiffness / o.mass);
    const double zeta = o.damping / (2.0 * std::sqrt(o.stiffness * o.mass));
    if (zeta < 1.0) {
        // x = e^{-ζω0 t} (x0 cos ωd t + B sin ωd t),  B = (v0 + ζω0 x0)/ωd
        const double wd = w0 * std::sqrt(1.0 - zeta * zeta);
        const double decay = std::exp(-zeta * w0 * t);
        const double c = std::cos(wd * t);
        const double s = std::sin(wd * t);
        const Vec3 b = (v0 + zeta * w0 * x0) / wd;
        const Vec3 x = decay * (x0 * c + b * s);
        const Vec3 v = decay * ((b * wd - zeta * w0 * x0) * c - (x0 * wd + zeta * w0 * b) * s);
        return {x, v};
    }
    if (zeta == 1.0) {
        // x = (x0 + (v0 + ω0 x0) t) e^{-ω0 t}
        const double decay = std::exp(-w0 * t);
        const Vec3 b = v0 + w0 * x0;
        return {(x0 + b * t) * decay, (b - w0 * (x0 + b * t)) * decay};
    }
    // x = A e^{r1 t} + B e^{r2 t},  r1,2 = -ω0 (ζ ∓ sqrt(ζ² - 1))
    const double root = std::sqrt(zeta * zeta - 1.0);
    const double r1 = -w0 * (zeta - root);
    const double r2 = -w0 * (zeta + root);
    const Vec3 a = (v0 - r2 * x0) / (r1 - r2);
    const Vec3 b = x0 - a;
    const double e1 = std::exp(r1 * t);
    const double e2 = std::exp(r2 * t);
    return {a * e1 + b * e2, a * r1 * e1 + b * r2 * e2};
}

OrbitElements orbit_elements(double mu, const Vec3& r0, const Vec3& v0) {
    const double r = r0.norm();
    if (r == 0.0) {
        throw std::domain_error("kepler: r0 must not be zero");
    }
    const double inv_a = 2.0 / r - v0.squaredNorm() / mu;  // vis-viva
    if (!(inv_a > 0.0)) {
        throw std::domain_error("kepler: the orbit is not bound (energy >= 0)");
    }
    const double a = 1.0 / inv_a;
    const double sigma0 = r0.dot(v0) / std::sqrt(mu);
    const double ecos = 1.0 - r / a;
    const double esin = sigma0 / std::sqrt(a);
    const double e = std::sqrt(ecos * ecos + esin * esin);
    return {a, e, 2.0 * std::numbers::pi * std::sqrt(a * a * a / mu)};
}

PointState kepler(double mu, const Vec3& r0, const Vec3& v0, double t) {
    const OrbitElements el = orbit_elements(mu, r0, v0);
    const double a = el.a;
    const double r = r0.norm();
    const double sqrt_a = std::sqrt(a);
    const double sigma0 = r0.dot(v0) / std::sqrt(mu);
    const double n = std::sqrt(mu / (a * a * a));
    const double two_pi = 2.0 * std::numbers::pi;

    // Whole revolutions are exact (ΔE grows by 2π per period); Newton solves
    // the remainder M in [0, 2π), where F(0) = -M <= 0 < F(2π).
    const double mean = n * t;
    const double turns = std::floor(mean / two_pi);
    const double m = mean - turns * two_pi;
    auto kepler_residual = [&](double de) {
        return de + sigma0 / sqrt_a * (1.0 - std::cos(de)) - (1.0 - r / a) * std::sin(de) - m;
    };
    double lo = 0.0;
    double hi = two_pi;
    double de = m;
    for (int iteration = 0; iteration < 100; ++iteration) {
        const double f = kepler_residual(de);
        if (f == 0.0) {
            break;
        }
        (f < 0.0 ? lo : hi) = de;
        // F'(ΔE) = r(ΔE)/a > 0
        const double slope = 1.0 + sigma0 / sqrt_a * std::sin(de) - (1.0 - r / a) * std::cos(de);
        double next = de - f / slope;
        if (!(next > lo && next < hi)) {
            next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
        }
        if (std::abs(next - de) <= 1e-15 * two_pi) {
            de = next;
            break;
        }
        de = next;
    }
    de += turns * two_pi;

    const double c = std::cos(de);
    const double s = std::sin(de);
    const double r_t = a + (r - a) * c + sigma0 * sqrt_a * s;
    const double f = 1.0 - a / r * (1.0 - c);
    const double g = t - (de - s) / n;
    const double f_dot = -std::sqrt(mu * a) * s / (r_t * r);
    const double g_dot = 1.0 - a / r_t * (1.0 - c);
    return {f * r0 + g * v0, f_dot * r0 + g_dot * v0};
}

Angle small_angle_pendulum(double length, double g, double theta0, double theta_dot0, double t) {
    const double w = std::sqrt(g / length);
    const double c = std::cos(w * t);
    const double s = std::sin(w * t);
    return {theta0 * c + theta_dot0 / w * s, -theta0 * w * s + theta_dot0 * c};
}

double pendulum_period(double length, double g, double theta0) {
    // K(k) = π / (2 AGM(1, sqrt(1 - k²)))
    const double k = std::sin(0.5 * theta0);
    double x = 1.0;
    double y = std::sqrt(1.0 - k * k);
    for (int i = 0; i < 64 && std::abs(x - y) > 1e-16 * x; ++i) {
        const double mean = 0.5 * (x + y);
        y = std::sqrt(x * y);
        x = mean;
    }
    const double elliptic_k = std::numbers::pi / (2.0 * x);
    return 4.0 * std::sqrt(length / g) * elliptic_k;
}

}  // namespace sim::analytic
