// The viewer's dynamic resolution. While a scene runs, each frame is drawn at
// a fraction of the window's pixels per side (render::RenderSettings::scale)
// and stretched, filtered, over the window, its overlays drawn over it at the
// window's pixels (text stays sharp), the fraction chosen from the frames
// just shown so that a frame stays within kBudgetMs; still (paused, stepped,
// a screenshot, the last frame) a frame is drawn whole. Game engines do the
// same under load ("dynamic resolution"): a moving picture a little softer,
// instead of a slow one. On llvmpipe a frame's cost is mostly its pixels
// (the showcase's fragment shading is three quarters of it), so the fraction
// follows the square root of budget / time.
#pragma once

#include <algorithm>
#include <cmath>

namespace scenes::view {

class FrameBudget {
public:
    static constexpr double kBudgetMs = 25.0;  // a frame while running: 40 frames/s
    // Below 3/8 of the pixels per side (480 x 270 of a 720p window) a
    // droplet or a ragdoll's hand is a pixel or two.
    static constexpr float kMinScale = 0.375f;
    static constexpr float kStep = 1.0f / 16;  // scales are multiples of this: the targets are not remade every frame

    // fixed: the scale while running, kMinScale .. 1; -1: chosen frame by frame.
    explicit FrameBudget(float fixed) : fixed_(fixed), scale_(fixed > 0 ? fixed : kStartScale) {}

    // The scale for the next frame: 1 when it is drawn still.
    float scale(bool running) const { return running ? scale_ : 1.0f; }

    // The last frame, drawn at scale(running): `work_ms` from its start up to
    // its swap (physics, drawing, panel), `frame_ms` from the swap before to
    // its own (the frame as the user sees it: the swap copies the frame to
    // the display, which under X without a GPU is a copy of every pixel by
    // the X server; with vsync it also waits for the display). Over budget
    // (frame_ms), it moves down towards the scale that would have fitted
    // (85% of the budget, so that a frame a little slower still fits), at
    // most a fifth a frame; up, at most a tenth a frame, only while the work
    // alone has room (under 60% of the budget): a frame that waited for
    // vsync reads 16.7 ms whatever its work, and the scale would swing.
    void frame_took(double work_ms, double frame_ms, bool running) {
        if (!running || fixed_ > 0 || !(work_ms > 0) || !(frame_ms >= work_ms)) return;
        double wanted = scale_;
        if (frame_ms > kBudgetMs) {
            wanted = std::max(scale_ * std::sqrt(0.85 * kBudgetMs / frame_ms), 0.8 * scale_);
        } else if (work_ms < 0.6 * kBudgetMs) {
            wanted = std::min(scale_ * std::sqrt(0.85 * kBudgetMs / work_ms), 1.1 * scale_);
        }
        const double stepped = std::round(wanted / kStep) * kStep;
        scale_ = std::clamp(static_cast<float>(stepped), kMinScale, 1.0f);
    }

private:
    // The first running frames: a light scene's frames rise to 1 within a
    // few frames (a tenth a frame), softer until then.
    static constexpr float kStartScale = 0.75f;
    float fixed_;
    float scale_;
};

}  // namespace scenes::view
