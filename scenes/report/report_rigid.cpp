// The report's rigid bodies: three problems with closed forms (report_rigid.h)
// run through sim::RigidWorld's public API under Plausible's defaults and
// ODE's own settings, and through Bullet's two solvers
// (report_rigid_peers.cpp), each at a 1/60 s frame in substeps: its errors
// and its cost in µs of wall time per frame, timed in the same run.
#include "scenes/report/report_rigid.h"

#include "scenes/report/report_stages.h"

#include "sim/error.h"
#include "sim/rigid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace scenes::report {
namespace {

using RigidClock = std::chrono::steady_clock;
constexpr double kFrame = 1.0 / 60.0;  // s

// A setting of sim::RigidWorld the report measures.
struct RigidWorldSetting {
    std::string solver, setting;
    sim::RigidSettings settings;
};

// Plausible's defaults, the same with every body in ODE (articulated off),
// then ODE as it comes: its own joint ERP 0.2 and CFM 1e-10, its implicit
// gyroscopic term, no position pass. Sleep off and no ground.
std::vector<RigidWorldSetting> rigid_world_settings() {
    sim::RigidSettings plausible;
    plausible.ground = false;
    plausible.sleep = false;
    sim::RigidSettings maximal = plausible;
    maximal.articulated = false;
    sim::RigidSettings ode = maximal;
    ode.joint_erp = 0.2;
    ode.joint_cfm = 1e-10;
    ode.gyroscopic_rk4 = false;
    ode.position_iterations = 0;
    ode.speculative_stops = false;
    std::vector<RigidWorldSetting> out = {{"plausible", "defaults", plausible},
                                          {"plausible", "articulated off", maximal}};
    for (const int n : {10, 20, 50}) {
        sim::RigidSettings s = ode;
        s.iterations = n;
        out.push_back({"ode_quickstep", std::to_string(n) + " iterations", s});
    }
    sim::RigidSettings exact = ode;
    exact.quickstep = false;
    out.push_back({"ode_exact", "dWorldStep", exact});
    return out;
}

// One problem through sim::RigidWorld.
class RigidWorldRun final : public RigidRun {
public:
    RigidWorldRun(std::string_view problem, const sim::RigidSettings& settings, double h)
        : problem_(problem), world_(settings), h_(h) {
        sim::BodyDef body;
        body.mass = 1.0;
        if (problem == "pendulum") {
            body.size = sim::Vec3(RigidPendulum::width, RigidPendulum::length, RigidPendulum::width);
            body.position = RigidPendulum::center();
            body.orientation = RigidPendulum::orientation();
            bodies_.push_back(world_.add_body(body));
            world_.add_joint({.type = sim::JointType::hinge, .a = bodies_[0], .axis = sim::Vec3::UnitZ()});
        } else if (problem == "top") {
            body.shape = sim::RigidShape::cylinder;
            body.size = sim::Vec3(RigidTop::radius, RigidTop::thickness, 0.0);
            body.position = RigidTop::center();
            body.orientation = RigidTop::orientation();
            body.velocity = RigidTop::velocity();
            body.angular_velocity = RigidTop::angular_velocity();
            bodies_.push_back(world_.add_body(body));
            world_.add_joint({.type = sim::JointType::ball, .a = bodies_[0]});
        } else if (problem == "chain") {
            body.size = sim::Vec3(RigidChain::length, RigidChain::width, RigidChain::width);
            for (int k = 0; k < RigidChain::links; ++k) {
                body.position = RigidChain::center(k);
                bodies_.push_back(world_.add_body(body));
                sim::JointDef hinge{.type = sim::JointType::hinge,
                                    .a = bodies_.back(),
                                    .anchor = sim::Vec3(RigidChain::length * k, 0.0, 0.0),
                                    .axis = sim::Vec3::UnitZ()};
                if (k > 0) hinge.b = bodies_[bodies_.size() - 2];
                world_.add_joint(hinge);
            }
        } else {
            throw sim::InputError("report: no rigid problem '" + std::string(problem) + "'");
        }
    }

    void step() override { world_.step(h_); }
    double energy() const override { return world_.kinetic_energy() + world_.potential_energy(); }
    sim::Vec3 probe() const override {
        const sim::BodyState s = world_.state(bodies_[0]);
        if (problem_ == "pendulum") return s.position;
        if (problem_ == "top") return s.orientation * sim::Vec3::UnitZ();
        return sim::Vec3::Zero();
    }
    bool broken() const override {
        for (const sim::BodyId b : bodies_) {
            const sim::BodyState s = world_.state(b);
            if (!s.position.allFinite() || !(s.angular_velocity.norm() <= sim::kMaxBodySpin)) return true;
        }
        return false;
    }

private:
    std::string problem_;
    sim::RigidWorld world_;
    std::vector<sim::BodyId> bodies_;
    double h_;  // s
};

// The pendulum's angle from hanging straight down, rad, from its centre.
double swing_angle(const sim::Vec3& x) { return std::atan2(x.x(), -x.y()); }
// The top's axis's azimuth about +y, rad (x towards -z: a turn about +y).
double azimuth(const sim::Vec3& a) { return std::atan2(-a.z(), a.x()); }

// One run of `run` over span.seconds: its errors into `s`; returns the wall
// time of its steps alone, s.
double run_once(const std::string& problem, RigidRun& run, double h, double seconds, RigidSample& s) {
    const long steps = std::lround(seconds / h);
    const long precession_steps = std::lround(RigidTop::precession_span / h);
    const double e0 = run.energy();
    std::vector<double> crossings;  // s, where the pendulum's angle changes sign
    double before = problem == "pendulum" ? swing_angle(run.probe()) : 0.0;
    double phi = problem == "top" ? azimuth(run.probe()) : 0.0, turned = 0.0;  // rad, the top's azimuth unwrapped
    double rate = kNaN;                                                        // rad/s, the top's precession
    double wall = 0.0;
    for (long i = 1; i <= steps; ++i) {
        const auto start = RigidClock::now();
        run.step();
        wall += std::chrono::duration<double>(RigidClock::now() - start).count();
        if (run.broken()) {
            s.failed = true;
            return wall;
        }
        if (problem == "pendulum") {
            const double now = swing_angle(run.probe());
            if ((before > 0.0) != (now > 0.0)) {
                crossings.push_back(h * (static_cast<double>(i - 1) + before / (before - now)));
            }
            before = now;
        } else if (problem == "top" && i <= precession_steps) {
            const double next = azimuth(run.probe());
            turned += std::remainder(next - phi, 2.0 * std::numbers::pi);
            phi = next;
            if (i == precession_steps) rate = turned / (h * static_cast<double>(i));
        }
    }
    const double de = std::abs(run.energy() - e0);  // J
    if (!std::isfinite(de)) {
        s.failed = true;
        return wall;
    }
    if (problem == "pendulum") {
        s.period_error =
            crossings.size() >= 3 ? std::abs((crossings[2] - crossings[0]) / RigidPendulum::period() - 1.0) : kNaN;
        s.energy_error = de / RigidPendulum::swing_energy();
        s.error = std::isnan(s.period_error) ? kNaN : std::max(s.period_error, s.energy_error);
    } else if (problem == "top") {
        const double tilt = std::acos(std::clamp(run.probe().normalized().y(), -1.0, 1.0));  // rad
        s.precession_error = std::abs(rate / RigidTop::precession() - 1.0);
        s.tilt_error = std::abs(tilt - RigidTop::tilt) * 180.0 / std::numbers::pi;
        s.error = std::isfinite(s.precession_error)
                      ? std::max(s.precession_error, std::abs(tilt / RigidTop::tilt - 1.0))
                      : kNaN;
    } else {
        s.energy_error = de / RigidChain::released();
        s.error = s.energy_error;
    }
    return wall;
}

// One solver and setting at one h: the errors of its first run, the median
// cost of span.repetitions runs, each on a world built before its clock.
template <class Make>
RigidSample measure_one(const std::string& problem, const std::string& solver, const std::string& setting, double h,
                        const RigidSpan& span, const Make& make) {
    RigidSample s{.problem = problem, .solver = solver, .setting = setting, .h = h};
    std::vector<double> walls;
    for (int r = 0; r < std::max(1, span.repetitions); ++r) {
        RigidSample again = s;
        const std::unique_ptr<RigidRun> run = make(h);
        walls.push_back(run_once(problem, *run, h, span.seconds, r == 0 ? s : again));
        if (s.failed) break;  // a stopped run's time is no measure of a step
    }
    if (!s.failed) s.us_per_frame = 1e6 * median(walls) / span.seconds * kFrame;
    if (s.failed) s.error = kNaN;
    return s;
}

}  // namespace

const std::vector<std::string>& rigid_problems() {
    static const std::vector<std::string> list = {"pendulum", "top", "chain"};
    return list;
}

int rigid_series_count() {
    return static_cast<int>(rigid_problems().size() * (rigid_world_settings().size() + rigid_peers().size()));
}

std::vector<RigidSample> measure_rigid(const RigidSpan& span, Progress& progress) {
    std::vector<RigidSample> out;
    for (const std::string& problem : rigid_problems()) {
        auto sweep = [&](const std::string& solver, const std::string& setting, const auto& make) {
            for (const int n : span.substeps) {
                out.push_back(measure_one(problem, solver, setting, kFrame / n, span, make));
            }
            progress.step("rigid " + problem + " " + solver);
        };
        for (const RigidWorldSetting& o : rigid_world_settings()) {
            sweep(o.solver, o.setting,
                  [&](double h) { return std::make_unique<RigidWorldRun>(problem, o.settings, h); });
        }
        for (const RigidPeer& peer : rigid_peers()) {
            sweep(peer.solver, peer.setting, [&](double h) { return bullet_run(peer.solver, problem, h); });
        }
    }
    return out;
}

}  // namespace scenes::report
