// Images in memory and on disk: PNG read and write (stb_image, stb_image_write),
// an atomic write (temp file + rename: a reader never sees half a PNG), the
// per-pixel comparison the golden checks and backend tests use, and the contact
// sheet (N frames tiled into one labelled PNG).
#pragma once

#include "render/error.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace render {

class Font;

// An 8-bit colour, sRGB encoded as stored in PNG files.
struct Rgba8 {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
    friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

// Pixels row-major, top row first, `channels` bytes per pixel (3 = RGB, 4 = RGBA).
struct Image {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<std::uint8_t> pixels;  // width * height * channels bytes

    std::uint8_t* at(int x, int y) { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels; }
    const std::uint8_t* at(int x, int y) const {
        return pixels.data() + (static_cast<std::size_t>(y) * width + x) * channels;
    }
    Rgba8 pixel(int x, int y) const;  // alpha is 255 for RGB images
    bool empty() const { return width == 0 || height == 0; }
};

// A width x height image filled with one colour. Throws RenderError(bad_input)
// for a size <= 0 or above 16384, or channels other than 3 or 4.
Image make_image(int width, int height, int channels, Rgba8 fill);

// The PNG file of `image`, in memory (where it goes is the commands' choice:
// scenes/common/output_file.h). Throws RenderError(bad_input) for an image
// whose size or bytes do not hold together, or when the encoder fails.
std::string encode_png(const Image& image);

// Reads a PNG into an image with `channels` channels (3 or 4). Throws
// RenderError(bad_input) naming the path when it is missing or not a PNG.
Image read_png(const std::filesystem::path& path, int channels = 4);

// Per-pixel comparison of two images of the same size and channel count.
// A pixel "differs" when its largest channel difference exceeds `tolerance`
// (in 8-bit levels). The diff image shows differing pixels in red over a
// faded grey copy of `expected`, so a failure is readable at a glance.
struct ImageDiff {
    int max_channel_diff = 0;     // largest |a - b| over all pixels and channels, 8-bit levels
    std::size_t pixels_over = 0;  // pixels whose largest channel difference > tolerance
    double share_over = 0.0;      // pixels_over / (width * height), 0..1
    Image diff;                   // RGB visualisation, same size as the inputs
};
// Throws RenderError(bad_input) when sizes or channel counts differ.
ImageDiff diff_images(const Image& actual, const Image& expected, int tolerance);

// N frames of the same size tiled into one sheet, left to right then top to
// bottom, each with its label written under it in the given font.
struct SheetOptions {
    int columns = 0;                    // 0: all frames in one row (a filmstrip)
    int padding = 4;                    // px between tiles and around the edge
    float label_size = 14.0f;           // px, text height of the labels
    Rgba8 background{32, 32, 36, 255};  // sheet colour behind the tiles
    Rgba8 label_color{235, 235, 235, 255};
};
// Throws RenderError(bad_input) for zero frames, frames of different sizes or
// channel counts, or a label count different from the frame count.
Image contact_sheet(std::span<const Image> frames, std::span<const std::string> labels, const Font& font,
                    const SheetOptions& options = {});

}  // namespace render
