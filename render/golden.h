// The golden image metric (docs/design.md "Golden checks"): byte-identical is a
// pass; otherwise, with d the largest channel difference of a pixel, small
// errors (1 <= d <= small_max_d) are allowed on a share of the pixels and
// large errors (d > small_max_d) on a much smaller one. llvmpipe on another
// CPU may round a few edge pixels differently; a moved object changes a
// whole silhouette.
#pragma once

#include "render/font.h"
#include "render/image.h"

#include <cstddef>
#include <string>

namespace render {

struct GoldenThresholds {
    int small_max_d = 3;          // 8-bit levels; d above it is a large error
    double small_share = 0.05;    // 0..1 of pixels allowed to have small errors
    double large_share = 0.0001;  // 0..1 of pixels allowed to have large errors
};
// Throws RenderError(bad_input) naming the field and value.
void validate(const GoldenThresholds& t);

// Another renderer (another Mesa, an llvmpipe built with another LLVM or
// using other vector widths, a GPU) draws the same scene with its own
// rounding: the signed-distance-field text and anti-aliased edges move here
// and there. Measured: Debian sid's Mesa 26.2 against the goldens' Mesa
// 22.3, 0.011% to 0.033% of the pixels with large errors, nearly all on the
// text. A golden made by another renderer is judged with ten times the
// large-error share (0.1% by default); the state hashes still judge the
// physics exactly, and the verdict says which tolerance was used.
constexpr double kAnotherRendererLargeFactor = 10;
GoldenThresholds for_another_renderer(GoldenThresholds t);

struct PixelBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // px, half-open [x0, x1) x [y0, y1)
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct GoldenDiff {
    bool identical = false;
    bool pass = false;
    bool size_mismatch = false;  // then nothing below is meaningful and diff is empty
    std::string summary;         // one line, always with the numbers
    std::size_t small_pixels = 0, large_pixels = 0;
    double small_share = 0, large_share = 0;  // 0..1 of the pixels
    int max_d = 0;                            // 8-bit levels
    PixelBox large_box;                       // bounding box of the large errors
    Image diff;  // RGB: expected in faded grey, small errors yellow, large red, the large-error box outlined
};

GoldenDiff compare_golden(const Image& actual, const Image& expected, const GoldenThresholds& t = {});

// expected | actual | diff, side by side under captions.
Image side_by_side(const Image& expected, const Image& actual, const Image& diff, const Font& font);

}  // namespace render
