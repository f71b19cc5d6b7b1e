// The golden image metric: byte-identical passes; small errors (d <= 3
// levels) pass on up to 5% of the pixels, large ones on up to 0.01%.
#include "render/golden.h"

#include <gtest/gtest.h>

namespace render {
namespace {

Image grey(int w = 320, int h = 240) { return make_image(w, h, 3, Rgba8{120, 130, 140, 255}); }

// Adds `d` levels to the red channel of `count` pixels, row by row from (x0, y0).
Image with_errors(int count, int d, int x0 = 10, int y0 = 20) {
    Image image = grey();
    for (int k = 0; k < count; ++k) {
        const int x = x0 + k % 50, y = y0 + k / 50;
        image.at(x, y)[0] = static_cast<std::uint8_t>(image.at(x, y)[0] + d);
    }
    return image;
}

TEST(Golden, IdenticalImagesPassAndSaySo) {
    const GoldenDiff d = compare_golden(grey(), grey());
    EXPECT_TRUE(d.identical);
    EXPECT_TRUE(d.pass);
    EXPECT_EQ(d.summary, "identical");
}

TEST(Golden, SmallErrorsPassUpToFivePercent) {
    const int pixels = 320 * 240;  // 76800; 5% is 3840
    const GoldenDiff under = compare_golden(with_errors(3840, 3), grey());
    EXPECT_FALSE(under.identical);
    EXPECT_TRUE(under.pass) << under.summary;
    EXPECT_EQ(under.small_pixels, 3840u);
    EXPECT_DOUBLE_EQ(under.small_share, 3840.0 / pixels);
    const GoldenDiff over = compare_golden(with_errors(3841, 3), grey());
    EXPECT_FALSE(over.pass) << over.summary;
    EXPECT_EQ(over.diff.pixel(10, 20), (Rgba8{240, 200, 20, 255})) << "small errors are yellow";
}

TEST(Golden, LargeErrorsPassUpToOneInTenThousand) {
    // 0.01% of 76800 px is 7.68 px: 7 pass, 8 fail.
    const GoldenDiff seven = compare_golden(with_errors(7, 50), grey());
    EXPECT_TRUE(seven.pass) << seven.summary;
    EXPECT_EQ(seven.large_pixels, 7u);
    EXPECT_EQ(seven.max_d, 50);
    const GoldenDiff eight = compare_golden(with_errors(8, 50), grey());
    EXPECT_FALSE(eight.pass) << eight.summary;
    // The box is exactly the changed pixels: x 10..17, y 20.
    EXPECT_EQ(eight.large_box.x0, 10);
    EXPECT_EQ(eight.large_box.x1, 18);
    EXPECT_EQ(eight.large_box.y0, 20);
    EXPECT_EQ(eight.large_box.y1, 21);
    EXPECT_EQ(eight.diff.pixel(12, 20), (Rgba8{230, 25, 25, 255})) << "large errors are red";
    EXPECT_EQ(eight.diff.pixel(12, 19), (Rgba8{30, 80, 220, 255})) << "the box is outlined";
    EXPECT_NE(eight.summary.find("max d 50"), std::string::npos) << eight.summary;
}

TEST(Golden, SizeMismatchIsReportedNotThrown) {
    const GoldenDiff d = compare_golden(grey(330, 240), grey());
    EXPECT_TRUE(d.size_mismatch);
    EXPECT_FALSE(d.pass);
    EXPECT_EQ(d.summary, "size 330x240, expected 320x240");
}

TEST(Golden, ThresholdsAreValidated) {
    EXPECT_THROW(validate(GoldenThresholds{.small_max_d = -1}), RenderError);
    EXPECT_THROW(validate(GoldenThresholds{.small_share = 1.5}), RenderError);
    EXPECT_THROW(validate(GoldenThresholds{.large_share = -0.1}), RenderError);
    // A looser threshold turns the eight-pixel failure into a pass.
    EXPECT_TRUE(compare_golden(with_errors(8, 50), grey(), {.large_share = 0.001}).pass);
}

}  // namespace
}  // namespace render
