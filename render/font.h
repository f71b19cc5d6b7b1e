// Text for overlays and sheet labels: DejaVu Sans (Debian's fonts-dejavu-core)
// through stb_truetype, baked once into a signed-distance-field atlas. One SDF
// atlas serves every text size (the GL renderer thresholds it in a shader; the
// CPU path samples it the same way), and baking is deterministic: the same
// font file gives the same atlas bytes on every run.
#pragma once

#include "render/error.h"
#include "render/image.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

namespace render {

// One glyph placed on screen: a rectangle in pixels (y down) and its place in
// the atlas (texture coordinates 0..1).
struct GlyphQuad {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // px, screen rectangle
    float u0 = 0, v0 = 0, u1 = 0, v1 = 0;  // atlas coordinates
};

// Size of a laid-out text, in pixels, for a given text height.
struct TextBox {
    float width = 0;   // px, widest line
    float height = 0;  // px, lines * line height
};

class Font {
public:
    // Loads a TrueType file and bakes the SDF atlas. Throws RenderError
    // (unavailable) naming the path when the file is missing or not a font.
    static Font load(const std::filesystem::path& ttf);
    // $PLAUSIBLE_FONT if set, else DejaVu Sans where fonts-dejavu-core puts it.
    static std::filesystem::path default_path();
    // The default font, loaded once per process (later calls return the same one).
    static const Font& default_font();

    // The atlas: one byte per texel, row-major, top row first. A texel holds
    // the signed distance to the glyph outline: kOnEdge on the outline, higher
    // inside, falling by kDistanceScale per pixel (at bake size) outside.
    static constexpr int kOnEdge = 128;
    static constexpr float kDistanceScale = 32.0f;  // atlas levels per px at bake size
    const std::vector<std::uint8_t>& atlas() const { return atlas_; }
    int atlas_width() const { return atlas_width_; }
    int atlas_height() const { return atlas_height_; }
    float bake_size() const { return bake_size_; }  // px, text height the atlas was baked at

    // Lays out UTF-8 text with the top-left corner of its box at (x, y), text
    // height `size_px` (ascent + descent). '\n' starts a new line. Characters
    // missing from the atlas are drawn as '?'.
    std::vector<GlyphQuad> layout(std::string_view utf8, float x, float y, float size_px) const;
    TextBox measure(std::string_view utf8, float size_px) const;

    // True when the atlas has the code point (others are drawn as '?').
    bool has_glyph(char32_t codepoint) const;

private:
    // One baked glyph; sizes are at bake size, in pixels.
    struct Glyph {
        char32_t codepoint = 0;
        int index = 0;                   // glyph index in the font file (kerning)
        int x = 0, y = 0, w = 0, h = 0;  // texels, its rectangle in the atlas
        float x_offset = 0;              // px, from the pen to the rectangle's left edge
        float y_offset = 0;              // px, from the baseline to the rectangle's top (negative: above)
        float advance = 0;               // px, pen movement after the glyph
    };
    struct File;  // the font file's bytes and stb_truetype's view of them (kerning)

    const Glyph& glyph(char32_t codepoint) const;
    float kerning(const Glyph& left, const Glyph& right) const;  // px at bake size

    std::shared_ptr<const File> file_;
    std::vector<Glyph> glyphs_;  // sorted by code point
    float ascent_ = 0;           // px at bake size, above the baseline
    float line_height_ = 0;      // px at bake size, baseline to baseline
    std::vector<std::uint8_t> atlas_;
    int atlas_width_ = 0;
    int atlas_height_ = 0;
    float bake_size_ = 0;
};

// Draws text into an image on the CPU (used by contact sheets, which need no
// GL context), blending `color` by the glyph coverage from the SDF atlas.
void draw_text(Image& image, const Font& font, std::string_view utf8, float x, float y, float size_px, Rgba8 color);

}  // namespace render
