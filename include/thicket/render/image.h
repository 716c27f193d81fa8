#pragma once
/// 8-bit RGB image, row 0 at the top, and PNG output.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/core/vec3.h"

namespace thicket {

struct Rgb8 {
    uint8_t r = 0, g = 0, b = 0;
    constexpr bool operator==(const Rgb8&) const = default;
};

/// Maps a colour with components in [0, 1] (clamped; NaN gives 0) to 8 bits, rounding.
Rgb8 to_rgb8(Vec3 colour);

class Image {
public:
    Image() = default;
    /// A width x height image filled with `fill`; throws Error unless both sizes are in
    /// [1, kMaxSide].
    Image(int width, int height, Rgb8 fill = {});

    static constexpr int kMaxSide = 32768;

    int width() const { return width_; }
    int height() const { return height_; }
    Rgb8& at(int x, int y) { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; }
    const Rgb8& at(int x, int y) const { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; }
    /// Writes a pixel if (x, y) lies inside the image; drawing code may run off the edges.
    void set(int x, int y, Rgb8 c) {
        if (x >= 0 && y >= 0 && x < width_ && y < height_) at(x, y) = c;
    }
    /// Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
    void fill_rect(int x0, int y0, int x1, int y1, Rgb8 c);
    /// Packed RGB bytes, row-major from the top row.
    const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(pixels_.data()); }

private:
    int width_ = 0, height_ = 0;
    std::vector<Rgb8> pixels_;
};

static_assert(sizeof(Rgb8) == 3, "Image::data() relies on packed RGB triples");

/// Draws `text` in the built-in 5x7 pixel font with its top-left corner at (x, y), every font
/// pixel a scale x scale square, clipped to the image. Knows 0-9 . - / : % and the letters
/// a d e m n o r s x y; other characters advance like a blank.
void draw_text(Image& image, int x, int y, std::string_view text, int scale, Rgb8 colour);
/// Width in pixels of draw_text's output: 6 * scale per character, less the last gap.
int text_width(std::string_view text, int scale);
/// Height of a line of draw_text's output: 7 * scale.
constexpr int text_height(int scale) { return 7 * scale; }

/// Writes `image` as an 8-bit RGB PNG. The file is written under a temporary name in the same
/// directory and renamed into place, so `path` is either the complete new image or untouched.
/// Throws Error naming `path` and the reason on failure.
void write_png(const Image& image, const std::string& path);

}  // namespace thicket
