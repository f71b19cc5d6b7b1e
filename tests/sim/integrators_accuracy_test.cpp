// Every integrator against closed forms (ballistic shot, harmonic oscillator,
// Kepler orbit with e = 0.5), and its order of convergence measured over five
// halvings of dt. Tolerances are in metres (position error at the end time).
#include "sim/integrators.h"
#include "sim/problems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sim::test {
namespace {

using namespace sim::problems;

// The oscillator (kOscillator, kOscX0, kOscV0, kOscEnd) and the orbit's end
// (kKeplerEnd) are sim/problems.h's, as the report sweeps them.
constexpr double kKeplerE = 0.5;

double oscillator_error(Integrator id, double dt) {
    World world(oscillator_model(kOscillator, kOscX0, kOscV0));
    run_to(world, id, kOscEnd, dt);
    const auto exact = analytic::oscillator(kOscillator, kOscX0, kOscV0, world.state().t);
    return (world.state().x.get(1) - exact.x).norm();
}

double kepler_error(Integrator id, double dt) {
    World world(kepler_model(kKeplerE));
    run_to(world, id, kKeplerEnd, dt);
    const auto exact = analytic::kepler(kKeplerMu, kepler_r0(kKeplerE), kepler_v0(kKeplerE), world.state().t);
    return (world.state().x.get(1) - exact.x).norm();
}

double ballistic_error(Integrator id, double dt, double end) {
    World world(ballistic_model());
    run_to(world, id, end, dt);
    const auto exact = analytic::ballistic(Vec3::Zero(), kShotVelocity, kShotGravity, world.state().t);
    return (world.state().x.get(0) - exact.x).norm();
}

// Expected position error bounds at one step size, m. Each bound is about
// 1.3 to 2 times the error measured when the table was written, so a change
// that makes a method less accurate fails here.
struct ClosedFormCase {
    Integrator id;
    double ballistic_tol;   // m, T = 1 s, dt = 0.01 s
    double oscillator_tol;  // m, T = 10 s, dt = 0.01 s
    double kepler_tol;      // m, T = 5 s, dt = 2.5e-3 s
};

// The Euler methods' ballistic error is ½ |g| T dt = 0.04905 m exactly, so
// their bound is that value plus 1e-9 m; the others are exact for a constant
// force and must hit the parabola to round-off.
const std::vector<ClosedFormCase> kClosedFormCases = {
    {Integrator::forward_euler, 0.04905 + 1e-9, 0.06, 0.3},
    {Integrator::symplectic_euler, 0.04905 + 1e-9, 4e-3, 1e-2},
    {Integrator::leapfrog, 1e-12, 5e-5, 2.5e-4},
    {Integrator::velocity_verlet, 1e-12, 5e-5, 2.5e-4},
    {Integrator::position_verlet, 1e-12, 5e-5, 2.5e-4},
    {Integrator::rk4, 1e-12, 1e-9, 1e-9},
    {Integrator::backward_euler, 0.04905 + 1e-9, 0.06, 0.35},
};

class ClosedForm : public testing::TestWithParam<ClosedFormCase> {};

TEST_P(ClosedForm, BallisticOscillatorKepler) {
    const ClosedFormCase& c = GetParam();
    const double ballistic = ballistic_error(c.id, 0.01, 1.0);
    const double oscillator = oscillator_error(c.id, 0.01);
    const double kepler = kepler_error(c.id, 2.5e-3);
    EXPECT_LE(ballistic, c.ballistic_tol) << "ballistic position error, m";
    EXPECT_LE(oscillator, c.oscillator_tol) << "oscillator position error, m";
    EXPECT_LE(kepler, c.kepler_tol) << "Kepler e=0.5 position error, m";
    std::printf("%-17s ballistic %.3e m  oscillator %.3e m  kepler %.3e m\n",
                std::string(integrator_info(c.id).name).c_str(), ballistic, oscillator, kepler);
}

TEST(ClosedFormEuler, BallisticErrorIsHalfGTDt) {
    // Forward and symplectic Euler miss the parabola by exactly ½|g| T dt:
    // the sum of the rectangle rule's missing triangles.
    for (Integrator id : {Integrator::forward_euler, Integrator::symplectic_euler}) {
        const double predicted = 0.5 * kShotGravity.norm() * 1.0 * 0.01;
        EXPECT_NEAR(ballistic_error(id, 0.01, 1.0), predicted, 1e-9) << "m, " << integrator_info(id).name;
    }
}

TEST(ClosedFormVerlet, ReproduceParabolaToRoundOff) {
    // Constant force: leapfrog and velocity Verlet are exact, whatever dt; all
    // that remains is rounding, a few ulp of the coordinates (up to 6 m here)
    // per step: tolerance steps x 4 x 2.2e-16 x 6 m.
    for (Integrator id : {Integrator::leapfrog, Integrator::velocity_verlet}) {
        for (double dt : {0.1, 1.0 / 60.0, 1e-3}) {
            const double steps = std::round(2.0 / dt);
            const double tolerance = steps * 4.0 * 2.220446e-16 * 6.0;  // m
            EXPECT_LE(ballistic_error(id, dt, 2.0), tolerance)
                << "m, " << integrator_info(id).name << " dt " << dt << " s";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Integrators, ClosedForm, testing::ValuesIn(kClosedFormCases),
                         [](const auto& info) { return std::string(integrator_info(info.param.id).name); });

// Order of convergence ------------------------------------------------------

// Least-squares slope of log(error) against log(dt).
double fitted_slope(const std::vector<double>& dts, const std::vector<double>& errors) {
    const double n = static_cast<double>(dts.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < dts.size(); ++i) {
        const double x = std::log(dts[i]);
        const double y = std::log(errors[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Coarsest dt of each sweep, chosen so that all six step sizes lie in the
// asymptotic range: errors well below the problem's size, well above round-off.
struct OrderCase {
    Integrator id;
    double oscillator_dt0;  // s
    double kepler_dt0;      // s
};

const std::vector<OrderCase> kOrderCases = {
    {Integrator::forward_euler, 0.01, 2.5e-3},   {Integrator::symplectic_euler, 0.01, 2.5e-3},
    {Integrator::leapfrog, 0.05, 0.0125},        {Integrator::velocity_verlet, 0.05, 0.0125},
    {Integrator::position_verlet, 0.05, 0.0125}, {Integrator::rk4, 0.2, 0.05},
    {Integrator::backward_euler, 0.01, 2.5e-3},
};

constexpr int kHalvings = 5;  // six step sizes: dt0 ... dt0 / 32
constexpr double kOrderTolerance = 0.15;

// Collects one line per fit for the summary `make test` prints.
std::vector<std::string>& order_lines() {
    static std::vector<std::string> lines;
    return lines;
}

class Order : public testing::TestWithParam<OrderCase> {};

TEST_P(Order, FittedSlopeMatchesTheory) {
    const OrderCase& c = GetParam();
    const IntegratorInfo& info = integrator_info(c.id);
    struct Problem {
        const char* name;
        double dt0;
        double (*error)(Integrator, double);
    };
    for (const Problem& p : {Problem{"oscillator", c.oscillator_dt0, &oscillator_error},
                             Problem{"kepler_e0.5", c.kepler_dt0, &kepler_error}}) {
        std::vector<double> dts;
        std::vector<double> errors;
        for (int h = 0; h <= kHalvings; ++h) {
            dts.push_back(p.dt0 / (1 << h));
            errors.push_back(p.error(c.id, dts.back()));
        }
        const double slope = fitted_slope(dts, errors);
        EXPECT_NEAR(slope, info.order, kOrderTolerance)
            << info.name << " on " << p.name << ": fitted order (dimensionless), errors from " << errors.front()
            << " m to " << errors.back() << " m";
        char line[160];
        std::snprintf(line, sizeof line, "%-17s %-12s fitted %5.2f  expected %d  error %.2e .. %.2e m",
                      std::string(info.name).c_str(), p.name, slope, info.order, errors.front(), errors.back());
        std::printf("%s\n", line);
        order_lines().push_back(line);
    }
}

INSTANTIATE_TEST_SUITE_P(Integrators, Order, testing::ValuesIn(kOrderCases),
                         [](const auto& info) { return std::string(integrator_info(info.param.id).name); });

// Writes the fitted orders to $PLAUSIBLE_TEST_RESULTS/orders-<test>.txt (one
// file per test case, since ctest runs each case in its own process).
class OrderReport : public testing::EmptyTestEventListener {
    void OnTestEnd(const testing::TestInfo& test) override {
        const char* dir = std::getenv("PLAUSIBLE_TEST_RESULTS");
        if (dir == nullptr || order_lines().empty()) {
            return;
        }
        std::filesystem::create_directories(dir);
        std::string name = std::string(test.test_suite_name()) + "." + test.name();
        for (char& ch : name) {
            ch = (ch == '/') ? '_' : ch;
        }
        std::ofstream out(std::filesystem::path(dir) / ("orders-" + name + ".txt"));
        for (const std::string& line : order_lines()) {
            out << line << '\n';
        }
        order_lines().clear();
    }
};

const bool kReportInstalled = [] {
    testing::UnitTest::GetInstance()->listeners().Append(new OrderReport);
    return true;
}();

}  // namespace
}  // namespace sim::test
