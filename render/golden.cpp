#include "render/golden.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace render {
namespace {

std::string percent(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g%%", 100.0 * share);
    return text;
}

// Copies `src` (any channel count) into `dst` (RGB) at (x0, y0).
void blit(Image& dst, const Image& src, int x0, int y0) {
    for (int y = 0; y < src.height; ++y) {
        for (int x = 0; x < src.width; ++x) {
            const std::uint8_t* s = src.at(x, y);
            std::uint8_t* d = dst.at(x0 + x, y0 + y);
            d[0] = s[0], d[1] = s[1], d[2] = s[2];
        }
    }
}

}  // namespace

GoldenThresholds for_another_renderer(GoldenThresholds t) {
    t.large_share = std::min(1.0, t.large_share * kAnotherRendererLargeFactor);
    return t;
}

void validate(const GoldenThresholds& t) {
    if (t.small_max_d < 0 || t.small_max_d > 255) {
        throw RenderError(ErrorKind::bad_input, "thresholds.small_max_d must be within 0 .. 255 levels (got " +
                                                    std::to_string(t.small_max_d) + ")");
    }
    auto share = [](double v, const char* name) {
        if (!(v >= 0.0 && v <= 1.0)) {
            char text[32];
            std::snprintf(text, sizeof text, "%g", v);
            throw RenderError(
                ErrorKind::bad_input,
                std::string("thresholds.") + name + " must be a share within 0 .. 1 of the pixels (got " + text + ")");
        }
    };
    share(t.small_share, "small_share");
    share(t.large_share, "large_share");
}

GoldenDiff compare_golden(const Image& actual, const Image& expected, const GoldenThresholds& t) {
    validate(t);
    GoldenDiff r;
    if (actual.width != expected.width || actual.height != expected.height) {
        r.size_mismatch = true;
        r.summary = "size " + std::to_string(actual.width) + "x" + std::to_string(actual.height) + ", expected " +
                    std::to_string(expected.width) + "x" + std::to_string(expected.height);
        return r;
    }
    const int w = actual.width, h = actual.height;
    r.diff = make_image(w, h, 3, Rgba8{});
    r.large_box = PixelBox{w, h, 0, 0};
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::uint8_t* a = actual.at(x, y);
            const std::uint8_t* e = expected.at(x, y);
            int d = 0;
            for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(e[k])));
            r.max_d = std::max(r.max_d, d);
            std::uint8_t* out = r.diff.at(x, y);
            if (d > t.small_max_d) {
                ++r.large_pixels;
                out[0] = 230, out[1] = 25, out[2] = 25;
                r.large_box.x0 = std::min(r.large_box.x0, x), r.large_box.y0 = std::min(r.large_box.y0, y);
                r.large_box.x1 = std::max(r.large_box.x1, x + 1), r.large_box.y1 = std::max(r.large_box.y1, y + 1);
            } else if (d > 0) {
                ++r.small_pixels;
                out[0] = 240, out[1] = 200, out[2] = 20;
            } else {
                // Faded grey: the scene is recognisable behind the colours.
                const int grey = (2126 * e[0] + 7152 * e[1] + 722 * e[2]) / 10000;
                out[0] = out[1] = out[2] = static_cast<std::uint8_t>(170 + grey * 85 / 255);
            }
        }
    }
    if (r.large_pixels == 0) r.large_box = PixelBox{};
    // The large-error box, outlined one pixel outside it in blue.
    if (!r.large_box.empty()) {
        const PixelBox& b = r.large_box;
        auto mark = [&](int x, int y) {
            if (x < 0 || y < 0 || x >= w || y >= h) return;
            std::uint8_t* p = r.diff.at(x, y);
            p[0] = 30, p[1] = 80, p[2] = 220;
        };
        for (int x = b.x0 - 1; x <= b.x1; ++x) mark(x, b.y0 - 1), mark(x, b.y1);
        for (int y = b.y0 - 1; y <= b.y1; ++y) mark(b.x0 - 1, y), mark(b.x1, y);
    }
    const double n = static_cast<double>(w) * h;
    r.small_share = static_cast<double>(r.small_pixels) / n;
    r.large_share = static_cast<double>(r.large_pixels) / n;
    r.identical = r.small_pixels == 0 && r.large_pixels == 0;
    r.pass = r.identical || (r.small_share <= t.small_share && r.large_share <= t.large_share);
    if (r.identical) {
        r.summary = "identical";
        return r;
    }
    r.summary = "large errors on " + percent(r.large_share) + " (" + std::to_string(r.large_pixels) + " px, limit " +
                percent(t.large_share) + "), small on " + percent(r.small_share) + " (" +
                std::to_string(r.small_pixels) + " px, limit " + percent(t.small_share) + "), max d " +
                std::to_string(r.max_d);
    if (!r.large_box.empty()) {
        r.summary += ", large-error box x " + std::to_string(r.large_box.x0) + ".." +
                     std::to_string(r.large_box.x1 - 1) + " y " + std::to_string(r.large_box.y0) + ".." +
                     std::to_string(r.large_box.y1 - 1);
    }
    return r;
}

Image side_by_side(const Image& expected, const Image& actual, const Image& diff, const Font& font) {
    const Image* columns[3] = {&expected, &actual, &diff};
    const char* captions[3] = {"expected", "actual", "diff"};
    constexpr int kPad = 6;
    constexpr float kCaption = 14.0f;  // px
    const int caption_h = static_cast<int>(kCaption * 1.5f);
    int width = kPad, height = 0;
    for (const Image* c : columns) {
        if (c->empty()) continue;
        width += c->width + kPad;
        height = std::max(height, c->height);
    }
    Image sheet = make_image(width, height + caption_h + 2 * kPad, 3, Rgba8{32, 32, 36, 255});
    int x = kPad;
    for (int i = 0; i < 3; ++i) {
        if (columns[i]->empty()) continue;
        draw_text(sheet, font, captions[i], static_cast<float>(x), static_cast<float>(kPad), kCaption,
                  Rgba8{235, 235, 235, 255});
        blit(sheet, *columns[i], x, kPad + caption_h);
        x += columns[i]->width + kPad;
    }
    return sheet;
}

}  // namespace render
