#include "thicket/render/image.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "thicket/core/error.h"
#include "thicket/util/atomic_file.h"

// stb_image_write is compiled into this file with internal linkage, so the library carries its
// own PNG encoder and never clashes with another copy of stb in the program that links it.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace thicket {

Rgb8 to_rgb8(Vec3 colour) {
    auto q = [](float c) -> uint8_t {
        if (!(c > 0.0f)) return 0;  // also catches NaN
        if (c >= 1.0f) return 255;
        return uint8_t(std::lround(c * 255.0f));
    };
    return {q(colour.x), q(colour.y), q(colour.z)};
}

Image::Image(int width, int height, Rgb8 fill) : width_(width), height_(height) {
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
        throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not within 1x1 to " +
                    std::to_string(kMaxSide) + "x" + std::to_string(kMaxSide));
    pixels_.assign(size_t(width) * size_t(height), fill);
}

void Image::fill_rect(int x0, int y0, int x1, int y1, Rgb8 c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width_);
    y1 = std::min(y1, height_);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) at(x, y) = c;
}

void write_png(const Image& image, const std::string& path) {
    if (image.width() < 1 || image.height() < 1) throw Error(path + ": cannot write an empty image");
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width(), image.height(), 3, image.data(), image.width() * 3))
        throw Error(path + ": cannot encode the image as PNG");
    write_file_atomically(path, bytes);
}

}  // namespace thicket
