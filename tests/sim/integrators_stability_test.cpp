// Energy behaviour of each integrator on the undamped oscillator over 1e5
// steps at ω·dt = 0.1: forward Euler gains energy (the pendulum swings wider
// and wider), the symplectic methods stay in a band without drift, backward
// Euler loses energy. Energies are relative to the initial energy E0.
#include "sim/integrators.h"
#include "sim/problems.h"

#include "sim/state_hash.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace sim::test {
namespace {

using namespace sim::problems;

// kOscillator (sim/problems.h): ω = 1 rad/s.
constexpr double kDt = 0.1;  // s, so ω·dt = 0.1
constexpr long kSteps = 100000;

// Energy ratio E/E0 after every step.
std::vector<double> energy_history(Integrator id, long steps) {
    World world(oscillator_model(kOscillator, Vec3(1.0, 0.0, 0.0), Vec3::Zero()));
    // The integrator alone, to overflow if it must: the watchdog would stop it.
    WatchdogLimits off;
    off.enabled = false;
    world.set_watchdog(off);
    const double e0 = world.energy();
    std::vector<double> ratio;
    ratio.reserve(static_cast<std::size_t>(steps));
    for (long i = 0; i < steps; ++i) {
        world.step({id, kDt, 1});
        ratio.push_back(world.energy() / e0);
    }
    return ratio;
}

double mean(const std::vector<double>& values, std::size_t first, std::size_t count) {
    double sum = 0.0;
    for (std::size_t i = first; i < first + count; ++i) {
        sum += values[i];
    }
    return sum / static_cast<double>(count);
}

TEST(EnergyForwardEuler, GrowsByOnePlusOmegaSquaredDtSquaredPerStep) {
    // On x'' = -ω² x forward Euler multiplies the energy by exactly
    // (1 + ω²dt²) each step; after 1000 steps E/E0 = 1.01^1000 ≈ 2.1e4.
    const std::vector<double> ratio = energy_history(Integrator::forward_euler, 1000);
    for (std::size_t i = 1; i < ratio.size(); ++i) {
        ASSERT_GT(ratio[i], ratio[i - 1]) << "energy must grow every step (step " << i << ")";
    }
    const double predicted = std::pow(1.0 + kDt * kDt, 1000.0);
    EXPECT_NEAR(ratio.back() / predicted, 1.0, 1e-9) << "E/E0 relative to the prediction (dimensionless)";
    std::printf("forward_euler: E/E0 after 1000 steps %.6e (predicted %.6e)\n", ratio.back(), predicted);
}

TEST(EnergyForwardEuler, OverflowsLongBefore1e5Steps) {
    // 1.01^1e5 ≈ e^995 exceeds the largest double: the run explodes.
    const std::vector<double> ratio = energy_history(Integrator::forward_euler, kSteps);
    EXPECT_FALSE(std::isfinite(ratio.back())) << "E/E0 after 1e5 steps: " << ratio.back();
}

TEST(EnergyForwardEuler, TheWatchdogStopsItWithAVerdict) {
    World world(oscillator_model(kOscillator, Vec3(1.0, 0.0, 0.0), Vec3::Zero()));
    WatchdogLimits limits;
    limits.energy_growth = 2.0;
    world.set_watchdog(limits);
    const double e0 = world.energy();
    long frames = 0;
    while (!world.verdict().exploded() && frames < 100000) {
        world.step({Integrator::forward_euler, kDt, 1});
        ++frames;
    }
    // E grows by exactly (1 + ω² dt²) per step (ω = 1 here): it first exceeds 2 E0
    // after ceil(ln 2 / ln(1 + dt²)) steps.
    const long predicted = static_cast<long>(std::ceil(std::log(2.0) / std::log1p(kDt * kDt)));
    const Verdict& v = world.verdict();
    ASSERT_TRUE(v.exploded());
    EXPECT_EQ(v.quantity, "energy");
    EXPECT_EQ(static_cast<long>(v.frame), predicted);
    EXPECT_DOUBLE_EQ(v.limit, 2.0 * e0) << "J";
    EXPECT_GT(v.value, v.limit) << "J";
    const std::uint64_t hash = state_hash(world.state());
    world.step({Integrator::forward_euler, kDt, 1});
    EXPECT_EQ(state_hash(world.state()), hash) << "no step after the verdict";
    EXPECT_NE(v.message("oscillator").find("oscillator: exploded at frame " + std::to_string(predicted) + ": energy"),
              std::string::npos)
        << v.message("oscillator");
}

struct BandCase {
    Integrator id;
    double band;  // max |E/E0 - 1| allowed over 1e5 steps (dimensionless)
};

// Bands from the modified energy each method conserves exactly on this
// problem: symplectic Euler conserves ½(v² + ω²x²) - ½ dt ω² x v, so
// |E/E0 - 1| <= ω dt / (2 - ω dt) = 0.0526; the Verlet family conserves
// ½v² + ½ω²x²(1 - ω²dt²/4), so |E/E0 - 1| <= ω²dt²/(4 - ω²dt²) = 0.0025
// for positions; Störmer recovers its velocity from positions as
// v (1 + ω²dt²/2) + O(dt³), which lifts the kinetic part by up to ω²dt², so
// its band is 0.01.
const std::vector<BandCase> kBandCases = {
    {Integrator::symplectic_euler, 0.0527},
    {Integrator::leapfrog, 0.0026},
    {Integrator::velocity_verlet, 0.0026},
    {Integrator::position_verlet, 0.01},
};

class EnergyBand : public testing::TestWithParam<BandCase> {};

TEST_P(EnergyBand, StaysInBandWithoutDrift) {
    const BandCase& c = GetParam();
    const std::vector<double> ratio = energy_history(c.id, kSteps);
    const auto [lo, hi] = std::minmax_element(ratio.begin(), ratio.end());
    EXPECT_LE(*hi - 1.0, c.band) << "E/E0 - 1, dimensionless";
    EXPECT_LE(1.0 - *lo, c.band) << "1 - E/E0, dimensionless";
    // No drift: the mean over the first and the last 10% of the run (about
    // 160 periods each) agree to 1e-4 of E0.
    const std::size_t tenth = ratio.size() / 10;
    const double early = mean(ratio, 0, tenth);
    const double late = mean(ratio, ratio.size() - tenth, tenth);
    EXPECT_NEAR(late, early, 1e-4) << "mean E/E0, first vs last 10% of 1e5 steps";
    std::printf("%-17s E/E0 in [%.6f, %.6f], mean first 10%% %.8f, last 10%% %.8f\n",
                std::string(integrator_info(c.id).name).c_str(), *lo, *hi, early, late);
}

INSTANTIATE_TEST_SUITE_P(Symplectic, EnergyBand, testing::ValuesIn(kBandCases),
                         [](const auto& info) { return std::string(integrator_info(info.param.id).name); });

TEST(EnergyBackwardEuler, LosesEnergyEveryStep) {
    // Backward Euler divides the energy by (1 + ω²dt²) each step (the
    // linearisation is exact for a linear spring).
    const std::vector<double> ratio = energy_history(Integrator::backward_euler, kSteps);
    for (std::size_t i = 1; i < 1000; ++i) {
        ASSERT_LT(ratio[i], ratio[i - 1]) << "energy must fall every step (step " << i << ")";
    }
    EXPECT_NEAR(ratio[999] * std::pow(1.0 + kDt * kDt, 1000.0), 1.0, 1e-9)
        << "E/E0 after 1000 steps relative to 1.01^-1000 (dimensionless)";
    EXPECT_LT(ratio.back(), 1e-100) << "E/E0 after 1e5 steps";
    std::printf("backward_euler: E/E0 after 1000 steps %.6e, after 1e5 steps %.3e\n", ratio[999], ratio.back());
}

TEST(EnergyRk4, DecaysSlowly) {
    // RK4 is not symplectic: on the oscillator it multiplies the energy by
    // |R(iωdt)|² = 1 - y⁶/72 + y⁸/576 (y = ω dt) each step, with
    // R(z) = 1 + z + z²/2 + z³/6 + z⁴/24: a slow monotone loss.
    const std::vector<double> ratio = energy_history(Integrator::rk4, kSteps);
    const double y = kDt;
    const double per_step = 1.0 - std::pow(y, 6) / 72.0 + std::pow(y, 8) / 576.0;
    const double predicted = std::pow(per_step, static_cast<double>(kSteps));
    EXPECT_NEAR(ratio.back(), predicted, 1e-9) << "E/E0 after 1e5 steps (dimensionless)";
    EXPECT_LT(ratio.back(), 1.0);
}

}  // namespace
}  // namespace sim::test
