// Screen-space overlays built on the CPU (internal to render/): rectangles,
// anti-aliased lines, text and plot panels become one list of triangles in
// pixel coordinates that the renderer draws in a single call. Lines are
// triangles with a distance-to-centre attribute, never GL wide lines (not in
// the core profile beyond width 1), and fade over one pixel at their edges,
// so they look smooth with or without MSAA.
#pragma once

#include "render/draw_list.h"
#include "render/font.h"

#include <string>
#include <vector>

namespace render::detail {

struct OverlayVertex {
    float x, y;        // px, origin top-left
    float u, v;        // atlas coordinates (text)
    float r, g, b, a;  // sRGB colour, straight alpha
    float edge;        // lines: distance from the centre line, px; text: < -1e5 marks a glyph
    float half_width;  // lines: half the width, px (fills have a large value: no fade)
    bool operator==(const OverlayVertex&) const = default;
};

class OverlayBatch {
public:
    explicit OverlayBatch(const Font& font) : font_(font) {}

    void rect(Vec2 min, Vec2 max, Color color);
    void line(Vec2 a, Vec2 b, float width, Color color);
    void polyline(const std::vector<Vec2>& points, float width, Color color);
    void text(const std::string& text, Vec2 top_left, float size, Color color);
    void text_block(const Text& text);  // with its optional backdrop
    void plot(const Plot& plot);

    const std::vector<OverlayVertex>& vertices() const { return vertices_; }
    void clear() { vertices_.clear(); }

private:
    const Font& font_;
    std::vector<OverlayVertex> vertices_;
};

// "Nice" tick positions (1, 2 or 5 times a power of ten) covering [lo, hi],
// about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target);
// A tick label: the shortest of %g forms that tells neighbouring ticks apart.
std::string tick_label(double value, double step);

}  // namespace render::detail
