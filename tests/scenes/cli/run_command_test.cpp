// `plausible run --csv` through the real command: with rigid bodies, each
// body's row also carries its orientation (a unit quaternion) and angular
// velocity, the existing columns in their order; the quaternion turns from
// frame to frame as the angular velocity says; and the columns show what a
// teacher plots from them, the Dzhanibekov flip of the inertia scene (the
// spin about the intermediate axis reverses in the body's frame, those about
// the smallest and largest axes keep their sign); with each body's mass and
// inertia, energy and momentum come from the CSV alone and agree with
// `run --json`'s. And `run --json`'s timing of a run too short to sample.
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
    Eigen::Vector3d w;        // rad/s, world frame
    Eigen::Vector3d x, v;     // m, m/s
    double mass = 0.0;        // kg
    Eigen::Matrix3d inertia;  // kg·m², body frame
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
    EXPECT_EQ(lines[0], "frame,time,kind,id,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,mass,ixx,iyy,izz,ixy,ixz,iyz")
        << "old columns first, in order";
    std::map<int, std::vector<BodyRow>> bodies;  // by id, frame by frame
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> c = split(lines[i]);
        ASSERT_EQ(c.size(), 24u) << lines[i];
        ASSERT_EQ(c[2], "body") << "the inertia scene has no particles";
        auto d = [&](int k) { return std::stod(c[static_cast<std::size_t>(k)]); };
        BodyRow row{Eigen::Quaterniond(d(10), d(11), d(12), d(13)),
                    Eigen::Vector3d(d(14), d(15), d(16)),
                    Eigen::Vector3d(d(4), d(5), d(6)),
                    Eigen::Vector3d(d(7), d(8), d(9)),
                    d(17),
                    Eigen::Matrix3d::Zero()};
        row.inertia << d(18), d(21), d(22), d(21), d(19), d(23), d(22), d(23), d(20);
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

// Energy, momentum and angular momentum from the CSV's columns alone, at the
// first and last frame, against what `run --json` reports for the same run
// (the inertia scene: zero gravity, so the energy is kinetic).
TEST_F(RunCsv, EnergyAndMomentumFromTheCsvAloneMatchRunJson) {
    constexpr int kFrames = 120;
    const std::vector<std::string> lines = csv("inertia", kFrames);
    ASSERT_GT(lines.size(), 1u);
    struct Totals {
        double energy = 0.0;                          // J
        Eigen::Vector3d p = Eigen::Vector3d::Zero();  // kg·m/s
        Eigen::Vector3d l = Eigen::Vector3d::Zero();  // kg·m²/s, about the origin
    };
    std::map<int, Totals> by_frame;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> c = split(lines[i]);
        ASSERT_EQ(c.size(), 24u) << lines[i];
        auto d = [&](int k) { return std::stod(c[static_cast<std::size_t>(k)]); };
        const double m = d(17);
        Eigen::Matrix3d I;
        I << d(18), d(21), d(22), d(21), d(19), d(23), d(22), d(23), d(20);
        const Eigen::Matrix3d R = Eigen::Quaterniond(d(10), d(11), d(12), d(13)).toRotationMatrix();
        const Eigen::Vector3d x(d(4), d(5), d(6)), v(d(7), d(8), d(9)), w(d(14), d(15), d(16));
        const Eigen::Matrix3d Iw = R * I * R.transpose();  // kg·m², world frame
        Totals& t = by_frame[std::stoi(c[0])];
        t.energy += 0.5 * m * v.squaredNorm() + 0.5 * w.dot(Iw * w);
        t.p += m * v;
        t.l += x.cross(m * v) + Iw * w;
    }
    const test::Ran r = test::run({PLAUSIBLE_EXE, "run", "inertia", "--frames", std::to_string(kFrames), "--json"});
    ASSERT_EQ(r.status, 0) << r.out;
    const nlohmann::json rigid = nlohmann::json::parse(r.out).at("rigid");
    for (const auto& [when, frame] : {std::pair<const char*, int>{"first", 0}, {"last", kFrames}}) {
        const Totals& t = by_frame.at(frame);
        ASSERT_GT(t.energy, 1.0) << "J: the handles spin";
        EXPECT_NEAR(rigid["energy"][when].get<double>(), t.energy, 1e-12 * t.energy) << when << " frame, J";
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(rigid["momentum"][when][k].get<double>(), t.p[k], 1e-12) << when << " frame, kg·m/s";
            EXPECT_NEAR(rigid["angular_momentum"][when][k].get<double>(), t.l[k], 1e-12 * t.l.norm())
                << when << " frame, kg·m²/s";
        }
    }
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
