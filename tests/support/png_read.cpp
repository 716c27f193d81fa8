#include "support/png_read.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace thicket::testing {

std::vector<unsigned char> read_png_rgb(const std::string& path, int& width, int& height, std::string& error) {
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
    if (!data) {
        error = stbi_failure_reason();
        width = height = 0;
        return {};
    }
    std::vector<unsigned char> rgb(data, data + size_t(width) * size_t(height) * 3);
    stbi_image_free(data);
    return rgb;
}

}  // namespace thicket::testing
