#include "thicket/render/film.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include <tinyexr.h>

#include "thicket/core/error.h"
#include "thicket/util/atomic_file.h"

namespace thicket {

float srgb_encode(float x) {
    if (!(x > 0.0f)) return 0.0f;
    if (x >= 1.0f) return 1.0f;
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

Image tonemap_srgb(const std::vector<Vec3>& radiance, int width, int height, float exposure) {
    if (width < 1 || height < 1 || radiance.size() != size_t(width) * size_t(height))
        throw Error("tonemap: " + std::to_string(radiance.size()) + " pixels for a " + std::to_string(width) + "x" +
                    std::to_string(height) + " image");
    Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Vec3 c = radiance[size_t(y) * size_t(width) + size_t(x)] * exposure;
            image.at(x, y) = to_rgb8({srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z)});
        }
    return image;
}

ImageFormat image_format_of(const std::string& path) {
    const std::string name = std::filesystem::path(path).filename().string();
    const size_t dot = name.rfind('.');
    std::string ext = dot == std::string::npos || dot == 0 ? "" : name.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".exr") return ImageFormat::Exr;
    throw Error(path + ": " + (ext.empty() ? std::string("no extension") : "the extension '" + name.substr(dot) + "'") +
                " names no image format thicket writes: use .png (8-bit sRGB) or .exr (linear float)");
}

void write_exr(const std::vector<Vec3>& radiance, int width, int height, const std::string& path, float exposure) {
    if (width < 1 || height < 1 || radiance.size() != size_t(width) * size_t(height))
        throw Error(path + ": " + std::to_string(radiance.size()) + " pixels for a " + std::to_string(width) + "x" +
                    std::to_string(height) + " image");
    std::vector<float> rgb(radiance.size() * 3);
    for (size_t i = 0; i < radiance.size(); ++i) {
        const Vec3 c = radiance[i] * exposure;
        if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) && std::isfinite(radiance[i].x) &&
            std::isfinite(radiance[i].y) && std::isfinite(radiance[i].z)) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "exposure %g times pixel %zu's radiance (%g, %g, %g) passes float's range (3.4e38)",
                          double(exposure), i, double(radiance[i].x), double(radiance[i].y), double(radiance[i].z));
            throw Error(path + ": " + buf);
        }
        rgb[3 * i] = c.x;
        rgb[3 * i + 1] = c.y;
        rgb[3 * i + 2] = c.z;
    }
    write_atomically(path, [&](const std::string& temp) {
        // Opened here first: tinyexr 1.0.1's SaveEXR leaks its header when it cannot open the file.
        std::FILE* probe = std::fopen(temp.c_str(), "wb");
        if (!probe) throw FileError(path + ": cannot write: " + std::strerror(errno));
        std::fclose(probe);
        const char* err = nullptr;
        if (SaveEXR(rgb.data(), width, height, 3, /*save_as_fp16=*/0, temp.c_str(), &err) < 0) {
            const std::string reason = err ? err : "unknown tinyexr error";
            if (err) FreeEXRErrorMessage(err);
            throw FileError(path + ": cannot write the EXR image: " + reason);
        }
    });
}

}  // namespace thicket
