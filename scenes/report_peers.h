// Peers for `plausible report`: boost::odeint's steppers (Debian's
// libboost-dev, header-only) on the report's closed-form problems, so that
// our integrators' cost at equal error can be given as a ratio. Built into
// the command's library only, never into the physics core.
#pragma once

#include "sim/vec3_array.h"

#include <string>
#include <string_view>
#include <vector>

namespace scenes {

struct PeerInfo {
    std::string name;  // "odeint_runge_kutta4"
    std::string ours;  // the integrator of ours it is compared with (of the same order)
    int order = 0;
    int evaluations = 0;   // force evaluations per step
    bool velocity_forces;  // can it take a velocity-dependent force (drag)?
};
const std::vector<PeerInfo>& peers();

// The problems the peers know: "ballistic", "oscillator", "damped",
// "kepler_e0.5", "kepler_e0.9" (the same accelerations as the report's
// particle models).
bool peer_knows(std::string_view problem);

struct PeerRun {
    sim::Vec3 x = sim::Vec3::Zero();  // m, at the end
    double seconds = 0.0;             // wall time of the run
};

// One run of `peer` on `problem` from (x0, v0) for `steps` steps of dt.
PeerRun run_peer(std::string_view peer, std::string_view problem, const sim::Vec3& x0, const sim::Vec3& v0, double dt,
                 long steps);

}  // namespace scenes
