// `plausible view` (see view.h). Sections:
//   1. the orbit camera and mouse rays
//   2. picking: what the cursor is on
//   3. the viewer: state, input, stepping, drawing, the panel
//   4. run_viewer: the loop
#include "scenes/view/view.h"

#include "render/gl_context.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scenes/draw/scene_run.h"
#include "sim/error.h"
#include "sim/integrators.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

namespace scenes {
namespace {

using Clock = std::chrono::steady_clock;
using render::Vec3;

// --- 1. the orbit camera and mouse rays ------------------------------------------

// The scene's camera as a point orbiting its target: yaw about +y, pitch
// above the horizon, distance; orthographic scenes zoom by their height.
struct Orbit {
    render::Camera base;  // the scene's camera (C goes back to it)
    Vec3 target = Vec3::Zero();
    float yaw = 0.0f;                          // rad
    float pitch = 0.0f;                        // rad, within ±kMaxPitch
    static constexpr float kMaxPitch = 1.48f;  // rad (85°): never straight down, where "up" is undefined
    float distance = 1.0f;                     // m
    float ortho_height = 4.0f;

    explicit Orbit(const render::Camera& camera) : base(camera) { reset(); }

    void reset() {
        target = base.target;
        const Vec3 d = base.eye - base.target;
        distance = std::max(1e-3f, d.norm());
        pitch = std::clamp(std::asin(std::clamp(d.y() / distance, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
        yaw = std::atan2(d.x(), d.z());
        ortho_height = base.ortho_height;
    }
    render::Camera camera() const {
        render::Camera c = base;
        c.target = target;
        c.eye =
            target + distance * Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
        c.up = Vec3::UnitY();
        c.ortho_height = ortho_height;
        return c;
    }
    void rotate(float dx, float dy) {        // px of mouse motion
        constexpr float kRadPerPx = 0.008f;  // rad per px of mouse motion: 400 px turn ~180°
        yaw -= kRadPerPx * dx;
        pitch = std::clamp(pitch + kRadPerPx * dy, -kMaxPitch, kMaxPitch);
    }
    void pan(float dx, float dy, int height) {  // px
        const render::Camera c = camera();
        const Vec3 forward = (c.target - c.eye).normalized();
        const Vec3 right = forward.cross(Vec3::UnitY()).normalized();
        const Vec3 up = right.cross(forward);
        const float metres_per_px = c.projection == render::Camera::Projection::orthographic
                                        ? ortho_height / static_cast<float>(height)
                                        : 2.0f * distance *
                                              std::tan(0.5f * c.fov_y_deg * std::numbers::pi_v<float> / 180.0f) /
                                              static_cast<float>(height);
        target += metres_per_px * (-dx * right + dy * up);
    }
    void zoom(float steps) {                     // wheel clicks, + is closer
        const float f = std::pow(0.88f, steps);  // 12% closer per wheel click
        distance = std::clamp(distance * f, 0.05f, 500.0f);
        ortho_height = std::clamp(ortho_height * f, 0.05f, 500.0f);
    }
};

struct Ray {
    Eigen::Vector3d origin;
    Eigen::Vector3d direction;  // unit
};

// The ray through pixel (px, py) of a width x height image (y down).
Ray mouse_ray(const render::Camera& camera, int width, int height, double px, double py) {
    const Eigen::Matrix4f m =
        (render::projection_matrix(camera, static_cast<float>(width) / static_cast<float>(height)) *
         render::view_matrix(camera))
            .inverse();
    const float nx = static_cast<float>(2.0 * px / width - 1.0), ny = static_cast<float>(1.0 - 2.0 * py / height);
    auto unproject = [&](float z) {
        const Eigen::Vector4f p = m * Eigen::Vector4f(nx, ny, z, 1.0f);
        return Eigen::Vector3d((p.head<3>() / p.w()).cast<double>());
    };
    const Eigen::Vector3d a = unproject(-1.0f), b = unproject(1.0f);
    return {a, (b - a).normalized()};
}

// --- 2. picking ------------------------------------------------------------------

struct Pick {
    sim::Drag drag;
    double depth = 0.0;  // m along the ray
};

// The nearest particle or body part the ray passes within reach of (its
// 1.5 radii, at least 6 cm): particles that move, and rigid bodies.
std::optional<Pick> pick(const SceneRun& run, const Ray& ray) {
    std::optional<Pick> best;
    auto consider = [&](const Eigen::Vector3d& centre, double reach, sim::Drag::Kind kind, std::uint32_t index) {
        const double t = (centre - ray.origin).dot(ray.direction);
        if (t <= 0.0) return;
        const double miss = (ray.origin + t * ray.direction - centre).norm();
        if (miss > reach || (best && t >= best->depth)) return;
        Pick p;
        p.drag.kind = kind;
        p.drag.index = index;
        p.drag.target = ray.origin + t * ray.direction;
        p.depth = t;
        best = p;
    };
    const sim::World& world = run.world();
    const sim::ParticleState& s = world.state();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.inv_mass[i] == 0.0) continue;
        const double r = run.scene().looks[i].radius;
        consider(s.x.get(i), std::max(1.5 * r, 0.06), sim::Drag::Kind::particle, static_cast<std::uint32_t>(i));
    }
    if (const sim::RigidWorld* rigid = world.rigid()) {
        for (const sim::PlacedPart& part : rigid->placed_parts()) {
            // A part's bounding sphere: boxes by their half diagonal, round parts by radius and half length.
            const double reach =
                part.shape == sim::RigidShape::box ? 0.5 * part.size.norm() : part.size.x() + 0.5 * part.size.y();
            consider(part.center, reach, sim::Drag::Kind::body, part.body.index);
        }
    }
    if (best && best->drag.kind == sim::Drag::Kind::body) {
        // Grab the point of the body where the ray came closest, in the body's frame.
        const sim::BodyState b = world.rigid()->state({best->drag.index, 0});
        best->drag.anchor = b.orientation.conjugate() * (best->drag.target - b.position);
    } else if (best) {
        best->drag.target = s.x.get(best->drag.index);
    }
    return best;
}

// --- 3. the viewer ---------------------------------------------------------------

// The shortest text that reads back as this float: a slider at 0.3 sets
// 0.3, not the double nearest 0.3f (0.30000001192092896).
std::string shortest(float value) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    return std::string(text, end);
}

// A rolling series for a live plot.
struct Series {
    std::deque<float> values;
    void push(float v, std::size_t keep = 300) {  // frames shown: 5 s at 60 Hz
        values.push_back(v);
        while (values.size() > keep) values.pop_front();
    }
    std::vector<float> data() const { return {values.begin(), values.end()}; }
};

class Viewer {
public:
    Viewer(const SceneDef& scene, std::vector<Override> overrides, const ViewOptions& options)
        : overrides_(std::move(overrides)),
          options_(options),
          def_(std::make_unique<SceneDef>(scene)),
          run_(std::make_unique<SceneRun>(*def_)),
          parameters_(scene_parameters(scene, overrides_)),
          orbit_(render_camera(scene.camera)),
          paused_(options.paused),
          panel_(options.panel) {
        edited_.reserve(parameters_.size());
        for (const Parameter& p : parameters_) edited_.push_back(static_cast<float>(p.value));
    }

    bool quit = false;
    bool screenshot_now = false;

    const SceneRun& run() const { return *run_; }
    bool running() const { return !paused_ && !run_->verdict().exploded(); }
    bool panel() const { return panel_; }

    void key(int key) {
        switch (key) {
            case GLFW_KEY_SPACE:
                paused_ = !paused_;
                break;
            case GLFW_KEY_RIGHT:
            case GLFW_KEY_PERIOD:
                step_once();
                break;
            case GLFW_KEY_LEFT:
            case GLFW_KEY_COMMA:
                step_back();
                break;
            case GLFW_KEY_R:
                reset();
                break;
            case GLFW_KEY_LEFT_BRACKET:
                time_scale_ = std::max(1.0f / 64.0f, 0.5f * time_scale_);
                break;
            case GLFW_KEY_RIGHT_BRACKET:
                time_scale_ = std::min(4.0f, 2.0f * time_scale_);
                break;
            case GLFW_KEY_I:
                next_integrator();
                break;
            case GLFW_KEY_H:
                panel_ = !panel_;
                break;
            case GLFW_KEY_C:
                orbit_.reset();
                break;
            case GLFW_KEY_P:
                screenshot_now = true;
                break;
            case GLFW_KEY_Q:
            case GLFW_KEY_ESCAPE:
                quit = true;
                break;
            default:
                break;
        }
    }

    void mouse_button(int button, bool down, double x, double y, int width, int height, bool shift) {
        if (!down) {
            if (button == GLFW_MOUSE_BUTTON_LEFT && grabbing_) release();
            mode_ = Mode::none;
            return;
        }
        last_x_ = x;
        last_y_ = y;
        if (button == GLFW_MOUSE_BUTTON_MIDDLE || (button == GLFW_MOUSE_BUTTON_RIGHT && shift)) {
            mode_ = Mode::pan;
        } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
            mode_ = Mode::orbit;
        } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
            const Ray ray = mouse_ray(orbit_.camera(), width, height, x, y);
            if (auto p = pick(*run_, ray)) {
                grab_ = *p;
                grabbing_ = true;
                mode_ = Mode::drag;
                run_->world_for_edit().set_drag(grab_.drag);
                std::printf("view: grabbed %s\n", grabbed_name().c_str());
                std::fflush(stdout);
            } else {
                mode_ = Mode::orbit;
            }
        }
    }

    void mouse_move(double x, double y, int width, int height) {
        const auto dx = static_cast<float>(x - last_x_), dy = static_cast<float>(y - last_y_);
        last_x_ = x;
        last_y_ = y;
        if (mode_ == Mode::orbit) orbit_.rotate(dx, dy);
        if (mode_ == Mode::pan) orbit_.pan(dx, dy, height);
        if (mode_ == Mode::drag && grabbing_) {
            // The target stays at the grabbed depth: on the plane through it facing the camera.
            const render::Camera c = orbit_.camera();
            const Eigen::Vector3d forward = (c.target - c.eye).normalized().cast<double>();
            const Ray ray = mouse_ray(c, width, height, x, y);
            const Eigen::Vector3d on_plane = grab_.drag.target;
            const double denom = ray.direction.dot(forward);
            if (std::abs(denom) > 1e-6) {
                const double t = (on_plane - ray.origin).dot(forward) / denom;
                if (t > 0) grab_.drag.target = ray.origin + t * ray.direction;
            }
            reapply_drag();
        }
    }

    void scroll(double steps) { orbit_.zoom(static_cast<float>(steps)); }

    // Advances by the wall time since the last frame (times the slow-motion
    // factor), in whole scene steps; or exactly one step per frame when
    // scripted (exit_after), so that frame N is the scene's frame N.
    void update(double wall_dt) {
        // A screenshot asked for shows the frame it was asked at (P then Space
        // in one poll still saves the paused frame).
        if (screenshot_now) return;
        if (paused_ || run_->verdict().exploded()) {
            accumulator_ = 0.0;
            return;
        }
        if (options_.exit_after > 0) {
            step_once(false);
            return;
        }
        accumulator_ += std::min(wall_dt, 0.1) * time_scale_;
        const double dt = run_->step().dt;
        // At most 8 steps a frame: a slow machine shows slow motion, not a spiral of death.
        for (int k = 0; k < 8 && accumulator_ >= dt; ++k) {
            step_once(false);
            accumulator_ -= dt;
        }
        accumulator_ = std::min(accumulator_, dt);
    }

    render::DrawList draw_list(int width, int height) const {
        render::DrawList list = run_->draw_list(width, height);
        list.camera = orbit_.camera();
        if (grabbing_) {
            // The mouse spring: a line from what is grabbed to the cursor.
            const render::Look look{render::Color{0.95f, 0.55f, 0.05f, 1}};
            const Eigen::Vector3d from = grabbed_point();
            list.cylinders.push_back(
                render::Cylinder{from.cast<float>(), grab_.drag.target.cast<float>(), 0.012f, look});  // 12 mm thick
            list.spheres.push_back(render::Sphere{grab_.drag.target.cast<float>(), 0.03f, look});      // 3 cm knob
        }
        return list;
    }

    void record_times(double render_ms) {
        // Per frame step since the last sampled one (World::SystemTimes
        // samples a light scene's frames, so several may share a figure).
        const sim::World::SystemTimes& t = run_->world().times();
        const std::array<double, 6> now{t.particles, t.constraints, t.collisions, t.plasticity, t.rigid, t.watchdog};
        const std::uint64_t sampled = t.sampled_frames - last_sampled_frames_;
        for (std::size_t k = 0; k < now.size(); ++k) {
            if (sampled > 0) last_ms_[k] = 1e3 * std::max(0.0, now[k] - last_times_[k]) / static_cast<double>(sampled);
            system_ms_[k].push(static_cast<float>(last_ms_[k]));
        }
        if (sampled > 0) last_times_ = now;
        last_sampled_frames_ = t.sampled_frames;
        render_ms_.push(static_cast<float>(render_ms));
        energy_.push(static_cast<float>(run_->world().energy()));
    }

    void panel_ui();

    // What went wrong in an input callback (they must not throw into GLFW):
    // printed, and shown in the panel.
    void report(const std::string& message) {
        std::fprintf(stderr, "view: %s\n", message.c_str());
        error_ = message;
    }

private:
    enum class Mode { none, orbit, pan, drag };

    void step_once(bool pause = true) {
        if (pause) paused_ = true;
        if (run_->verdict().exploded()) return;
        history_.push_back(run_->snapshot());
        history_bytes_ += history_.back().bytes();
        // Keep at most 3600 frames (a minute at 60 Hz) and about 256 MB of
        // history (trails included): the oldest go first.
        while (!history_.empty() && (history_.size() > 3600 || history_bytes_ > (256u << 20))) {
            history_bytes_ -= history_.front().bytes();
            history_.pop_front();
        }
        run_->advance();
    }

    void step_back() {
        paused_ = true;
        if (history_.empty()) return;
        run_->restore(history_.back());
        history_bytes_ -= history_.back().bytes();
        history_.pop_back();
        reapply_drag();
    }

    // Back to frame 0 with the live step settings (and the description as it is).
    void reset() { start(std::make_unique<SceneRun>(*def_)); }

    // Rebuilds the scene from its file with the panel's edits as overrides.
    // Nothing changes unless the new scene builds.
    void rebuild() {
        std::vector<Override> with = overrides_;
        for (std::size_t k = 0; k < parameters_.size(); ++k) {
            if (static_cast<float>(parameters_[k].value) == edited_[k]) continue;
            with.push_back({parameters_[k].key,
                            parameters_[k].integer ? std::to_string(std::lround(edited_[k])) : shortest(edited_[k])});
        }
        try {
            auto def = std::make_unique<SceneDef>(load_scene(def_->file, with));
            def->view = def_->view;  // the overlays chosen in the panel stay
            auto run = std::make_unique<SceneRun>(*def);
            run->set_step(run_->step());
            release();
            run_.reset();  // it refers to the old description
            def_ = std::move(def);
            start(std::move(run));
            error_.clear();
        } catch (const sim::InputError& e) {
            error_ = e.what();  // shown in the panel; the running scene stays as it was
        }
    }

    void start(std::unique_ptr<SceneRun> run) {
        if (run_) {
            run->set_step(run_->step());
            release();
        }
        run_ = std::move(run);
        history_.clear();
        history_bytes_ = 0;
        accumulator_ = 0.0;
        last_times_ = {};
        last_ms_ = {};
        last_sampled_frames_ = 0;
    }

    void next_integrator() {
        sim::StepSettings step = run_->step();
        const auto n = static_cast<int>(std::size(sim::kIntegrators));
        for (int k = 0; k < n; ++k) {
            if (sim::kIntegrators[static_cast<std::size_t>(k)].id == step.integrator) {
                step.integrator = sim::kIntegrators[static_cast<std::size_t>((k + 1) % n)].id;
                break;
            }
        }
        run_->set_step(step);
    }

    void release() {
        grabbing_ = false;
        if (run_) run_->world_for_edit().set_drag(std::nullopt);
    }
    // The grab again after a step back; let go when the world refuses it now
    // (a droplet not yet born at that time, a particle the watchdog froze).
    void reapply_drag() {
        if (!grabbing_) return;
        try {
            run_->world_for_edit().set_drag(grab_.drag);
        } catch (const sim::InputError&) {
            release();
        }
    }

    std::string grabbed_name() const {
        const std::uint32_t i = grab_.drag.index;
        if (grab_.drag.kind == sim::Drag::Kind::particle) {
            const std::string& name = def_->particle_names[i];
            return "particle " + std::to_string(i) + (name.empty() ? "" : " (" + name + ")");
        }
        const std::string& name = def_->body_names[i];
        return "body " + std::to_string(i) + (name.empty() ? "" : " (" + name + ")");
    }

    Eigen::Vector3d grabbed_point() const {
        const sim::World& w = run_->world();
        if (grab_.drag.kind == sim::Drag::Kind::particle) return w.state().x.get(grab_.drag.index);
        const sim::BodyState b = w.rigid()->state({grab_.drag.index, 0});
        return b.position + b.orientation * grab_.drag.anchor;
    }

    std::vector<Override> overrides_;
    ViewOptions options_;
    std::unique_ptr<SceneDef> def_;
    std::unique_ptr<SceneRun> run_;
    std::vector<Parameter> parameters_;
    std::vector<float> edited_;  // the sliders' values, one per parameter
    std::string error_;          // why the last rebuild was refused
    Orbit orbit_;
    bool paused_ = false;
    bool panel_ = true;
    float time_scale_ = 1.0f;   // simulated s per wall s
    double accumulator_ = 0.0;  // s of simulated time owed
    std::deque<SceneRun::Snapshot> history_;
    std::size_t history_bytes_ = 0;
    Mode mode_ = Mode::none;
    bool grabbing_ = false;
    Pick grab_;
    double last_x_ = 0.0, last_y_ = 0.0;
    Series energy_, render_ms_;
    std::array<Series, 6> system_ms_;
    std::array<double, 6> last_times_{};  // s, the world's times at the last sampled frame
    std::array<double, 6> last_ms_{};     // ms per frame step, the last figure
    std::uint64_t last_sampled_frames_ = 0;
};

void Viewer::panel_ui() {
    // Top right: the scene's own title and numbers are top left.
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 10, 10), ImGuiCond_FirstUseEver, ImVec2(1, 0));
    // As tall as its open sections, up to the window's height (then it scrolls).
    ImGui::SetNextWindowSizeConstraints(ImVec2(400, 0), ImVec2(400, io.DisplaySize.y - 20));
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (!ImGui::Begin("Plausible", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(210.0f);  // px; the rest of the row is the label
    ImGui::TextWrapped("%s", def_->description.c_str());
    ImGui::Text("frame %d   t = %.3f s", run_->frame(), run_->time());
    if (run_->verdict().exploded()) {
        ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "%s", run_->verdict().message(def_->name).c_str());
    }
    if (ImGui::Button(paused_ ? "Resume (Space)" : "Pause (Space)")) paused_ = !paused_;
    ImGui::SameLine();
    if (ImGui::Button("Step")) step_once();
    ImGui::SameLine();
    ImGui::BeginDisabled(history_.empty());
    if (ImGui::Button("Back")) step_back();
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (ImGui::Button("Reset")) reset();
    ImGui::Text("%zu stored states to step back through", history_.size());
    ImGui::SliderFloat("speed", &time_scale_, 1.0f / 64.0f, 4.0f, "%.3fx", ImGuiSliderFlags_Logarithmic);

    if (ImGui::CollapsingHeader("Step", ImGuiTreeNodeFlags_DefaultOpen)) {
        sim::StepSettings step = run_->step();
        bool changed = false;
        const char* current = sim::integrator_info(step.integrator).name.data();
        if (ImGui::BeginCombo("integrator", current)) {
            for (const auto& info : sim::kIntegrators) {
                if (ImGui::Selectable(info.name.data(), info.id == step.integrator)) {
                    step.integrator = info.id;
                    changed = true;
                }
            }
            ImGui::EndCombo();
        }
        auto dt_ms = static_cast<float>(1e3 * step.dt);
        constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;  // typed values too
        if (ImGui::SliderFloat("dt (ms)", &dt_ms, 0.1f, 100.0f, "%.2f", ImGuiSliderFlags_Logarithmic | kClamp)) {
            step.dt = 1e-3 * dt_ms;
            changed = true;
        }
        if (ImGui::SliderInt("substeps", &step.substeps, 1, 64, "%d", kClamp)) changed = true;
        if (changed) {
            try {
                run_->set_step(step);
            } catch (const sim::InputError& e) {
                error_ = e.what();
            }
        }
    }
    if (ImGui::CollapsingHeader("Overlays")) {
        // Drawing only: the run goes on as it was.
        View& v = def_->view;
        ImGui::Checkbox("title and numbers", &v.hud);
        ImGui::SameLine();
        ImGui::Checkbox("energy plot", &v.energy_plot);
        ImGui::SliderInt("trail (frames)", &v.trail_frames, 0, 600);
        auto arrows = [](const char* label, double& value, float lo, float hi) {
            auto f = static_cast<float>(value);
            if (ImGui::SliderFloat(label, &f, 0.0f, hi, f == 0.0f ? "off" : "%.3g", ImGuiSliderFlags_Logarithmic)) {
                value = f < lo ? 0.0 : f;
            }
        };
        arrows("velocity arrows (s)", v.velocity_arrows, 1e-3f, 10.0f);
        arrows("force arrows (m/N)", v.force_arrows, 1e-6f, 1e4f);
    }
    if (!parameters_.empty() && ImGui::CollapsingHeader("Scene parameters")) {
        ImGui::TextWrapped("The scene file's numbers; changing one rebuilds the scene from the file.");
        for (std::size_t k = 0; k < parameters_.size(); ++k) {
            const double v = parameters_[k].value;
            const float lo = v > 0 ? static_cast<float>(v / 10) : v < 0 ? static_cast<float>(v * 10) : -10.0f;
            const float hi = v > 0 ? static_cast<float>(v * 10) : v < 0 ? static_cast<float>(v / 10) : 10.0f;
            ImGui::PushID(static_cast<int>(k));
            const bool log = v > 0 && !parameters_[k].integer;
            ImGui::SliderFloat(parameters_[k].key.c_str(), &edited_[k], lo, hi,
                               parameters_[k].integer ? "%.0f" : "%.4g", log ? ImGuiSliderFlags_Logarithmic : 0);
            if (ImGui::IsItemDeactivatedAfterEdit()) rebuild();  // on release: one rebuild per change
            ImGui::PopID();
        }
        if (!error_.empty()) ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "%s", error_.c_str());
    }
    if (ImGui::CollapsingHeader("Plots", ImGuiTreeNodeFlags_DefaultOpen)) {
        const auto e = energy_.data();
        char label[64];
        std::snprintf(label, sizeof label, "E = %.5g J", e.empty() ? 0.0 : e.back());
        ImGui::PlotLines("energy", e.data(), static_cast<int>(e.size()), 0, label, FLT_MAX, FLT_MAX, ImVec2(0, 70));
        static constexpr std::array<const char*, 6> kNames{"particles",  "constraints", "collisions",
                                                           "plasticity", "rigid",       "watchdog"};
        for (std::size_t k = 0; k < kNames.size(); ++k) {
            const auto d = system_ms_[k].data();
            if (d.empty() || *std::max_element(d.begin(), d.end()) <= 0.0f) continue;  // a system the scene lacks
            std::snprintf(label, sizeof label, "%.3f ms/frame", d.back());
            ImGui::PlotLines(kNames[k], d.data(), static_cast<int>(d.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 40));
        }
        const auto r = render_ms_.data();
        std::snprintf(label, sizeof label, "%.1f ms/frame", r.empty() ? 0.0 : r.back());
        ImGui::PlotLines("rendering", r.data(), static_cast<int>(r.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 40));
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped(
        "Mouse: left drags a body (or orbits), right orbits, middle pans, wheel zooms. Keys: Space, Right/Left "
        "step and step back, R reset, [ ] speed, I integrator, H panel, P screenshot, C camera, Q quit.");
    ImGui::PopStyleColor();
    ImGui::PopItemWidth();
    ImGui::End();
}

// GLFW callbacks reach the viewer through the window's user pointer; ImGui's
// backend installs its own first and chains to these.
Viewer* viewer_of(GLFWwindow* window) { return static_cast<Viewer*>(glfwGetWindowUserPointer(window)); }

// The window's framebuffer in pixels, within what the renderer draws (16 ..
// 8192 px a side; a HiDPI window can be larger, and then shows the picture
// in its bottom-left corner instead of failing).
void framebuffer_size(GLFWwindow* window, int& width, int& height) {
    glfwGetFramebufferSize(window, &width, &height);
    width = std::clamp(width, 16, 8192);
    height = std::clamp(height, 16, 8192);
}

// Runs an input handler; what it throws is reported, never unwound through
// GLFW's C frames (that would end the program).
template <class F>
void guarded(GLFWwindow* window, F&& handle) {
    try {
        handle(*viewer_of(window));
    } catch (const std::exception& e) {
        viewer_of(window)->report(e.what());
    }
}

// The panel takes the mouse only where it is drawn (ImGui's flags are from the
// last frame it drew).
bool panel_has_mouse(GLFWwindow* window) { return viewer_of(window)->panel() && ImGui::GetIO().WantCaptureMouse; }

// Cursor positions are in screen units; the picture is in framebuffer pixels.
void cursor_in_pixels(GLFWwindow* window, double& x, double& y, int& w, int& h) {
    int ww = 0, wh = 0;
    framebuffer_size(window, w, h);
    glfwGetWindowSize(window, &ww, &wh);
    x *= ww > 0 ? static_cast<double>(w) / ww : 1.0;
    y *= wh > 0 ? static_cast<double>(h) / wh : 1.0;
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    // Shortcuts work while the panel has focus, except when it is taking typed text.
    if (action == GLFW_RELEASE || (viewer_of(window)->panel() && ImGui::GetIO().WantTextInput)) return;
    guarded(window, [&](Viewer& v) { v.key(key); });
}

void on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
    if (action == GLFW_PRESS && panel_has_mouse(window)) return;
    double x = 0, y = 0;
    int w = 0, h = 0;
    glfwGetCursorPos(window, &x, &y);
    cursor_in_pixels(window, x, y, w, h);
    guarded(window,
            [&](Viewer& v) { v.mouse_button(button, action == GLFW_PRESS, x, y, w, h, (mods & GLFW_MOD_SHIFT) != 0); });
}

void on_cursor(GLFWwindow* window, double x, double y) {
    int w = 0, h = 0;
    cursor_in_pixels(window, x, y, w, h);
    guarded(window, [&](Viewer& v) { v.mouse_move(x, y, w, h); });
}

void on_scroll(GLFWwindow* window, double /*dx*/, double dy) {
    if (panel_has_mouse(window)) return;
    guarded(window, [&](Viewer& v) { v.scroll(dy); });
}

void validate(const ViewOptions& o) {
    if (o.width < 64 || o.height < 64 || o.width > 7680 || o.height > 4320) {
        throw sim::InputError("view: --size must be within 64x64 .. 7680x4320 (got " + std::to_string(o.width) + "x" +
                              std::to_string(o.height) + ")");
    }
    if (o.exit_after < 0)
        throw sim::InputError("view: --exit-after must be >= 0 (got " + std::to_string(o.exit_after) + ")");
    if (o.msaa_samples != -1 && !render::supported_msaa_samples(o.msaa_samples)) {
        throw sim::InputError(
            "view: --msaa must be 0, 1, 2, 4 or 8, or -1 for 4 when still and off while running (got " +
            std::to_string(o.msaa_samples) + ")");
    }
    if (!o.screenshot.empty() && o.screenshot.extension() != ".png") {
        throw sim::InputError("view: --screenshot must end in .png (got '" + o.screenshot.string() + "')");
    }
}

// ImGui's context and backends for one window, torn down in reverse.
struct ImGuiSession {
    explicit ImGuiSession(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini written into the user's folder
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~ImGuiSession() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

}  // namespace

// --- 4. run_viewer ---------------------------------------------------------------

ViewResult run_viewer(const SceneDef& scene, const std::vector<Override>& overrides, const ViewOptions& options) {
    validate(options);
    Viewer viewer(scene, overrides, options);
    const auto context = render::create_context({.backend = render::Backend::glfw,
                                                 .window_width = options.width,
                                                 .window_height = options.height,
                                                 .title = "Plausible: " + scene.name});
    GLFWwindow* window = context->window();
    render::Renderer renderer(*context);
    glfwSetWindowUserPointer(window, &viewer);
    glfwSetKeyCallback(window, on_key);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);
    glfwSwapInterval(1);
    ImGuiSession imgui(window);

    auto last = Clock::now();
    int shown = 0;
    for (;;) {
        glfwPollEvents();
        const auto now = Clock::now();
        viewer.update(std::chrono::duration<double>(now - last).count());
        last = now;
        const bool done = viewer.quit || glfwWindowShouldClose(window) != 0 ||
                          (options.exit_after > 0 && ++shown >= options.exit_after);

        int width = 0, height = 0;
        framebuffer_size(window, width, height);
        const int msaa = options.msaa_samples >= 0                     ? options.msaa_samples
                         : viewer.running() && options.exit_after == 0 ? 0
                                                                       : 4;
        const auto r0 = Clock::now();
        renderer.draw(viewer.draw_list(width, height), {.width = width, .height = height, .msaa_samples = msaa});
        renderer.blit_to_window();
        const double render_ms = 1e3 * std::chrono::duration<double>(Clock::now() - r0).count();
        if (viewer.panel()) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            viewer.panel_ui();
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        }
        viewer.record_times(render_ms);
        if (viewer.screenshot_now) {
            // P: beside --screenshot (or here), named by scene and frame; a failed
            // write is reported and the session goes on.
            const std::filesystem::path file =
                options.screenshot.parent_path() /
                ("view-" + scene.name + "-" + std::to_string(viewer.run().frame()) + ".png");
            try {
                render::write_png(file, renderer.read_window());
                std::printf("view: screenshot %s\n", file.string().c_str());
                std::fflush(stdout);
            } catch (const std::exception& e) {
                viewer.report(e.what());
            }
            viewer.screenshot_now = false;
        }
        if (done && !options.screenshot.empty()) render::write_png(options.screenshot, renderer.read_window());
        context->swap_buffers();
        if (done) break;
    }
    return {viewer.run().frame(), viewer.run().time(), viewer.run().verdict().exploded(),
            viewer.run().state_hash_hex()};
}

}  // namespace scenes
