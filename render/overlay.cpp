#include "render/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace render::detail {
namespace {

constexpr float kFill = 1e6f;          // half_width of a fill: never fades
constexpr float kGlyphMarker = -1e6f;  // edge value that marks a glyph vertex

// Clips the segment a-b to the rectangle [lo, hi] (Liang-Barsky); false when
// nothing is left.
bool clip_segment(Vec2& a, Vec2& b, Vec2 lo, Vec2 hi) {
    float t0 = 0.0f, t1 = 1.0f;
    const Vec2 d = b - a;
    const float p[4] = {-d.x(), d.x(), -d.y(), d.y()};
    const float q[4] = {a.x() - lo.x(), hi.x() - a.x(), a.y() - lo.y(), hi.y() - a.y()};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0.0f) {
            if (q[i] < 0.0f) return false;
            continue;
        }
        const float t = q[i] / p[i];
        if (p[i] < 0.0f) {
            t0 = std::max(t0, t);
        } else {
            t1 = std::min(t1, t);
        }
        if (t0 > t1) return false;
    }
    const Vec2 start = a;
    a = start + t0 * d;
    b = start + t1 * d;
    return true;
}

}  // namespace

void OverlayBatch::rect(Vec2 min, Vec2 max, Color c) {
    auto v = [&](float x, float y) { return OverlayVertex{x, y, 0, 0, c.r, c.g, c.b, c.a, 0, kFill}; };
    vertices_.insert(vertices_.end(), {v(min.x(), min.y()), v(max.x(), min.y()), v(max.x(), max.y()),
                                       v(min.x(), min.y()), v(max.x(), max.y()), v(min.x(), max.y())});
}

void OverlayBatch::line(Vec2 a, Vec2 b, float width, Color c) {
    const Vec2 d = b - a;
    const float length = d.norm();
    if (length <= 0.0f || width <= 0.0f) return;
    const float half = 0.5f * width;
    // The quad extends one pixel beyond the line on every side so the edge can fade.
    const float reach = half + 1.0f;
    const Vec2 along = d / length, across(-along.y(), along.x());
    const Vec2 a0 = a - along * 0.5f * half, b0 = b + along * 0.5f * half;
    auto v = [&](Vec2 p, float edge) { return OverlayVertex{p.x(), p.y(), 0, 0, c.r, c.g, c.b, c.a, edge, half}; };
    const OverlayVertex p0 = v(a0 + across * reach, reach), p1 = v(b0 + across * reach, reach),
                        p2 = v(b0 - across * reach, -reach), p3 = v(a0 - across * reach, -reach);
    vertices_.insert(vertices_.end(), {p0, p1, p2, p0, p2, p3});
}

void OverlayBatch::polyline(const std::vector<Vec2>& points, float width, Color color) {
    for (std::size_t i = 1; i < points.size(); ++i) line(points[i - 1], points[i], width, color);
}

void OverlayBatch::text(const std::string& text, Vec2 top_left, float size, Color c) {
    for (const GlyphQuad& q : font_.layout(text, top_left.x(), top_left.y(), size)) {
        auto v = [&](float x, float y, float u, float w) {
            return OverlayVertex{x, y, u, w, c.r, c.g, c.b, c.a, kGlyphMarker, 0};
        };
        const OverlayVertex a = v(q.x0, q.y0, q.u0, q.v0), b = v(q.x1, q.y0, q.u1, q.v0), d = v(q.x1, q.y1, q.u1, q.v1),
                            e = v(q.x0, q.y1, q.u0, q.v1);
        vertices_.insert(vertices_.end(), {a, b, d, a, d, e});
    }
}

void OverlayBatch::text_block(const Text& t) {
    if (t.backdrop) {
        const TextBox box = font_.measure(t.text, t.size);
        const float pad = 0.3f * t.size;
        rect(t.position - Vec2(pad, pad), t.position + Vec2(box.width + pad, box.height + pad),
             Color{1.0f, 1.0f, 1.0f, 0.75f});
    }
    text(t.text, t.position, t.size, t.color);
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
    if (!(hi > lo) || target < 1) return {lo};
    const double raw = (hi - lo) / target;
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    double step = magnitude;
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        step = m * magnitude;
        if (step >= raw) break;
    }
    std::vector<double> ticks;
    for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0) {
        const double value = k * step;
        ticks.push_back(std::abs(value) < 1e-12 * step ? 0.0 : value);
    }
    return ticks;
}

std::string tick_label(double value, double step) {
    // Enough significant digits that consecutive ticks differ, at most 6.
    const double span = std::max(std::abs(value), step);
    const int digits = std::clamp(static_cast<int>(std::ceil(std::log10(span / step))) + 1, 1, 6);
    char text[32];
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    return text;
}

void OverlayBatch::plot(const Plot& p) {
    const float s = p.text_size;
    const Vec2 origin = p.position, size = p.size;
    rect(origin, origin + size, p.background);

    // Data range: as given, or fitted to the finite points with a 5% margin in y.
    float x_lo = std::numeric_limits<float>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
    for (const auto& series : p.series) {
        for (const Vec2& q : series.points) {
            if (!std::isfinite(q.x()) || !std::isfinite(q.y())) continue;
            x_lo = std::min(x_lo, q.x()), x_hi = std::max(x_hi, q.x());
            y_lo = std::min(y_lo, q.y()), y_hi = std::max(y_hi, q.y());
        }
    }
    if (!(x_hi >= x_lo)) x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
    if (!p.y_range) {
        const float pad = y_hi > y_lo ? 0.05f * (y_hi - y_lo) : std::max(1e-6f, 0.05f * std::abs(y_hi) + 1e-6f);
        y_lo -= pad, y_hi += pad;
    }
    if (p.x_range) x_lo = p.x_range->x(), x_hi = p.x_range->y();
    if (p.y_range) y_lo = p.y_range->x(), y_hi = p.y_range->y();
    if (!(x_hi > x_lo)) x_hi = x_lo + 1;
    if (!(y_hi > y_lo)) y_hi = y_lo + 1;

    const auto y_ticks = nice_ticks(y_lo, y_hi, 4);
    const auto x_ticks = nice_ticks(x_lo, x_hi, 5);
    const double y_step = y_ticks.size() > 1 ? y_ticks[1] - y_ticks[0] : 1.0;
    const double x_step = x_ticks.size() > 1 ? x_ticks[1] - x_ticks[0] : 1.0;
    float label_width = 0;
    for (double t : y_ticks) label_width = std::max(label_width, font_.measure(tick_label(t, y_step), 0.9f * s).width);

    // The plot area inside the panel: room for the title, the y tick labels and
    // y label on the left, the x tick labels and x label below.
    const float left = origin.x() + 0.4f * s + (p.y_label.empty() ? 0.0f : 1.3f * s) + label_width + 0.5f * s;
    const float top = origin.y() + (p.title.empty() ? 0.6f * s : 1.7f * s);
    const float right = origin.x() + size.x() - 0.8f * s;
    const float bottom = origin.y() + size.y() - 1.6f * s - (p.x_label.empty() ? 0.0f : 1.2f * s);
    if (right <= left + 10 || bottom <= top + 10) return;  // too small to draw a plot in
    auto to_px = [&](Vec2 q) {
        return Vec2(left + (q.x() - x_lo) / (x_hi - x_lo) * (right - left),
                    bottom - (q.y() - y_lo) / (y_hi - y_lo) * (bottom - top));
    };

    Color grid = p.foreground;
    grid.a *= 0.15f;
    for (double t : y_ticks) {
        const float y = to_px(Vec2(x_lo, static_cast<float>(t))).y();
        line(Vec2(left, y), Vec2(right, y), 1.0f, grid);
        const std::string label = tick_label(t, y_step);
        const TextBox box = font_.measure(label, 0.9f * s);
        text(label, Vec2(left - 0.4f * s - box.width, y - 0.5f * box.height), 0.9f * s, p.foreground);
    }
    for (double t : x_ticks) {
        const float x = to_px(Vec2(static_cast<float>(t), y_lo)).x();
        line(Vec2(x, top), Vec2(x, bottom), 1.0f, grid);
        line(Vec2(x, bottom), Vec2(x, bottom + 0.3f * s), 1.0f, p.foreground);
        const std::string label = tick_label(t, x_step);
        const TextBox box = font_.measure(label, 0.9f * s);
        text(label, Vec2(x - 0.5f * box.width, bottom + 0.4f * s), 0.9f * s, p.foreground);
    }
    line(Vec2(left, top), Vec2(left, bottom), 1.5f, p.foreground);
    line(Vec2(left, bottom), Vec2(right, bottom), 1.5f, p.foreground);

    if (!p.title.empty()) {
        const TextBox box = font_.measure(p.title, 1.05f * s);
        text(p.title, Vec2(0.5f * (left + right) - 0.5f * box.width, origin.y() + 0.3f * s), 1.05f * s, p.foreground);
    }
    if (!p.x_label.empty()) {
        const TextBox box = font_.measure(p.x_label, s);
        text(p.x_label, Vec2(0.5f * (left + right) - 0.5f * box.width, origin.y() + size.y() - 1.35f * s), s,
             p.foreground);
    }
    if (!p.y_label.empty()) {
        // Horizontal, at the top left above the axis: rotated text is harder to read on a slide.
        text(p.y_label, Vec2(origin.x() + 0.4f * s, top - 1.35f * s + (p.title.empty() ? 0.6f * s : 0.0f)), s,
             p.foreground);
    }

    // Series, clipped to the plot area, then the legend in the top-right corner.
    const Vec2 lo(left, top), hi(right, bottom);
    for (const auto& series : p.series) {
        for (std::size_t i = 1; i < series.points.size(); ++i) {
            const Vec2 q0 = series.points[i - 1], q1 = series.points[i];
            if (!q0.allFinite() || !q1.allFinite()) continue;
            Vec2 a = to_px(q0), b = to_px(q1);
            if (clip_segment(a, b, lo, hi)) line(a, b, series.width, series.color);
        }
    }
    // The legend sits on a translucent panel so it stays readable over the curves.
    float legend_width = 0;
    int entries = 0;
    for (const auto& series : p.series) {
        if (series.name.empty()) continue;
        legend_width = std::max(legend_width, font_.measure(series.name, 0.9f * s).width);
        ++entries;
    }
    if (entries > 0) {
        Color panel = p.background;
        panel.a = std::max(panel.a, 0.8f);
        rect(Vec2(right - 2.6f * s - legend_width, top + 0.1f * s),
             Vec2(right - 0.1f * s, top + 0.3f * s + 1.2f * s * static_cast<float>(entries)), panel);
    }
    float legend_y = top + 0.3f * s;
    for (const auto& series : p.series) {
        if (series.name.empty()) continue;
        const TextBox box = font_.measure(series.name, 0.9f * s);
        const float x1 = right - 0.4f * s, x0 = x1 - box.width;
        line(Vec2(x0 - 1.8f * s, legend_y + 0.5f * box.height), Vec2(x0 - 0.4f * s, legend_y + 0.5f * box.height),
             std::max(2.0f, series.width), series.color);
        text(series.name, Vec2(x0, legend_y), 0.9f * s, p.foreground);
        legend_y += 1.2f * s;
    }
}

}  // namespace render::detail
