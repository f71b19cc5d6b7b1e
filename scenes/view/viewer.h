// The viewer's state and what it does (private to scenes/view): input,
// stepping and stepping back, rebuilding from the panel's sliders, drawing.
// Its ImGui panel is in panel.cpp; the window and the loop in view.cpp.
#pragma once

#include "scenes/view/picking.h"
#include "scenes/view/view.h"
#include "sim/error.h"
#include "sim/integrators.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <array>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <string>

namespace scenes::view {

using Clock = std::chrono::steady_clock;

// The shortest text that reads back as this float: a slider at 0.3 sets
// 0.3, not the double nearest 0.3f (0.30000001192092896).
inline std::string shortest(float value) {
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
    // scripted (exit_after, or an input script), so that frame N is the
    // scene's frame N.
    void update(double wall_dt) {
        // A screenshot asked for shows the frame it was asked at (P then Space
        // in one poll still saves the paused frame).
        if (screenshot_now) return;
        if (paused_ || run_->verdict().exploded()) {
            accumulator_ = 0.0;
            return;
        }
        if (options_.exit_after > 0 || !options_.input.empty()) {
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

    void record_times(double render_ms, float render_scale) {
        render_scale_ = render_scale;
        // Per frame step since the last sampled one (World::SystemTimes
        // samples a light scene's frames, so several may share a figure).
        const sim::World& world = run_->world();
        const sim::World::SystemTimes& t = world.times();
        const std::uint64_t sampled = t.sampled_frames - last_sampled_frames_;
        for (const std::string& name : world.systems().names()) {
            SystemSeries& s = system_ms_[name];
            const double now = t.of(name);
            if (sampled > 0) s.last_ms = 1e3 * std::max(0.0, now - s.last_seconds) / static_cast<double>(sampled);
            if (sampled > 0) s.last_seconds = now;
            s.ms.push(static_cast<float>(s.last_ms));
        }
        last_sampled_frames_ = t.sampled_frames;
        render_ms_.push(static_cast<float>(render_ms));
        energy_.push(static_cast<float>(world.energy()));
    }

    void panel_ui();
    // Where the panel last drew the item of this label (window px: x0, y0,
    // x1, y1), for an input script's "move @LABEL"; null when never drawn.
    const std::array<float, 4>* item(const std::string& label) const {
        const auto it = items_.find(label);
        return it == items_.end() ? nullptr : &it->second;
    }
    void panel_run_controls();
    void panel_step();
    void panel_overlays();
    void panel_parameters();
    void panel_plots();

    // What went wrong in an input callback (they must not throw into GLFW):
    // printed, and shown in the panel.
    void report(const std::string& message) {
        std::fprintf(stderr, "view: %s\n", message.c_str());
        error_ = message;
    }

private:
    enum class Mode { none, orbit, pan, drag };

    void note_item(const std::string& label);  // the last item's place, under its label (panel.cpp)

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

    // A recording's frame (the panel's slider): the nearest stored state,
    // then steps; paused there. Stepping back goes on from it.
    void seek(int frame) {
        paused_ = true;
        history_.clear();
        history_bytes_ = 0;
        if (!run_->seek(frame)) report("cannot go to frame " + std::to_string(frame) + " of the recording");
        reapply_drag();
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
        for (auto& [name, series] : system_ms_) series.last_seconds = series.last_ms = 0.0;  // a new World's clocks
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
    float render_scale_ = 1.0f;  // the last frame's RenderSettings::scale
    struct SystemSeries {
        Series ms;                  // ms per frame step
        double last_seconds = 0.0;  // s, the world's time of it at the last sampled frame
        double last_ms = 0.0;       // ms per frame step, the last figure
    };
    std::map<std::string, SystemSeries> system_ms_;  // by the names of World::systems()
    std::uint64_t last_sampled_frames_ = 0;
    std::map<std::string, std::array<float, 4>> items_;  // the panel's items by label (item())
};

}  // namespace scenes::view
