// The viewer's ImGui panel: the verdict, the step (integrator, dt, substeps,
// time scale), the overlays, the scene's parameters as sliders, live plots.
#include "scenes/model/recording.h"
#include "scenes/view/viewer.h"

#include <imgui.h>

#include <cmath>

namespace scenes::view {

// What the run is and where: the description, frame and time, the verdict,
// the run buttons and the speed.
void Viewer::panel_run_controls() {
    ImGui::TextWrapped("%s", def_->description.c_str());
    ImGui::Text("frame %d   t = %.3f s", run_->frame(), run_->time());
    if (run_->verdict().exploded()) {
        ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "%s", run_->verdict().message(def_->name).c_str());
    }
    const char* pause = paused_ ? "Resume (Space)" : "Pause (Space)";
    if (ImGui::Button(pause)) paused_ = !paused_;
    note_item(pause);
    ImGui::SameLine();
    if (ImGui::Button("Step")) step_once();
    note_item("Step");
    ImGui::SameLine();
    ImGui::BeginDisabled(history_.empty());
    if (ImGui::Button("Back")) step_back();
    note_item("Back");
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (ImGui::Button("Reset")) reset();
    note_item("Reset");
    ImGui::Text("%zu stored states to step back through", history_.size());
    if (def_->recorded) {
        // Scrub: any frame of the recording, from its nearest stored state.
        int frame = run_->frame();
        const int last = static_cast<int>(def_->recorded->hashes.size()) - 1;
        if (ImGui::SliderInt("recording frame", &frame, 0, last) && frame != run_->frame()) seek(frame);
        note_item("recording frame");
        if (run_->diverged_frame() >= 0) {
            ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "DIVERGED from the recording at frame %d",
                               run_->diverged_frame());
        }
    }
    ImGui::SliderFloat("speed", &time_scale_, 1.0f / 64.0f, 4.0f, "%.3fx", ImGuiSliderFlags_Logarithmic);
    note_item("speed");
}

// The integrator, dt and substeps; a refused change is shown in red.
void Viewer::panel_step() {
    const bool open = ImGui::CollapsingHeader("Step", ImGuiTreeNodeFlags_DefaultOpen);
    note_item("Step (header)");
    if (!open) return;
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
    note_item("integrator");
    auto dt_ms = static_cast<float>(1e3 * step.dt);
    constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;  // typed values too
    if (ImGui::SliderFloat("dt (ms)", &dt_ms, 0.1f, 100.0f, "%.2f", ImGuiSliderFlags_Logarithmic | kClamp)) {
        step.dt = 1e-3 * dt_ms;
        changed = true;
    }
    note_item("dt (ms)");
    if (ImGui::SliderInt("substeps", &step.substeps, 1, 64, "%d", kClamp)) changed = true;
    note_item("substeps");
    if (changed) {
        try {
            run_->set_step(step);
        } catch (const sim::InputError& e) {
            error_ = e.what();
        }
    }
}

// Drawing only: the run goes on as it was.
void Viewer::panel_overlays() {
    const bool open = ImGui::CollapsingHeader("Overlays");
    note_item("Overlays");
    if (!open) return;
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

// The scene file's numbers as sliders; a change rebuilds the scene from the file.
void Viewer::panel_parameters() {
    if (parameters_.empty()) return;
    const bool open = ImGui::CollapsingHeader("Scene parameters");
    note_item("Scene parameters");
    if (!open) return;
    ImGui::TextWrapped("The scene file's numbers; changing one rebuilds the scene from the file.");
    for (std::size_t k = 0; k < parameters_.size(); ++k) {
        const double v = parameters_[k].value;
        const float lo = v > 0 ? static_cast<float>(v / 10) : v < 0 ? static_cast<float>(v * 10) : -10.0f;
        const float hi = v > 0 ? static_cast<float>(v * 10) : v < 0 ? static_cast<float>(v / 10) : 10.0f;
        ImGui::PushID(static_cast<int>(k));
        const bool log = v > 0 && !parameters_[k].integer;
        ImGui::SliderFloat(parameters_[k].key.c_str(), &edited_[k], lo, hi, parameters_[k].integer ? "%.0f" : "%.4g",
                           log ? ImGuiSliderFlags_Logarithmic : 0);
        note_item(parameters_[k].key);
        if (ImGui::IsItemDeactivatedAfterEdit()) rebuild();  // on release: one rebuild per change
        ImGui::PopID();
    }
    if (!error_.empty()) ImGui::TextColored(ImVec4(0.9f, 0.1f, 0.1f, 1), "%s", error_.c_str());
}

// Live plots: energy, each system's ms per frame step, rendering.
void Viewer::panel_plots() {
    const bool open = ImGui::CollapsingHeader("Plots", ImGuiTreeNodeFlags_DefaultOpen);
    note_item("Plots");
    if (!open) return;
    const auto e = energy_.data();
    char label[64];
    std::snprintf(label, sizeof label, "E = %.5g J", e.empty() ? 0.0 : e.back());
    ImGui::PlotLines("energy", e.data(), static_cast<int>(e.size()), 0, label, FLT_MAX, FLT_MAX, ImVec2(0, 70));
    for (const std::string& name : run_->world().systems().names()) {
        const auto it = system_ms_.find(name);
        if (it == system_ms_.end()) continue;
        const auto d = it->second.ms.data();
        if (d.empty() || *std::max_element(d.begin(), d.end()) <= 0.0f) continue;  // nothing measured yet
        std::snprintf(label, sizeof label, "%.3f ms/frame", d.back());
        ImGui::PlotLines(name.c_str(), d.data(), static_cast<int>(d.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 40));
    }
    const auto r = render_ms_.data();
    std::snprintf(label, sizeof label, "%.1f ms/frame, drawn at %d%%", r.empty() ? 0.0 : r.back(),
                  static_cast<int>(std::lround(100.0f * render_scale_)));
    ImGui::PlotLines("rendering", r.data(), static_cast<int>(r.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 40));
}

void Viewer::note_item(const std::string& label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    items_[label] = {a.x, a.y, b.x, b.y};
}

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
    panel_run_controls();
    panel_step();
    panel_overlays();
    panel_parameters();
    panel_plots();
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped(
        "Mouse: left drags a body (or orbits), right orbits, middle pans, wheel zooms. Keys: Space, Right/Left "
        "step and step back, R reset, [ ] speed, I integrator, H panel, P screenshot, C camera, Q quit.");
    ImGui::PopStyleColor();
    ImGui::PopItemWidth();
    ImGui::End();
}

}  // namespace scenes::view
