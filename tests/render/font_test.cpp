// The overlay font: DejaVu Sans baked into a signed-distance atlas through
// stb_truetype, laid out with the font's metrics.
#include "render/font.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace render {
namespace {

TEST(Font, DefaultFontHasTheLectureCharacters) {
    const Font& font = Font::default_font();
    EXPECT_GT(font.atlas_width(), 0);
    EXPECT_GT(font.atlas_height(), 0);
    EXPECT_EQ(font.atlas().size(), static_cast<std::size_t>(font.atlas_width()) * font.atlas_height());
    for (char32_t c : {U'A', U'z', U'0', U'Δ', U'ω', U'θ', U'·', U'²', U'±', U'→', U'≤'}) {
        EXPECT_TRUE(font.has_glyph(c)) << "U+" << std::hex << static_cast<unsigned>(c);
    }
}

TEST(Font, BakingIsDeterministic) {
    const Font a = Font::load(Font::default_path());
    const Font b = Font::load(Font::default_path());
    EXPECT_EQ(a.atlas(), b.atlas());
    EXPECT_EQ(a.atlas(), Font::default_font().atlas());
}

TEST(Font, MeasureScalesWithSizeAndCountsLines) {
    const Font& font = Font::default_font();
    const TextBox small = font.measure("Energy (J)", 10.0f);
    const TextBox large = font.measure("Energy (J)", 40.0f);
    EXPECT_GT(small.width, 20.0f);
    EXPECT_NEAR(large.width, 4.0f * small.width, 1e-3f * large.width) << "width is linear in the size, px";
    EXPECT_FLOAT_EQ(small.height, 10.0f);
    const TextBox two = font.measure("a\nlonger line", 10.0f);
    // DejaVu's line gap is 0: a line is the text height, or a little more for other fonts.
    EXPECT_GE(two.height, 2.0f * 10.0f);
    EXPECT_LT(two.height, 2.0f * 12.5f);
    EXPECT_FLOAT_EQ(two.width, font.measure("longer line", 10.0f).width);
    EXPECT_FLOAT_EQ(font.measure("", 10.0f).width, 0.0f);
}

TEST(Font, LayoutStaysInsideTheMeasuredBox) {
    const Font& font = Font::default_font();
    const std::string text = "t = 1.25 s  Δt = 1/60 s\nω·dt ≤ 2";
    const float x = 10, y = 20, size = 18;
    const TextBox box = font.measure(text, size);
    const auto quads = font.layout(text, x, y, size);
    ASSERT_FALSE(quads.empty());
    // Each quad includes the distance field's 4 px (at bake size) of padding.
    const float pad = 4.0f * size / font.bake_size() + 0.5f;
    for (const GlyphQuad& q : quads) {
        EXPECT_GE(q.x0, x - pad);
        EXPECT_LE(q.x1, x + box.width + pad);
        EXPECT_GE(q.y0, y - pad);
        EXPECT_LE(q.y1, y + box.height + pad);
        EXPECT_LT(q.u0, q.u1);
        EXPECT_LT(q.v0, q.v1);
    }
}

TEST(Font, MissingCharactersAndBadUtf8AreDrawnAsQuestionMarks) {
    const Font& font = Font::default_font();
    EXPECT_FALSE(font.has_glyph(U'中'));
    const auto question = font.layout("?", 0, 0, 16);
    // One '?' per missing character, and one per byte of a malformed sequence.
    for (const auto& [text, count] : {std::pair{"中", 1u}, {"\xff", 1u}, {"\xe2\x82", 2u}}) {
        const auto quads = font.layout(text, 0, 0, 16);
        ASSERT_EQ(quads.size(), count) << text;
        EXPECT_FLOAT_EQ(quads[0].u0, question[0].u0);
        EXPECT_FLOAT_EQ(quads[0].x1, question[0].x1);
    }
}

TEST(Font, LoadRefusesMissingAndNonFontFiles) {
    try {
        Font::load("/nonexistent/font.ttf");
        FAIL();
    } catch (const RenderError& e) {
        EXPECT_EQ(e.kind(), ErrorKind::unavailable);
        EXPECT_NE(std::string(e.what()).find("/nonexistent/font.ttf"), std::string::npos) << e.what();
    }
    const auto path = std::filesystem::temp_directory_path() / "plausible_not_a_font.ttf";
    std::ofstream(path) << "this is not a font";
    EXPECT_THROW(Font::load(path), RenderError);
    std::filesystem::remove(path);
}

TEST(Font, DrawTextPutsInkInsideItsBoxOnly) {
    const Font& font = Font::default_font();
    Image image = make_image(200, 60, 3, Rgba8{255, 255, 255, 255});
    const float x = 12, y = 15, size = 20;
    draw_text(image, font, "Plausible", x, y, size, Rgba8{0, 0, 0, 255});
    const TextBox box = font.measure("Plausible", size);
    int inside = 0, outside = 0;
    for (int py = 0; py < image.height; ++py) {
        for (int px = 0; px < image.width; ++px) {
            if (image.pixel(px, py).r > 128) continue;
            const bool in = px >= x - 1 && px <= x + box.width + 1 && py >= y - 1 && py <= y + box.height + 1;
            (in ? inside : outside)++;
        }
    }
    EXPECT_GT(inside, 80) << "dark pixels in the " << box.width << " x " << box.height << " px box";
    EXPECT_EQ(outside, 0);
}

}  // namespace
}  // namespace render
