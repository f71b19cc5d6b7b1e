// Work that grows faster than the file (scenes/model/work_limits.cpp): Newton
// gravity is refused where a frame would cost more than a second by the
// loader's estimate, n (n - 1) / 2 pairs x the passes a frame at 10 ns a pair,
// plus backward Euler's dense (3n)³/3 flops a substep at 4 ns; trails where
// they would hold more than 5e7 points. The boundaries below are worked out
// by hand from those rules.
#include "scenes/model/scene.h"

#include <gtest/gtest.h>

#include <string>

namespace scenes {
namespace {

// A group of n particles under Newton gravity, stepped by `step` (a [step] table's keys).
std::string newton_group(int n, const std::string& step = "") {
    return "description = \"d\"\nframes = 10\n[step]\n" + step + "\n[[groups]]\ncount = " + std::to_string(n) +
           "\nspacing = [0.01, 0, 0]\n[forces.newton_gravity]\nG = 1e-6\n";
}

// The refusal's message, or "" when the scene loads.
std::string refusal(const std::string& text) {
    try {
        parse_scene(text, "galaxy.toml");
        return "";
    } catch (const SceneError& e) {
        return e.what();
    }
}

TEST(WorkLimits, NewtonGravityStopsWhereAFrameWouldPassASecond) {
    // Symplectic Euler, 1 substep: 2 passes a frame (the force, the energy),
    // n (n - 1) x 10 ns <= 1 s up to n = 10000.
    EXPECT_EQ(refusal(newton_group(10'000)), "");
    const std::string big = refusal(newton_group(10'001));
    EXPECT_NE(big.find("galaxy.toml:8:1: forces.newton_gravity on 10001 particles is O(n²): n (n - 1) / 2 = "
                       "50005000 pairs, evaluated 2 times a frame"),
              std::string::npos)
        << big;
    EXPECT_NE(big.find("about 1 s a frame; at most 1 s a frame"), std::string::npos) << big;
    EXPECT_NE(big.find("these settings allow at most 10000 particles"), std::string::npos) << big;
    // RK4 with 4 substeps: 4 x 4 + 1 = 17 passes, n (n - 1) <= 2 / (17 x 1e-8)
    // = 11764705.9: n = 3430 (3430 x 3429 = 11761470), not 3431 (11768330).
    EXPECT_EQ(refusal(newton_group(3'430, "integrator = \"rk4\"\nsubsteps = 4")), "");
    const std::string rk4 = refusal(newton_group(3'431, "integrator = \"rk4\"\nsubsteps = 4"));
    EXPECT_NE(rk4.find("17 times a frame (rk4: 4 a step x 4 substeps, 1 for the energy)"), std::string::npos) << rk4;
    EXPECT_NE(rk4.find("at most 3430 particles"), std::string::npos) << rk4;
}

TEST(WorkLimits, BackwardEulerCountsItsDenseFactorization) {
    // 9 n³ x 4 ns + n (n - 1) x 10 ns <= 1 s: n = 302 (0.9925 s), not 303 (1.0024 s).
    EXPECT_EQ(refusal(newton_group(302, "integrator = \"backward_euler\"")), "");
    const std::string be = refusal(newton_group(303, "integrator = \"backward_euler\""));
    EXPECT_NE(be.find("backward_euler factors a dense 909 x 909 system each substep"), std::string::npos) << be;
    EXPECT_NE(be.find("at most 302 particles"), std::string::npos) << be;
}

TEST(WorkLimits, TheWatchdogsEnergyRuleAddsAPassEverySubstep) {
    // energy_growth on: 1 + 1 + 1 = 3 passes, n (n - 1) <= 2 / 3e-8: n = 8165, not 8166.
    const std::string watched = "\n[watchdog]\nenergy_growth = 2\n";
    EXPECT_EQ(refusal(newton_group(8'165) + watched), "");
    EXPECT_NE(refusal(newton_group(8'166) + watched).find("3 times a frame"), std::string::npos);
}

// Trails: moving particles x (min(trail_frames, frames) + 1) <= 5e7 points.
TEST(WorkLimits, TrailsStopAtFiftyMillionPoints) {
    auto trails = [](int frames, int trail_frames, const std::string& more = "") {
        return "description = \"d\"\nframes = " + std::to_string(frames) +
               "\n[[groups]]\ncount = 50000\nspacing = [0.01, 0, 0]\n" + more +
               "[view]\ntrail_frames = " + std::to_string(trail_frames) + "\n";
    };
    EXPECT_EQ(refusal(trails(2000, 999)), "") << "50000 x 1000 = 5e7";
    const std::string big = refusal(trails(2000, 1000));
    EXPECT_NE(big.find("galaxy.toml:7:16: view.trail_frames = 1000 behind 50000 moving particles keeps 50050000 "
                       "trail points by frame 2000"),
              std::string::npos)
        << big;
    EXPECT_EQ(refusal(trails(999, 5000)), "") << "the run ends first: 50000 x 1000";
    // Pinned particles keep no trail; an emitter's particles, parked until born, do.
    EXPECT_NE(refusal(trails(2000, 1000, "[[particles]]\nposition = [0, 1, 0]\npinned = true\n"))
                  .find("behind 50000 moving particles"),
              std::string::npos)
        << "the pinned one is not counted";
    EXPECT_NE(refusal(trails(2000, 999, "[[emitters]]\ncount = 10\n")).find("50010 moving particles"),
              std::string::npos);
}

// A cloth's links: structural 2 (n - 1) n, shear 2 (n - 1)², bend 2 (n - 2) n.
// 820² nodes make 4,026,202, past the 4,000,000 a scene may hold (about
// 350 bytes each: a 1000² cloth took 2.1 GB).
TEST(WorkLimits, LinksStopAtFourMillion) {
    const std::string big = refusal("description = \"d\"\n[[cloths]]\nnx = 820\nny = 820\nshear = 1\nbend = 1\n");
    EXPECT_NE(big.find("galaxy.toml:2:1: cloths[0] would make 4026202 links on 672400 nodes, 4026202 in the scene"),
              std::string::npos)
        << big;
    EXPECT_NE(big.find("about 1.4 GB at 350 bytes a link; at most 4000000 links"), std::string::npos) << big;
    // A soft body's 13 neighbour offsets, counted before the build: 100³ nodes, 12,731,796 links.
    const std::string soft = refusal("description = \"d\"\n[[soft_bodies]]\nnx = 100\nny = 100\nnz = 100\n");
    EXPECT_NE(soft.find("soft_bodies[0] would make 12731796 links on 1000000 nodes"), std::string::npos) << soft;
}

// Backward Euler on springs: 150 µs a particle + 1 ns a flop of the symbolic
// count, at most a second a frame. A 40² cloth (1600 nodes, 9.8e7 flops):
// 0.34 s; an 80² one (6400 nodes: 0.96 s before a flop): refused, and so is
// the 40² one at four substeps.
TEST(WorkLimits, BackwardEulerCountsItsSparseFactorization) {
    auto cloth = [](int n, int substeps) {
        return "description = \"d\"\n[step]\nintegrator = \"backward_euler\"\nsubsteps = " + std::to_string(substeps) +
               "\n[[cloths]]\nnx = " + std::to_string(n) + "\nny = " + std::to_string(n) + "\nshear = 1\nbend = 0.5\n";
    };
    EXPECT_EQ(refusal(cloth(40, 1)), "");
    const std::string big = refusal(cloth(80, 1));
    EXPECT_NE(big.find("galaxy.toml:3:14: step.integrator = \"backward_euler\" factors the springs' sparse system "
                       "every substep: 37602 springs on 6400 particles make a factorization of "),
              std::string::npos)
        << big;
    EXPECT_NE(refusal(cloth(40, 4)).find("x 4 substeps"), std::string::npos);
    // The same cloth held by constraints has no springs to factor.
    EXPECT_EQ(refusal(cloth(80, 1) + "link = \"constraints\"\n"), "");
}

// The linear work of a frame, times the substeps: 10⁵ particles at 5 ns each
// are 0.5 s a frame at 1000 substeps, 5 s at 10,000.
TEST(WorkLimits, AFrameOfLinearWorkStopsAtASecond) {
    auto group = [](int substeps) {
        return "description = \"d\"\n[step]\nsubsteps = " + std::to_string(substeps) +
               "\n[[groups]]\ncount = 100000\nspacing = [0.01, 0, 0]\n";
    };
    EXPECT_EQ(refusal(group(1000)), "");
    const std::string slow = refusal(group(10'000));
    EXPECT_NE(slow.find("galaxy.toml:3:12: a frame of 10000 substeps over 100000 particles would take about 5 s; at "
                        "most 1 s a frame"),
              std::string::npos)
        << slow;
}

// ODE's exact step solves a jointed island as one dense LCP, about rows³ at
// 0.6 ns: a chain of 400 ball-jointed links (400 joints, 1200 rows) is
// 1.04 s a frame and refused; 300 links (900 rows) 0.44 s; with quickstep
// (the default) neither is anywhere near.
TEST(WorkLimits, OdesExactStepCountsItsIslandsRowsCubed) {
    auto chain = [](int links, bool quickstep) {
        return "description = \"d\"\n[rigid]\nquickstep = " + std::string(quickstep ? "true" : "false") +
               "\n[[chains]]\nanchor = [0, 50, 0]\nlinks = " + std::to_string(links) +
               "\nlink_length = 0.05\nradius = 0.01\n";
    };
    EXPECT_EQ(refusal(chain(300, false)), "");
    EXPECT_EQ(refusal(chain(400, true)), "");
    const std::string exact = refusal(chain(400, false));
    EXPECT_NE(exact.find("rows³ of ODE's exact step would take about 1 s; at most 1 s a frame"), std::string::npos)
        << exact;
}

// Bodies no joint holds join one island through their contacts, four of
// three rows each: wrecking-ball's wall of twelve bricks ran 1.43 ms a
// substep at 400 substeps (5.7 s a frame at 4000, which the mutation sweep
// found let through); refused there, and not at 400.
TEST(WorkLimits, OdesExactStepCountsTheContactsOfFreeBodies) {
    auto wrecking_ball = [](int substeps) {
        try {
            load_scene(resolve_scene("wrecking-ball"), {{"step.substeps", std::to_string(substeps)}});
            return std::string();
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
    };
    EXPECT_EQ(wrecking_ball(400), "");
    EXPECT_NE(wrecking_ball(4000).find("rows³ of ODE's exact step would take about"), std::string::npos)
        << wrecking_ball(4000);
}

}  // namespace
}  // namespace scenes
