// The viewer's dynamic resolution. While a scene runs, each frame is drawn at
// a fraction of the window's pixels per side (render::RenderSettings::scale)
// and stretched, filtered, over the window, the fraction chosen from the
// frames just shown so that a frame stays within kBudgetMs; still (paused,
// stepped, a screenshot, the last frame) a frame is drawn whole. Game engines
// do the same under load ("dynamic resolution"): a moving picture a little
// softer, instead of a slow one. On llvmpipe a frame's cost is mostly its
// pixels (the showcase's fragment shading is three quarters of it), so the
// fraction follows the square root of budget / time.
#pragma once

#include <algorithm>
#include <cmath>

namespace scenes::view {

class FrameBudget {
public:
    static constexpr double kBudgetMs = 25.0;  // a frame while running: 40 frames/s
    static constexpr float kMinScale = 0.5f;   // below half the pixels per side the scene is hard to read
    static constexpr float kStep = 1.0f / 16;  // scales are multiples of this: the targets are not remade every frame

    // fixed: the scale while running, kMinScale .. 1; -1: chosen frame by frame.
    explicit FrameBudget(float fixed) : fixed_(fixed), scale_(fixed > 0 ? fixed : kStartScale) {}

    // The scale for the next frame: 1 when it is drawn still.
    float scale(bool running) const { return running ? scale_ : 1.0f; }

    // The last frame took `ms` of wall time drawn at scale(running):
    // everything up to the swap (physics, drawing, panel), not the swap, which
    // with vsync waits for the display (a frame would read 16.7 or 33.3 ms,
    // never inside the band, and the scale would swing).
    void frame_took(double ms, bool running) {
        if (!running || fixed_ > 0 || !(ms > 0)) return;
        // Inside the budget with some room, or over it: move towards the
        // scale that would have fitted it (85% of it, so that a frame a
        // little slower still fits), at most a fifth down or a tenth up a frame.
        if (ms > 0.7 * kBudgetMs && ms <= kBudgetMs) return;
        const double wanted = scale_ * std::sqrt(0.85 * kBudgetMs / ms);
        const double bounded = std::clamp(wanted, 0.8 * scale_, 1.1 * scale_);
        const double stepped = std::round(bounded / kStep) * kStep;
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
