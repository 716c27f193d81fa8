// The path tracer's image files: linear float OpenEXR read back bit for bit, and errors that name
// the file.
#include <gtest/gtest.h>
#include <tinyexr.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "thicket/core/error.h"
#include "thicket/render/film.h"

namespace thicket::film_test {
namespace {

TEST(Film, ExrHoldsTheScaledRadianceBitForBit) {
    const testing::TempDir dir("thicket_film");
    const int w = 3, h = 2;
    // Row 0 is the top row; values beyond [0, 1] stay, as linear radiance must.
    const std::vector<Vec3> radiance = {{0, 0, 0},    {1, 2, 3},        {0.1f, 0.2f, 0.3f},
                                        {1e3f, 5, 7}, {1e-6f, 0.5f, 8}, {0.25f, 0.75f, 0.125f}};
    const std::string path = dir.dir() + "/r.exr";
    write_exr(radiance, w, h, path, 2.0f);
    float* rgba = nullptr;
    int rw = 0, rh = 0;
    const char* err = nullptr;
    ASSERT_EQ(LoadEXR(&rgba, &rw, &rh, path.c_str(), &err), TINYEXR_SUCCESS) << (err ? err : "");
    ASSERT_EQ(rw, w);
    ASSERT_EQ(rh, h);
    for (int i = 0; i < w * h; ++i) {
        EXPECT_EQ(rgba[4 * i + 0], radiance[size_t(i)].x * 2.0f) << "pixel " << i;
        EXPECT_EQ(rgba[4 * i + 1], radiance[size_t(i)].y * 2.0f) << "pixel " << i;
        EXPECT_EQ(rgba[4 * i + 2], radiance[size_t(i)].z * 2.0f) << "pixel " << i;
    }
    std::free(rgba);
}

TEST(Film, ExrErrorsNameTheFile) {
    const testing::TempDir dir("thicket_film");
    const std::vector<Vec3> radiance(6, Vec3{1.0f});
    const std::string missing_dir = dir.dir() + "/no-such-dir/r.exr";
    try {
        write_exr(radiance, 3, 2, missing_dir);
        ADD_FAILURE() << "wrote into a missing directory";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find(missing_dir), std::string::npos) << e.what();
    }
    try {
        write_exr(radiance, 4, 2, dir.dir() + "/r.exr");
        ADD_FAILURE() << "accepted 6 pixels for a 4x2 image";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("6 pixels for a 4x2 image"), std::string::npos) << e.what();
    }
}

// Issue 31: the format follows the extension (any case), and anything else is refused naming it,
// where x.jpg used to receive PNG bytes.
TEST(Film, FormatByExtension) {
    EXPECT_EQ(image_format_of("a/b.png"), ImageFormat::Png);
    EXPECT_EQ(image_format_of("B.PNG"), ImageFormat::Png);
    EXPECT_EQ(image_format_of("x.exr"), ImageFormat::Exr);
    EXPECT_EQ(image_format_of("dir.png/x.Exr"), ImageFormat::Exr);
    for (const char* bad : {"x.jpg", "x.png.bak", "noext", "dir.exr/", ".png"}) {
        try {
            image_format_of(bad);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(bad), std::string::npos) << what;
            EXPECT_NE(what.find(".png"), std::string::npos) << what;
            EXPECT_NE(what.find(".exr"), std::string::npos) << what;
        }
    }
}

// An exposure that carries a finite radiance past float's range is refused naming the pixel
// (it wrote +inf into the file); radiance already infinite is the renderer's, written as is.
TEST(Film, ExrRefusesAnExposureThatOverflows) {
    const testing::TempDir dir("thicket_film");
    std::vector<Vec3> radiance(6, Vec3{0.5f});
    radiance[4] = Vec3{1e30f, 0.0f, 2.0f};
    const std::string path = dir.dir() + "/big.exr";
    try {
        write_exr(radiance, 3, 2, path, 1e10f);
        ADD_FAILURE() << "wrote an infinite pixel";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("pixel 4"), std::string::npos) << what;
        EXPECT_NE(what.find("exposure 1e+10"), std::string::npos) << what;
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    write_exr(radiance, 3, 2, path, 1e8f);  // 1e38 still fits
    EXPECT_TRUE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace thicket::film_test
