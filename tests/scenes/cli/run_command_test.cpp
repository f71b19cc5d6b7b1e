// `plausible run --csv` through the real command: with rigid bodies, each
// body's row also carries its orientation (a unit quaternion) and angular
// velocity, the existing columns in their order; the quaternion turns from
// frame to frame as the angular velocity says; and the columns show what a
// teacher plots from them, the Dzhanibekov flip of the inertia scene (the
// spin about the intermediate axis reverses in the body's frame, those about
// the smallest and largest axes keep their sign). And `run --json`'s timing
// of a run too short to sample.
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
}

struct BodyRow {
    Eigen::Quaterniond q;
    Eigen::Vector3d w;  // rad/s, world frame
};

class RunCsv : public ::testing::Test {
protected:
    // The CSV's lines, after `plausible run SCENE --frames N --csv`.
    std::vector<std::string> csv(const std::string& scene, int frames) {
        const fs::path file = dir_ / (scene + ".csv");
        const test::Ran r = test::shell(std::string(PLAUSIBLE_EXE) + " run " + scene + " --frames " +
                                        std::to_string(frames) + " --csv " + file.string());
        EXPECT_EQ(r.status, 0) << r.out;
        std::vector<std::string> lines;
        std::ifstream in(file);
        for (std::string line; std::getline(in, line);) lines.push_back(line);
        return lines;
    }
    test::TempDir temp_{"plausible-run-csv"};
    const fs::path& dir_ = temp_.path();
};

TEST_F(RunCsv, ParticleScenesKeepTheirColumns) {
    const std::vector<std::string> lines = csv("ballistic", 2);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines[0], "frame,time,kind,id,x,y,z,vx,vy,vz");
    EXPECT_EQ(split(lines[1]).size(), 10u);
}

TEST_F(RunCsv, BodyRowsCarryOrientationAndAngularVelocity) {
    constexpr int kFrames = 600;  // the inertia scene's 10 s
    const std::vector<std::string> lines = csv("inertia", kFrames);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines[0], "frame,time,kind,id,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz") << "old columns first, in order";
    std::map<int, std::vector<BodyRow>> bodies;  // by id, frame by frame
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> c = split(lines[i]);
        ASSERT_EQ(c.size(), 17u) << lines[i];
        ASSERT_EQ(c[2], "body") << "the inertia scene has no particles";
        const BodyRow row{Eigen::Quaterniond(std::stod(c[10]), std::stod(c[11]), std::stod(c[12]), std::stod(c[13])),
                          Eigen::Vector3d(std::stod(c[14]), std::stod(c[15]), std::stod(c[16]))};
        EXPECT_NEAR(row.q.norm(), 1.0, 1e-12) << "a unit quaternion: " << lines[i];
        bodies[std::stoi(c[3])].push_back(row);
    }
    ASSERT_EQ(bodies.size(), 3u);
    const double h = 1.0 / 60.0;  // s, the scene's frame
    for (const auto& [id, rows] : bodies) {
        ASSERT_EQ(rows.size(), static_cast<std::size_t>(kFrames + 1));
        // The turn from one frame's orientation to the next, as a rotation
        // vector over h, against the angular velocity: the step turns the
        // body by the angular velocities it reaches within the frame, so
        // the turn lies within half the frame's change of w of the mean of
        // its two ends, to O(h²) (here 2e-3 rad/s at |w| ~ 5 rad/s). A w in
        // the body's frame, or in degrees, misses by whole rad/s.
        double worst = 0.0;  // rad/s, beyond that bound
        for (std::size_t f = 0; f + 1 < rows.size(); ++f) {
            const Eigen::AngleAxisd turn(rows[f + 1].q * rows[f].q.conjugate());
            const Eigen::Vector3d turned = turn.angle() * turn.axis() / h;  // rad/s
            const Eigen::Vector3d mean = 0.5 * (rows[f].w + rows[f + 1].w);
            const double within = 0.5 * (rows[f + 1].w - rows[f].w).norm();
            worst = std::max(worst, (turned - mean).norm() - within);
        }
        EXPECT_LT(worst, 2e-3) << "body " << id << ": the quaternion turns as w says (rad/s)";
    }
    // In each body's own frame, the spin about its first axis: the
    // intermediate one (body 1, spun about its x) flips; the others keep
    // their sign about y (body 0) and z (body 2).
    auto flips = [&](int id, int axis) {
        int sign_changes = 0;
        double before = 0.0;
        for (const BodyRow& r : bodies[id]) {
            const double spin = (r.q.conjugate() * r.w)[axis];  // rad/s, body frame
            if (before != 0.0 && spin * before < 0.0) ++sign_changes;
            before = spin;
        }
        return sign_changes;
    };
    EXPECT_GE(flips(1, 0), 2) << "the Dzhanibekov flip: the intermediate axis reverses, and back";
    EXPECT_EQ(flips(0, 1), 0) << "the smallest axis is stable";
    EXPECT_EQ(flips(2, 2), 0) << "the largest axis is stable";
}

// `run --json`'s ms_per_step: the first frame is not timed (it pays once for
// what the later ones reuse), so a run of one frame has no figure, null
// rather than a 0 that would read as "free"; from the second frame on, a
// figure for the whole step.
TEST(RunJson, AOneFrameRunHasNoTimingAndALongerOneHas) {
    const test::Ran one = test::shell(std::string(PLAUSIBLE_EXE) + " run oscillator --frames 1 --json");
    ASSERT_EQ(one.status, 0) << one.out;
    EXPECT_NE(one.out.find(R"("ms_per_step":{"particles":null,"springs":null,"total":null,"watchdog":null})"),
              std::string::npos)
        << one.out;
    const test::Ran two = test::shell(std::string(PLAUSIBLE_EXE) + " run oscillator --frames 2 --json");
    ASSERT_EQ(two.status, 0) << two.out;
    const std::size_t total = two.out.find(R"("total":)");
    ASSERT_NE(total, std::string::npos) << two.out;
    EXPECT_GT(std::strtod(two.out.c_str() + total + 8, nullptr), 0.0) << "ms, " << two.out;
}

}  // namespace
