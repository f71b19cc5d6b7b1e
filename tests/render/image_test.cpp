// Images: PNG round trips, atomic writes that leave nothing behind on failure,
// the per-pixel comparison, and contact sheets.
#include "render/image.h"

#include "render/font.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace render {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder for one test.
fs::path scratch(const std::string& name) {
    const char* root = std::getenv("PLAUSIBLE_TEST_RESULTS");
    const fs::path dir = fs::path(root != nullptr ? root : fs::temp_directory_path().string()) / "image" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Every pixel differs from its neighbours, so a flipped row or a swapped
// channel cannot go unnoticed.
Image gradient(int w, int h, int channels) {
    Image image = make_image(w, h, channels, Rgba8{});
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = image.at(x, y);
            p[0] = static_cast<std::uint8_t>(x * 7);
            p[1] = static_cast<std::uint8_t>(y * 11);
            p[2] = static_cast<std::uint8_t>(x + y);
            if (channels == 4) p[3] = static_cast<std::uint8_t>(255 - x);
        }
    }
    return image;
}

TEST(Image, PngRoundTripKeepsEveryByte) {
    const fs::path dir = scratch("round_trip");
    for (int channels : {3, 4}) {
        const Image image = gradient(37, 19, channels);  // odd width: rows are not 4-byte aligned
        const fs::path png = dir / ("gradient" + std::to_string(channels) + ".png");
        std::ofstream(png, std::ios::binary) << encode_png(image);
        const Image back = read_png(png, channels);
        EXPECT_EQ(back.width, 37);
        EXPECT_EQ(back.height, 19);
        EXPECT_EQ(back.pixels, image.pixels) << channels << " channels";
    }
}

TEST(Image, EncodeRefusesAMalformedImage) {
    Image bad = gradient(8, 8, 3);
    bad.pixels.pop_back();
    EXPECT_THROW(encode_png(bad), RenderError);
}

TEST(Image, ReadRefusesMissingAndNonPngFiles) {
    const fs::path dir = scratch("read");
    try {
        read_png(dir / "nothing.png");
        FAIL();
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("nothing.png"), std::string::npos) << e.what();
    }
    std::ofstream(dir / "text.png") << "not a PNG\n";
    EXPECT_THROW(read_png(dir / "text.png"), RenderError);
    EXPECT_THROW(read_png(dir / "text.png", 2), RenderError);
}

TEST(Image, MakeImageRefusesBadSizes) {
    for (const auto& [w, h, c] : {std::tuple{0, 4, 3}, {4, -1, 3}, {20000, 4, 3}, {4, 4, 2}}) {
        EXPECT_THROW(make_image(w, h, c, Rgba8{}), RenderError) << w << "x" << h << "x" << c;
    }
    const Image image = make_image(3, 2, 4, Rgba8{1, 2, 3, 4});
    EXPECT_EQ(image.pixel(2, 1), (Rgba8{1, 2, 3, 4}));
}

TEST(Image, DiffCountsPixelsOverTheTolerance) {
    const Image a = gradient(20, 10, 3);
    Image b = a;
    b.at(3, 4)[1] = static_cast<std::uint8_t>(b.at(3, 4)[1] + 10);  // one pixel, 10 levels
    b.at(5, 5)[2] = static_cast<std::uint8_t>(b.at(5, 5)[2] + 2);   // one pixel, 2 levels
    const ImageDiff same = diff_images(a, a, 0);
    EXPECT_EQ(same.max_channel_diff, 0);
    EXPECT_EQ(same.pixels_over, 0u);
    const ImageDiff d = diff_images(b, a, 3);
    EXPECT_EQ(d.max_channel_diff, 10);
    EXPECT_EQ(d.pixels_over, 1u);
    EXPECT_DOUBLE_EQ(d.share_over, 1.0 / 200.0);
    EXPECT_EQ(diff_images(b, a, 1).pixels_over, 2u);
    // The diff image marks the differing pixel in red.
    EXPECT_EQ(d.diff.pixel(3, 4), (Rgba8{230, 20, 20, 255}));
    EXPECT_EQ(d.diff.pixel(0, 0).r, d.diff.pixel(0, 0).g);  // grey elsewhere
    EXPECT_THROW(diff_images(a, gradient(20, 11, 3), 3), RenderError);
    EXPECT_THROW(diff_images(a, gradient(20, 10, 4), 3), RenderError);
}

TEST(Image, ContactSheetTilesFramesWithLabels) {
    const Font& font = Font::default_font();
    const std::vector<Image> frames = {make_image(40, 30, 3, Rgba8{200, 0, 0, 255}),
                                       make_image(40, 30, 3, Rgba8{0, 200, 0, 255}),
                                       make_image(40, 30, 3, Rgba8{0, 0, 200, 255})};
    const std::vector<std::string> labels = {"0", "30", "60"};
    SheetOptions options;
    options.padding = 4;
    options.label_size = 12.0f;
    const Image sheet = contact_sheet(frames, labels, font, options);
    const int label_height = 17;  // ceil(1.4 x 12 px)
    EXPECT_EQ(sheet.width, 4 + 3 * (40 + 4));
    EXPECT_EQ(sheet.height, 4 + 30 + label_height + 4);
    for (int i = 0; i < 3; ++i) {
        const int x0 = 4 + i * 44;
        EXPECT_EQ(sheet.pixel(x0, 4), frames[i].pixel(0, 0)) << "frame " << i << " top-left";
        EXPECT_EQ(sheet.pixel(x0 + 39, 33), frames[i].pixel(0, 0)) << "frame " << i << " bottom-right";
        // Its label: light pixels on the dark sheet under the tile.
        int light = 0;
        for (int y = 34; y < 34 + label_height; ++y) {
            for (int x = x0; x < x0 + 40; ++x) light += sheet.pixel(x, y).r > 128 ? 1 : 0;
        }
        EXPECT_GT(light, 5) << "label " << labels[i];
    }
    // Two columns: a second row.
    options.columns = 2;
    EXPECT_EQ(contact_sheet(frames, labels, font, options).height, 4 + 2 * (30 + label_height + 4));

    EXPECT_THROW(contact_sheet({}, {}, font), RenderError);
    EXPECT_THROW(contact_sheet(frames, std::vector<std::string>{"a"}, font), RenderError);
    const std::vector<Image> mixed = {frames[0], make_image(41, 30, 3, Rgba8{})};
    EXPECT_THROW(contact_sheet(mixed, std::vector<std::string>{"a", "b"}, font), RenderError);
}

}  // namespace
}  // namespace render
