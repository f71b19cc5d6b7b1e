// Text through stb_truetype (compiled in Debian's libstb): a signed-distance-
// field atlas baked once per font, packed with stb_rect_pack, laid out with
// the font's own metrics and kerning (see font.h).
#include "render/font.h"

#include <stb_rect_pack.h>
#include <stb_truetype.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

namespace render {

struct Font::File {
    std::vector<unsigned char> bytes;
    stbtt_fontinfo info{};
};

namespace {

// Text height the atlas is baked at, px. One SDF atlas serves every size: the
// distance field is resampled, so 32 px keeps 13 px labels crisp and 48 px
// titles smooth.
constexpr float kBakeSize = 32.0f;
// Texels of distance field around each glyph: the field falls from kOnEdge to
// 0 over kOnEdge / kDistanceScale = 4 px outside the outline.
constexpr int kPadding = 4;
constexpr int kAtlasWidth = 1024;  // texels; the height is what the glyphs need

// The characters a physics lecture writes: ASCII, Latin-1 (°, ±, ², ·, ×),
// Greek (Δt, ω, θ, μ), and the arrows, operators, super- and subscripts of
// formulas.
std::vector<char32_t> character_set() {
    std::vector<char32_t> set;
    for (char32_t c = 0x20; c <= 0x7E; ++c) set.push_back(c);
    for (char32_t c = 0xA0; c <= 0xFF; ++c) set.push_back(c);
    for (char32_t c = 0x391; c <= 0x3A9; ++c) set.push_back(c);
    for (char32_t c = 0x3B1; c <= 0x3C9; ++c) set.push_back(c);
    for (char32_t c = 0x2070; c <= 0x208E; ++c) set.push_back(c);
    for (char32_t c :
         {0x2013, 0x2014, 0x2022, 0x2026, 0x2032, 0x2033, 0x2190, 0x2191, 0x2192, 0x2193, 0x2202, 0x2207,
          0x2211, 0x2212, 0x221A, 0x221D, 0x221E, 0x222B, 0x2248, 0x2260, 0x2261, 0x2264, 0x2265, 0x22C5}) {
        set.push_back(c);
    }
    return set;
}

// Decodes one UTF-8 sequence at `p`, advancing it; malformed input gives
// U+FFFD (drawn as '?') and skips one byte.
char32_t next_codepoint(std::string_view text, std::size_t& p) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char b0 = byte(p);
    int length = b0 < 0x80 ? 1 : (b0 >> 5) == 0x6 ? 2 : (b0 >> 4) == 0xE ? 3 : (b0 >> 3) == 0x1E ? 4 : 0;
    if (length == 0 || p + length > text.size()) {
        ++p;
        return 0xFFFD;
    }
    char32_t c = length == 1 ? b0 : b0 & (0x7F >> length);
    for (int i = 1; i < length; ++i) {
        const unsigned char b = byte(p + i);
        if ((b & 0xC0) != 0x80) {
            ++p;
            return 0xFFFD;
        }
        c = (c << 6) | (b & 0x3F);
    }
    p += length;
    return c;
}

}  // namespace

std::filesystem::path Font::default_path() {
    const char* env = std::getenv("PLAUSIBLE_FONT");
    return env != nullptr && *env != '\0' ? std::filesystem::path(env) : std::filesystem::path(PLAUSIBLE_FONT_FILE);
}

const Font& Font::default_font() {
    static const Font font = load(default_path());
    return font;
}

Font Font::load(const std::filesystem::path& ttf) {
    auto file = std::make_shared<File>();
    std::ifstream in(ttf, std::ios::binary);
    if (!in) {
        throw RenderError(
            ErrorKind::unavailable,
            "font " + ttf.string() + " cannot be opened (install fonts-dejavu-core, or set PLAUSIBLE_FONT)");
    }
    file->bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const int offset = file->bytes.empty() ? -1 : stbtt_GetFontOffsetForIndex(file->bytes.data(), 0);
    if (offset < 0 || !stbtt_InitFont(&file->info, file->bytes.data(), offset)) {
        throw RenderError(ErrorKind::unavailable, "font " + ttf.string() + " is not a TrueType font");
    }
    const stbtt_fontinfo& info = file->info;
    const float scale = stbtt_ScaleForPixelHeight(&info, kBakeSize);  // kBakeSize / (ascent - descent)
    int ascent = 0, descent = 0, line_gap = 0;
    stbtt_GetFontVMetrics(&info, &ascent, &descent, &line_gap);

    Font font;
    font.bake_size_ = kBakeSize;
    font.ascent_ = static_cast<float>(ascent) * scale;
    font.line_height_ = static_cast<float>(ascent - descent + line_gap) * scale;

    // Distance fields of every glyph the font has, then packed into the atlas.
    struct Field {
        unsigned char* pixels = nullptr;
        int w = 0, h = 0, x_offset = 0, y_offset = 0;
    };
    std::vector<Field> fields;
    for (char32_t c : character_set()) {
        const int index = stbtt_FindGlyphIndex(&info, static_cast<int>(c));
        if (index == 0 && c != U' ') continue;  // not in this font
        Glyph g;
        g.codepoint = c;
        g.index = index;
        int advance = 0, bearing = 0;
        stbtt_GetGlyphHMetrics(&info, index, &advance, &bearing);
        g.advance = static_cast<float>(advance) * scale;
        Field f;
        f.pixels = stbtt_GetGlyphSDF(&info, scale, index, kPadding, static_cast<unsigned char>(kOnEdge), kDistanceScale,
                                     &f.w, &f.h, &f.x_offset, &f.y_offset);
        g.x_offset = static_cast<float>(f.x_offset);
        g.y_offset = static_cast<float>(f.y_offset);
        font.glyphs_.push_back(g);
        fields.push_back(f);
    }
    std::vector<stbrp_rect> rects(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
        rects[i].id = static_cast<int>(i);
        rects[i].w = fields[i].w + 1;  // one empty texel between glyphs: bilinear taps never bleed
        rects[i].h = fields[i].h + 1;
    }
    constexpr int kMaxAtlasHeight = 4096;
    std::vector<stbrp_node> nodes(kAtlasWidth);
    stbrp_context packer;
    stbrp_init_target(&packer, kAtlasWidth, kMaxAtlasHeight, nodes.data(), static_cast<int>(nodes.size()));
    const bool packed = stbrp_pack_rects(&packer, rects.data(), static_cast<int>(rects.size())) == 1;
    int height = 1;
    for (const stbrp_rect& r : rects) height = std::max(height, r.y + r.h);
    if (packed) {
        font.atlas_width_ = kAtlasWidth;
        font.atlas_height_ = height;
        font.atlas_.assign(static_cast<std::size_t>(kAtlasWidth) * height, 0);
        for (std::size_t i = 0; i < fields.size(); ++i) {
            Glyph& g = font.glyphs_[i];
            g.x = rects[i].x, g.y = rects[i].y, g.w = fields[i].w, g.h = fields[i].h;
            for (int row = 0; row < g.h; ++row) {
                std::copy_n(fields[i].pixels + static_cast<std::size_t>(row) * g.w, g.w,
                            font.atlas_.begin() + static_cast<std::ptrdiff_t>((g.y + row) * kAtlasWidth + g.x));
            }
        }
    }
    for (Field& f : fields) stbtt_FreeSDF(f.pixels, nullptr);
    if (!packed) throw RenderError(ErrorKind::unavailable, "font " + ttf.string() + ": glyphs do not fit the atlas");
    std::sort(font.glyphs_.begin(), font.glyphs_.end(),
              [](const Glyph& a, const Glyph& b) { return a.codepoint < b.codepoint; });
    if (!font.has_glyph(U'?')) throw RenderError(ErrorKind::unavailable, "font " + ttf.string() + " has no '?'");
    font.file_ = std::move(file);
    return font;
}

bool Font::has_glyph(char32_t codepoint) const {
    const auto it = std::lower_bound(glyphs_.begin(), glyphs_.end(), codepoint,
                                     [](const Glyph& g, char32_t c) { return g.codepoint < c; });
    return it != glyphs_.end() && it->codepoint == codepoint;
}

const Font::Glyph& Font::glyph(char32_t codepoint) const {
    if (codepoint == U'\t') codepoint = U' ';
    const auto find = [&](char32_t c) {
        return std::lower_bound(glyphs_.begin(), glyphs_.end(), c,
                                [](const Glyph& g, char32_t x) { return g.codepoint < x; });
    };
    auto it = find(codepoint);
    if (it == glyphs_.end() || it->codepoint != codepoint) it = find(U'?');
    return *it;
}

float Font::kerning(const Glyph& left, const Glyph& right) const {
    const float scale = stbtt_ScaleForPixelHeight(&file_->info, bake_size_);
    return static_cast<float>(stbtt_GetGlyphKernAdvance(&file_->info, left.index, right.index)) * scale;
}

std::vector<GlyphQuad> Font::layout(std::string_view utf8, float x, float y, float size_px) const {
    std::vector<GlyphQuad> quads;
    if (!(size_px > 0) || !std::isfinite(x) || !std::isfinite(y)) return quads;
    const float k = size_px / bake_size_;  // screen px per bake px
    float pen = x, baseline = y + ascent_ * k;
    const Glyph* previous = nullptr;
    for (std::size_t p = 0; p < utf8.size();) {
        const char32_t c = next_codepoint(utf8, p);
        if (c == U'\n') {
            pen = x;
            baseline += line_height_ * k;
            previous = nullptr;
            continue;
        }
        const Glyph& g = glyph(c);
        if (previous != nullptr) pen += kerning(*previous, g) * k;
        if (g.w > 0 && g.h > 0) {
            GlyphQuad q;
            q.x0 = pen + g.x_offset * k;
            q.y0 = baseline + g.y_offset * k;
            q.x1 = q.x0 + static_cast<float>(g.w) * k;
            q.y1 = q.y0 + static_cast<float>(g.h) * k;
            q.u0 = static_cast<float>(g.x) / static_cast<float>(atlas_width_);
            q.v0 = static_cast<float>(g.y) / static_cast<float>(atlas_height_);
            q.u1 = static_cast<float>(g.x + g.w) / static_cast<float>(atlas_width_);
            q.v1 = static_cast<float>(g.y + g.h) / static_cast<float>(atlas_height_);
            quads.push_back(q);
        }
        pen += g.advance * k;
        previous = &g;
    }
    return quads;
}

TextBox Font::measure(std::string_view utf8, float size_px) const {
    TextBox box;
    if (!(size_px > 0)) return box;
    const float k = size_px / bake_size_;
    float width = 0;
    int lines = 1;
    const Glyph* previous = nullptr;
    for (std::size_t p = 0; p < utf8.size();) {
        const char32_t c = next_codepoint(utf8, p);
        if (c == U'\n') {
            box.width = std::max(box.width, width);
            width = 0;
            ++lines;
            previous = nullptr;
            continue;
        }
        const Glyph& g = glyph(c);
        if (previous != nullptr) width += kerning(*previous, g) * k;
        width += g.advance * k;
        previous = &g;
    }
    box.width = std::max(box.width, width);
    // The last line is the text height (ascent + descent), the others a full line each.
    box.height = static_cast<float>(lines - 1) * line_height_ * k + size_px;
    return box;
}

void draw_text(Image& image, const Font& font, std::string_view utf8, float x, float y, float size_px, Rgba8 color) {
    if (image.empty()) return;
    const float k = size_px / font.bake_size();
    // Atlas levels per screen pixel: the coverage ramp is one pixel wide.
    const float levels_per_px = Font::kDistanceScale / k;
    const auto& atlas = font.atlas();
    const int aw = font.atlas_width(), ah = font.atlas_height();
    auto texel = [&](int tx, int ty) {
        tx = std::clamp(tx, 0, aw - 1), ty = std::clamp(ty, 0, ah - 1);
        return static_cast<float>(atlas[static_cast<std::size_t>(ty) * aw + tx]);
    };
    for (const GlyphQuad& q : font.layout(utf8, x, y, size_px)) {
        const int px0 = std::max(0, static_cast<int>(std::floor(q.x0))),
                  px1 = std::min(image.width, static_cast<int>(std::ceil(q.x1)));
        const int py0 = std::max(0, static_cast<int>(std::floor(q.y0))),
                  py1 = std::min(image.height, static_cast<int>(std::ceil(q.y1)));
        for (int py = py0; py < py1; ++py) {
            for (int px = px0; px < px1; ++px) {
                // The pixel centre in atlas texels, sampled bilinearly (texel centres at +0.5).
                const float u =
                    (q.u0 + ((static_cast<float>(px) + 0.5f - q.x0) / (q.x1 - q.x0)) * (q.u1 - q.u0)) * aw - 0.5f;
                const float v =
                    (q.v0 + ((static_cast<float>(py) + 0.5f - q.y0) / (q.y1 - q.y0)) * (q.v1 - q.v0)) * ah - 0.5f;
                const int tx = static_cast<int>(std::floor(u)), ty = static_cast<int>(std::floor(v));
                const float fx = u - static_cast<float>(tx), fy = v - static_cast<float>(ty);
                const float d = (texel(tx, ty) * (1 - fx) + texel(tx + 1, ty) * fx) * (1 - fy) +
                                (texel(tx, ty + 1) * (1 - fx) + texel(tx + 1, ty + 1) * fx) * fy;
                const float alpha =
                    std::clamp((d - static_cast<float>(Font::kOnEdge)) / levels_per_px + 0.5f, 0.0f, 1.0f) *
                    (static_cast<float>(color.a) / 255.0f);
                if (alpha <= 0.0f) continue;
                std::uint8_t* out = image.at(px, py);
                const std::uint8_t src[3] = {color.r, color.g, color.b};
                for (int c = 0; c < 3; ++c) {
                    out[c] = static_cast<std::uint8_t>(
                        std::lround(static_cast<float>(out[c]) + (static_cast<float>(src[c]) - out[c]) * alpha));
                }
            }
        }
    }
}

}  // namespace render
