#pragma once
// Reading a PNG back in tests (stb_image), to check what the renderer wrote.
#include <string>
#include <vector>

namespace thicket::testing {

/// The pixels of the PNG at `path` as RGB bytes, row by row, with its size; empty (and the
/// reason in `error`) if it cannot be read.
std::vector<unsigned char> read_png_rgb(const std::string& path, int& width, int& height, std::string& error);

}  // namespace thicket::testing
