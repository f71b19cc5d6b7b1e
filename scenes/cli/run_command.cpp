// `plausible run SCENE`: the scene headless to its end, then a summary (text,
// or one JSON object with --json), and with --csv every object's state at
// every frame. Exit 1 when the watchdog stopped the run.
#include "scenes/cli/commands.h"
#include "scenes/model/recording.h"

#include "scenes/common/interrupt.h"
#include "scenes/common/output_file.h"
#include "scenes/common/progress.h"
#include "scenes/draw/run_recorder.h"
#include "scenes/draw/scene_run.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

namespace scenes::cli {

namespace {

namespace fs = std::filesystem;

struct RunArgs {
    SceneOptions scene;
    std::optional<std::string> csv;
    std::optional<std::string> record;
    bool json = false;
};

// --csv FILE: one row per object per frame, written to a temporary file and
// renamed at the end, so that an error or Ctrl+C leaves nothing behind.
class CsvWriter {
public:
    // bodies: the scene has rigid bodies, whose rows carry their orientation,
    // angular velocity, mass and inertia in fourteen more columns (empty on
    // particle rows): enough to compute energy and momentum from the file.
    CsvWriter(const std::string& path, bool bodies) : file_(path), bodies_(bodies) {
        out_.open(file_.temporary(), std::ios::binary);
        if (!out_) throw file_.error(std::strerror(errno));
        out_ << "frame,time,kind,id,x,y,z,vx,vy,vz"
             << (bodies_ ? ",qw,qx,qy,qz,wx,wy,wz,mass,ixx,iyy,izz,ixy,ixz,iyz" : "") << '\n';
        out_.precision(17);
    }
    CsvWriter(const CsvWriter&) = delete;
    CsvWriter& operator=(const CsvWriter&) = delete;

    void rows(const SceneRun& run) {
        const sim::ParticleState& s = run.world().state();
        for (std::size_t i = 0; i < s.size(); ++i) {
            row(run.frame(), s.t, "particle", i, s.x.get(i), s.v.get(i));
            out_ << (bodies_ ? ",,,,,,,,,,,,,,\n" : "\n");
        }
        if (const sim::RigidWorld* rigid = run.world().rigid()) {
            const auto ids = rigid->bodies();
            for (std::size_t k = 0; k < ids.size(); ++k) {
                const sim::BodyState b = rigid->state(ids[k]);
                row(run.frame(), s.t, "body", k, b.position, b.velocity);
                const Eigen::Quaterniond& q = b.orientation;
                const sim::Vec3& w = b.angular_velocity;
                const Eigen::Matrix3d I = rigid->inertia(ids[k]);
                out_ << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << w.x() << ',' << w.y()
                     << ',' << w.z() << ',' << rigid->mass(ids[k]) << ',' << I(0, 0) << ',' << I(1, 1) << ',' << I(2, 2)
                     << ',' << I(0, 1) << ',' << I(0, 2) << ',' << I(1, 2) << '\n';
            }
        }
        if (!out_) throw file_.error(std::strerror(errno));  // the disk full: stop now, not at the end
    }
    // Renames the finished file into place.
    void commit() {
        out_.close();
        if (!out_) throw file_.error(std::strerror(errno));
        file_.commit();
    }

private:
    void row(int frame, double t, const char* kind, std::size_t id, const sim::Vec3& x, const sim::Vec3& v) {
        out_ << frame << ',' << t << ',' << kind << ',' << id << ',' << x.x() << ',' << x.y() << ',' << x.z() << ','
             << v.x() << ',' << v.y() << ',' << v.z();
    }
    OutputFile file_;
    bool bodies_ = false;
    std::ofstream out_;
};

// The energy over a run, J: at the start, and its range over every frame.
struct EnergyRange {
    double initial = 0.0, min = 0.0, max = 0.0;
    explicit EnergyRange(double e0) : initial(e0), min(e0), max(e0) {}
    void add(double e) { min = std::min(min, e), max = std::max(max, e); }
};

// Steps the run to the scene's end (or the watchdog's stop), writing every
// frame's rows to `csv` when there is one; returns the energy range. On a
// terminal a progress bar on stderr says how far it is and how long is left
// (a large scene runs for minutes; without it a run looks hung).
EnergyRange run_to_end(SceneRun& run, int frames, CsvWriter* csv, RunRecorder* recorder) {
    EnergyRange energy(run.world().energy());
    if (csv) csv->rows(run);
    if (recorder) recorder->frame(run);
    Progress progress("run", progress_wanted(), frames);
    while (run.frame() < frames && run.advance()) {
        energy.add(run.world().energy());
        if (csv) csv->rows(run);
        if (recorder) recorder->frame(run);
        if (interrupt_signal() != 0) check_interrupt("run --csv", "frame " + std::to_string(run.frame()));
        progress.step([&] { return "frame " + std::to_string(run.frame()); });
    }
    if (run.verdict().exploded()) {
        if (csv) csv->rows(run);
        if (recorder) recorder->frame(run);
        energy.add(run.world().energy());
    }
    if (csv) check_interrupt("run --csv", "the last frame");
    return energy;
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
nlohmann::json vector(const sim::Vec3& v) { return {number(v.x()), number(v.y()), number(v.z())}; }

// The rigid bodies' totals at one frame: what --json reports at the first and
// the last, so that a run's drift in them can be read without the CSV.
struct RigidTotals {
    double energy = 0.0;                     // J, kinetic + potential
    sim::Vec3 momentum = sim::Vec3::Zero();  // kg·m/s
    sim::Vec3 angular = sim::Vec3::Zero();   // kg·m²/s, about the world origin
    explicit RigidTotals(const sim::RigidWorld& w)
        : energy(w.kinetic_energy() + w.potential_energy()), momentum(w.momentum()), angular(w.angular_momentum()) {}
};
double finite_or_nan(double v) { return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN(); }

// ms per step of each system the World runs (docs/design.md: one entry per
// system in `systems`, and the total), measured on the sampled frames
// (World::SystemTimes); the entries partition the step, the total is the
// whole step with the glue between systems. null where no frame was sampled
// (a run of one frame: the first is not timed).
nlohmann::json ms_per_system(const sim::World& world) {
    const auto& times = world.times();
    auto ms = [&](double seconds) {
        return times.sampled_frames == 0 ? nlohmann::json(nullptr) : nlohmann::json(times.ms_per_step(seconds));
    };
    nlohmann::json per_system = nlohmann::json::object();
    for (const std::string& system : world.systems().names()) per_system[system] = ms(times.of(system));
    per_system["total"] = ms(times.total);
    return per_system;
}

// The first ghost's distance from its closed form now, m (none without a ghost).
std::optional<double> ghost_error(const SceneDef& scene, const SceneRun& run) {
    if (scene.ghosts.empty()) return std::nullopt;
    const Ghost& g = scene.ghosts.front();
    const sim::World& world = run.world();
    const sim::Vec3 x = g.body >= 0 ? world.rigid()->state({static_cast<std::uint32_t>(g.body), 0}).position
                                    : world.state().x.get(g.particle);
    return (x - g.exact(run.time()).x).norm();
}

// What both summaries report.
struct Summary {
    const SceneDef& scene;
    const SceneRun& run;
    EnergyRange energy;
    double final_energy = 0.0;  // J
    nlohmann::json ms_per_step;
    std::optional<double> error;  // m, see ghost_error
    std::optional<RigidTotals> rigid_first, rigid_last;
};

nlohmann::json verdict_json(const sim::Verdict& verdict, const std::string& scene) {
    if (!verdict.exploded()) return {{"status", "ok"}};
    return {{"status", "exploded"},
            {"frame", verdict.frame},
            {"quantity", verdict.quantity},
            {"index", verdict.index},
            {"value", number(verdict.value)},
            {"limit", number(verdict.limit)},
            {"message", verdict.message(scene)}};
}

void print_json(const Summary& s) {
    const sim::World& world = s.run.world();
    nlohmann::json j;
    j["scene"] = s.scene.name;
    j["integrator"] = sim::integrator_info(s.scene.step.integrator).name;
    j["dt"] = s.scene.step.dt;
    j["substeps"] = s.scene.step.substeps;
    j["steps"] = world.steps();
    j["frames"] = s.run.frame();
    j["sim_time"] = number(s.run.time());
    j["systems"] = world.systems().names();
    j["state_hash"] = s.run.state_hash_hex();
    j["energy"] = {{"initial", number(s.energy.initial)},
                   {"final", number(s.final_energy)},
                   {"min", number(s.energy.min)},
                   {"max", number(s.energy.max)}};
    j["verdict"] = verdict_json(s.run.verdict(), s.scene.name);
    j["ms_per_step"] = s.ms_per_step;
    nlohmann::json contained = nlohmann::json::array();
    for (const auto& c : world.contained()) {
        contained.push_back({{"name", c.name},
                             {"frame", c.verdict.frame},
                             {"quantity", c.verdict.quantity},
                             {"index", c.verdict.index},
                             {"value", number(c.verdict.value)},
                             {"message", c.verdict.message(s.scene.name + ": " + c.name)}});
    }
    if (!contained.empty()) j["contained"] = contained;
    j["force_evaluations"] = world.force_evaluations();
    if (s.error) j["position_error"] = number(*s.error);
    if (world.rigid() != nullptr) j["solver_messages"] = world.rigid()->solver_messages();
    if (s.rigid_first && s.rigid_last) {
        const RigidTotals &a = *s.rigid_first, &b = *s.rigid_last;
        j["rigid"] = {{"energy", {{"first", number(a.energy)}, {"last", number(b.energy)}}},
                      {"momentum", {{"first", vector(a.momentum)}, {"last", vector(b.momentum)}}},
                      {"angular_momentum", {{"first", vector(a.angular)}, {"last", vector(b.angular)}}}};
    }
    std::cout << j.dump() << "\n";
}

void print_text(const Summary& s) {
    const SceneDef& scene = s.scene;
    const sim::World& world = s.run.world();
    const std::string integrator(sim::integrator_info(scene.step.integrator).name);
    std::printf("%s: %s of %s, dt %s x %s, t = %.4g s\n", scene.name.c_str(), counted(s.run.frame(), "frame").c_str(),
                integrator.c_str(), format_dt(scene.step.dt).c_str(), counted(scene.step.substeps, "substep").c_str(),
                s.run.time());
    const double e0 = s.energy.initial;
    const double drift = e0 != 0.0 ? 100.0 * (s.final_energy - e0) / std::abs(e0) : 0.0;
    std::printf("  energy    initial %.6g J, final %.6g J (%+.3g%%), range [%.6g, %.6g] J\n", e0,
                finite_or_nan(s.final_energy), drift, s.energy.min, s.energy.max);
    if (s.error) {
        const Ghost& g = scene.ghosts.front();
        const std::string& who = g.body >= 0 ? scene.body_names[static_cast<std::size_t>(g.body)] + "'s centre of mass"
                                             : scene.particle_names[g.particle];
        std::printf("  accuracy  %s is %.3e m from the %s closed form\n", who.c_str(), *s.error, g.solution.c_str());
    }
    if (s.ms_per_step["total"].is_null()) {
        std::printf("  cost      %.0f force evaluations (one frame: not timed)\n", world.force_evaluations());
    } else {
        std::printf("  cost      %.0f force evaluations, %.3g ms per step (", world.force_evaluations(),
                    s.ms_per_step["total"].get<double>());
        bool first = true;
        for (const auto& [system, v] : s.ms_per_step.items()) {
            if (system == "total") continue;
            std::printf("%s%s %.3g", first ? "" : ", ", system.c_str(), v.get<double>());
            first = false;
        }
        std::printf(")\n");
    }
    for (const auto& c : world.contained()) {
        std::printf("  contained %s (frozen; the run went on)\n",
                    c.verdict.message(scene.name + ": " + c.name).c_str());
    }
    if (world.rigid() != nullptr) {
        for (const std::string& said : world.rigid()->solver_messages()) std::printf("  ODE said  %s\n", said.c_str());
    }
    std::printf("  state     hash %s\n", s.run.state_hash_hex().c_str());
    if (s.run.verdict().exploded()) std::printf("%s\n", s.run.verdict().message(scene.name).c_str());
}

int run_scene(const RunArgs& args) {
    const SceneDef scene = args.scene.load();
    SceneRun run(scene);
    // Ctrl+C while the CSV is being written: stop at the next frame and
    // remove it (a run without --csv writes nothing and keeps the default).
    std::optional<InterruptScope> interrupts;
    std::optional<CsvWriter> csv;
    if (args.csv) interrupts.emplace(), csv.emplace(*args.csv, !scene.model.rigid.bodies.empty());
    std::optional<RunRecorder> recorder;
    // Refused before the run: a path that cannot be written, a run too long to record.
    if (args.record) check_output(*args.record), recorder.emplace(run, scene.frames);
    std::optional<RigidTotals> rigid_first;
    if (const sim::RigidWorld* rigid = run.world().rigid()) rigid_first.emplace(*rigid);
    const EnergyRange energy = run_to_end(run, scene.frames, csv ? &*csv : nullptr, recorder ? &*recorder : nullptr);
    if (csv) csv->commit();
    std::string recorded;  // what was written, and its size
    if (recorder) {
        const Recording& rec = recorder->recording();
        write_recording(*args.record, rec);
        char text[64];
        std::snprintf(text, sizeof text, "%.2f MiB", static_cast<double>(fs::file_size(*args.record)) / (1 << 20));
        recorded = "recorded " + *args.record + ": " + counted(rec.frames, "frame") + ", " +
                   counted(static_cast<long long>(rec.states.size()), "state") + " (every " +
                   (rec.every == 1 ? std::string("frame") : counted(rec.every, "frame")) + "), " + text;
    }
    std::optional<RigidTotals> rigid_last;
    if (const sim::RigidWorld* rigid = run.world().rigid()) rigid_last.emplace(*rigid);
    const Summary summary{
        scene,       run,       energy, run.world().energy(), ms_per_system(run.world()), ghost_error(scene, run),
        rigid_first, rigid_last};
    if (args.json) {
        print_json(summary);
        if (!recorded.empty()) std::fprintf(stderr, "%s\n", recorded.c_str());  // stdout is the JSON
    } else {
        print_text(summary);
        if (!recorded.empty()) std::printf("%s\n", recorded.c_str());
    }
    const int replay = report_replay(scene, run.diverged_frame(), run.frame());
    return run.verdict().exploded() ? kExitFailed : replay;
}

}  // namespace

Command add_run(CLI::App& app) {
    auto args = std::make_shared<RunArgs>();
    CLI::App* run = app.add_subcommand("run", "Run a scene headless and print a summary");
    run->add_option("scene", args->scene.scene,
                    "Scene name (see `plausible list`), path of a .toml file, or a recording (--record; a regular file "
                    "of at most 128 MiB)")
        ->required();
    args->scene.add_to(run);
    run->add_option("--csv", args->csv,
                    "Write frame,time,kind,id,x,y,z,vx,vy,vz per particle and rigid body per frame (s, m, m/s; a "
                    "body's x is its centre of mass); with rigid bodies also qw,qx,qy,qz,wx,wy,wz,mass,ixx,iyy,izz,"
                    "ixy,ixz,iyz: a body's orientation (unit quaternion, body to world), angular velocity (rad/s, "
                    "world frame), mass (kg) and inertia tensor about its centre of mass in its own frame "
                    "(kg m2), empty on particle rows");
    run->add_option("--record", args->record,
                    "Write the run as a recording: the scene, the state hash after every frame (8 bytes a "
                    "frame) and the state every K frames (K grows with the run: the states stay within 2 MB, "
                    "or are the first alone where it is larger); it says its size when written. At most 128 "
                    "MiB: a run whose recording could be larger is refused before it runs (exit 2). render, "
                    "video, view, check and run take it as a scene and replay it, reporting the first frame "
                    "whose state differs (exit 1)");
    run->add_flag("--json", args->json,
                  "Print one JSON object: the scene, its step, the final state hash, energy, the watchdog's "
                  "verdict, and ms_per_step, the step's time (total) and each system's, sampled on a few frames "
                  "(null for a run of one frame). With rigid bodies, rigid: their "
                  "energy (J), momentum (kg m/s) and angular momentum about the origin (kg m2/s) at the first "
                  "and the last frame");
    return {run, [args] { return run_scene(*args); }};
}

}  // namespace scenes::cli
