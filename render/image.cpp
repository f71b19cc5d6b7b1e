// Images in memory and on disk (see image.h). stb_image and stb_image_write
// come compiled in Debian's libstb: only their headers are included here.
#include "render/image.h"

#include "render/font.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace render {
namespace {

constexpr int kMaxSide = 16384;  // px; larger than any frame or sheet the project makes

void check_size(int width, int height, int channels, const char* what) {
    if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide) {
        throw RenderError(ErrorKind::bad_input, std::string(what) + ": image size " + std::to_string(width) + "x" +
                                                    std::to_string(height) + " must be within 1x1 .. " +
                                                    std::to_string(kMaxSide) + "x" + std::to_string(kMaxSide) + " px");
    }
    if (channels != 3 && channels != 4) {
        throw RenderError(ErrorKind::bad_input,
                          std::string(what) + ": channels must be 3 or 4 (got " + std::to_string(channels) + ")");
    }
}

// stbi_write_png_to_func's sink: appends to a byte vector.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

Rgba8 Image::pixel(int x, int y) const {
    const std::uint8_t* p = at(x, y);
    return Rgba8{p[0], p[1], p[2], channels == 4 ? p[3] : std::uint8_t{255}};
}

Image make_image(int width, int height, int channels, Rgba8 fill) {
    check_size(width, height, channels, "make_image");
    Image image;
    image.width = width;
    image.height = height;
    image.channels = channels;
    image.pixels.resize(static_cast<std::size_t>(width) * height * channels);
    const std::uint8_t rgba[4] = {fill.r, fill.g, fill.b, fill.a};
    for (std::size_t i = 0; i < image.pixels.size(); i += channels) std::memcpy(&image.pixels[i], rgba, channels);
    return image;
}

std::string encode_png(const Image& image) {
    check_size(image.width, image.height, image.channels, "encode_png");
    if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * image.channels) {
        throw RenderError(ErrorKind::bad_input, "encode_png: image holds " + std::to_string(image.pixels.size()) +
                                                    " bytes, not width x height x channels");
    }
    std::vector<unsigned char> png;
    if (stbi_write_png_to_func(&append_bytes, &png, image.width, image.height, image.channels, image.pixels.data(),
                               image.width * image.channels) == 0) {
        throw RenderError(ErrorKind::bad_input, "encode_png: the PNG encoder failed");
    }
    return std::string(png.begin(), png.end());
}

Image read_png(const std::filesystem::path& path, int channels) {
    if (channels != 3 && channels != 4) {
        throw RenderError(ErrorKind::bad_input,
                          "read_png: channels must be 3 or 4 (got " + std::to_string(channels) + ")");
    }
    int width = 0, height = 0, in_file = 0;
    stbi_uc* data = stbi_load(path.c_str(), &width, &height, &in_file, channels);
    if (data == nullptr) {
        const std::string reason = std::filesystem::exists(path) ? stbi_failure_reason() : "no such file";
        throw RenderError(ErrorKind::bad_input, "cannot read " + path.string() + " as PNG: " + reason);
    }
    Image image;
    image.width = width;
    image.height = height;
    image.channels = channels;
    image.pixels.assign(data, data + static_cast<std::size_t>(width) * height * channels);
    stbi_image_free(data);
    return image;
}

ImageDiff diff_images(const Image& actual, const Image& expected, int tolerance) {
    if (actual.width != expected.width || actual.height != expected.height || actual.channels != expected.channels) {
        throw RenderError(ErrorKind::bad_input,
                          "cannot compare a " + std::to_string(actual.width) + "x" + std::to_string(actual.height) +
                              "x" + std::to_string(actual.channels) + " image with a " +
                              std::to_string(expected.width) + "x" + std::to_string(expected.height) + "x" +
                              std::to_string(expected.channels) + " one");
    }
    ImageDiff result;
    result.diff.width = actual.width;
    result.diff.height = actual.height;
    result.diff.channels = 3;
    result.diff.pixels.resize(static_cast<std::size_t>(actual.width) * actual.height * 3);
    const int c = actual.channels;
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const std::uint8_t* a = actual.at(x, y);
            const std::uint8_t* e = expected.at(x, y);
            int d = 0;
            for (int k = 0; k < c; ++k) d = std::max(d, std::abs(int(a[k]) - int(e[k])));
            result.max_channel_diff = std::max(result.max_channel_diff, d);
            std::uint8_t* out = result.diff.at(x, y);
            if (d > tolerance) {
                ++result.pixels_over;
                out[0] = 230, out[1] = 20, out[2] = 20;
            } else {
                // A faded grey copy of the expected image: the scene is recognisable
                // behind the red without competing with it.
                const int grey = (2126 * e[0] + 7152 * e[1] + 722 * e[2]) / 10000;
                out[0] = out[1] = out[2] = static_cast<std::uint8_t>(160 + grey * 95 / 255);
            }
        }
    }
    result.share_over = static_cast<double>(result.pixels_over) / (static_cast<double>(actual.width) * actual.height);
    return result;
}

Image contact_sheet(std::span<const Image> frames, std::span<const std::string> labels, const Font& font,
                    const SheetOptions& options) {
    if (frames.empty()) throw RenderError(ErrorKind::bad_input, "contact sheet: no frames");
    if (labels.size() != frames.size()) {
        throw RenderError(ErrorKind::bad_input, "contact sheet: " + std::to_string(frames.size()) + " frames but " +
                                                    std::to_string(labels.size()) + " labels");
    }
    const Image& first = frames.front();
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const Image& f = frames[i];
        if (f.width != first.width || f.height != first.height || f.channels != first.channels || f.empty()) {
            throw RenderError(ErrorKind::bad_input,
                              "contact sheet: frame " + std::to_string(i) + " is " + std::to_string(f.width) + "x" +
                                  std::to_string(f.height) + "x" + std::to_string(f.channels) + ", frame 0 is " +
                                  std::to_string(first.width) + "x" + std::to_string(first.height) + "x" +
                                  std::to_string(first.channels));
        }
    }
    if (options.padding < 0 || !(options.label_size > 0) || options.columns < 0) {
        throw RenderError(ErrorKind::bad_input, "contact sheet: padding >= 0, label size > 0 and columns >= 0 needed");
    }
    const int n = static_cast<int>(frames.size());
    const int columns = options.columns == 0 ? n : std::min(options.columns, n);
    const int rows = (n + columns - 1) / columns;
    const int pad = options.padding;
    const int label_height = static_cast<int>(std::ceil(options.label_size * 1.4f));
    const int cell_w = first.width + pad, cell_h = first.height + label_height + pad;
    Image sheet = make_image(pad + columns * cell_w, pad + rows * cell_h, first.channels, options.background);
    const std::size_t row_bytes = static_cast<std::size_t>(first.width) * first.channels;
    for (int i = 0; i < n; ++i) {
        const int x0 = pad + (i % columns) * cell_w, y0 = pad + (i / columns) * cell_h;
        for (int y = 0; y < first.height; ++y) {
            std::memcpy(sheet.at(x0, y0 + y), frames[i].at(0, y), row_bytes);
        }
        const TextBox box = font.measure(labels[i], options.label_size);
        const float x = static_cast<float>(x0) + 0.5f * (static_cast<float>(first.width) - box.width);
        const float y = static_cast<float>(y0 + first.height) + 0.2f * options.label_size;
        draw_text(sheet, font, labels[i], std::max(static_cast<float>(x0), x), y, options.label_size,
                  options.label_color);
    }
    return sheet;
}

}  // namespace render
