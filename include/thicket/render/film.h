#pragma once
/// From linear radiance to an image file: sRGB tone mapping to 8 bits for PNG, or linear float
/// OpenEXR.
#include <string>
#include <vector>

#include "thicket/core/vec3.h"
#include "thicket/render/image.h"

namespace thicket {

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1] (clamped; NaN gives 0).
float srgb_encode(float linear);

/// Linear radiance (row 0 at the top, width x height values) scaled by `exposure`, clamped to
/// [0, 1] and sRGB-encoded to 8 bits. Throws Error if the sizes disagree.
Image tonemap_srgb(const std::vector<Vec3>& radiance, int width, int height, float exposure = 1.0f);

/// The image files thicket writes, chosen by the output's extension.
enum class ImageFormat { Png, Exr };
/// The format `path`'s extension names, case-insensitively: .png or .exr. Throws Error
/// "<path>: ..." naming the extension (or its absence) and the supported ones otherwise, so that
/// x.jpg is refused rather than given PNG bytes under a JPEG name.
ImageFormat image_format_of(const std::string& path);

/// Writes linear radiance (row 0 at the top) scaled by `exposure` to `path` as OpenEXR: 32-bit
/// float R, G, B channels, ZIP-compressed, no tone mapping (tinyexr). Atomic like every output:
/// the file appears whole or not at all. Throws Error naming `path` if the sizes disagree, if
/// `exposure` carries a finite radiance past float's range (the pixel and the exposure named),
/// or the file cannot be written.
void write_exr(const std::vector<Vec3>& radiance, int width, int height, const std::string& path,
               float exposure = 1.0f);

}  // namespace thicket
