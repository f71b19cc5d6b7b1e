#include "scenes/report_peers.h"

#include "sim/error.h"

#include <boost/numeric/odeint.hpp>

#include <array>
#include <chrono>
#include <cmath>

namespace scenes {
namespace {

namespace odeint = boost::numeric::odeint;
using S3 = std::array<double, 3>;
using S6 = std::array<double, 6>;

// The accelerations of the report's problems (unit-mass test particle).
struct Ballistic {
    void operator()(const S3&, const S3&, S3& a) const { a = {0.0, -9.81, 0.0}; }
};
struct Oscillator {  // k = m = 1
    void operator()(const S3& x, const S3&, S3& a) const {
        for (int k = 0; k < 3; ++k) a[k] = -x[k];
    }
};
struct Damped {  // k = m = 1, c = 0.2
    void operator()(const S3& x, const S3& v, S3& a) const {
        for (int k = 0; k < 3; ++k) a[k] = -x[k] - 0.2 * v[k];
    }
};
struct Kepler {  // μ = 1
    void operator()(const S3& x, const S3&, S3& a) const {
        const double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        const double s = -1.0 / (r2 * std::sqrt(r2));
        for (int k = 0; k < 3; ++k) a[k] = s * x[k];
    }
};

template <class Accel>
PeerRun integrate(std::string_view peer, Accel accel, const sim::Vec3& x0, const sim::Vec3& v0, double dt, long steps) {
    S3 x{x0.x(), x0.y(), x0.z()}, v{v0.x(), v0.y(), v0.z()};
    double t = 0.0;
    const auto start = std::chrono::steady_clock::now();
    if (peer == "odeint_runge_kutta4") {
        S6 s{x[0], x[1], x[2], v[0], v[1], v[2]};
        odeint::runge_kutta4<S6> stepper;
        auto f = [&](const S6& y, S6& d, double) {
            S3 a;
            accel(S3{y[0], y[1], y[2]}, S3{y[3], y[4], y[5]}, a);
            d = {y[3], y[4], y[5], a[0], a[1], a[2]};
        };
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, s, t, dt);
        x = {s[0], s[1], s[2]};
    } else if (peer == "odeint_velocity_verlet") {
        odeint::velocity_verlet<S3> stepper;
        auto f = [&](const S3& q, const S3& w, S3& a, double) { accel(q, w, a); };
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, std::make_pair(std::ref(x), std::ref(v)), t, dt);
    } else if (peer == "odeint_rkn_mclachlan4") {
        odeint::symplectic_rkn_sb3a_mclachlan<S3> stepper;
        auto f = [&](const S3& q, S3& dpdt) { accel(q, S3{}, dpdt); };  // position forces only
        for (long i = 0; i < steps; ++i, t += dt) stepper.do_step(f, std::make_pair(std::ref(x), std::ref(v)), t, dt);
    } else {
        throw sim::InputError("report: no peer '" + std::string(peer) + "'");
    }
    PeerRun r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.x = sim::Vec3(x[0], x[1], x[2]);
    return r;
}

}  // namespace

const std::vector<PeerInfo>& peers() {
    static const std::vector<PeerInfo> list = {
        {"odeint_runge_kutta4", "rk4", 4, 4, true},
        {"odeint_velocity_verlet", "velocity_verlet", 2, 1, true},
        // McLachlan's 4th-order symplectic Runge-Kutta-Nyström, 6 stages (5 new force evaluations per step).
        {"odeint_rkn_mclachlan4", "rk4", 4, 5, false},
    };
    return list;
}

bool peer_knows(std::string_view problem) {
    return problem == "ballistic" || problem == "oscillator" || problem == "damped" || problem == "kepler_e0.5" ||
           problem == "kepler_e0.9";
}

PeerRun run_peer(std::string_view peer, std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double dt,
                 long steps) {
    if (problem == "ballistic") return integrate(peer, Ballistic{}, x0, v0, dt, steps);
    if (problem == "oscillator") return integrate(peer, Oscillator{}, x0, v0, dt, steps);
    if (problem == "damped") return integrate(peer, Damped{}, x0, v0, dt, steps);
    if (problem == "kepler_e0.5" || problem == "kepler_e0.9") return integrate(peer, Kepler{}, x0, v0, dt, steps);
    throw sim::InputError("report: the peers do not know the problem '" + std::string(problem) + "'");
}

}  // namespace scenes
