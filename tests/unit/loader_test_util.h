#pragma once
// Shared by the loader tests (one file per format, as src/scene/*_loader.cpp): a temporary
// directory, the error-message check, and a PLY writer for any layout with the reference mesh
// it is checked against.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::loader_test {

namespace fs = std::filesystem;

/// A directory that exists for one test and is removed afterwards.
class TempDir {
public:
    TempDir() {
        static int counter = 0;
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() / ("thicket_loader_" + std::to_string(::getpid()) + "_" +
                                             std::to_string(counter++) + "_" + (info ? info->name() : "x"));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name, const std::string& bytes) const {
        const fs::path p = path_ / name;
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p.string();
    }
    std::string dir() const { return path_.string(); }

private:
    fs::path path_;
};

/// Expects an Error whose message names the file and contains every given fragment.
inline void expect_error(const std::function<void()>& load, const std::string& path,
                  const std::vector<std::string>& fragments) {
    try {
        load();
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path, 0), 0u) << "message does not start with the path: " << what;
        for (const std::string& f : fragments)
            EXPECT_NE(what.find(f), std::string::npos) << f << " not in: " << what;
    }
}

// ---- a small PLY writer for any layout ---------------------------------------------------------

enum class Fmt { ascii, le, be };

struct PlyProp {
    std::string type, name;
    std::string count_type;  ///< non-empty: a list property
};
struct PlyElem {
    std::string name;
    std::vector<PlyProp> props;
    std::vector<std::vector<std::vector<double>>> rows;  ///< row -> property -> values
};

inline void put(std::string& out, const std::string& type, double v, Fmt fmt) {
    static const std::vector<std::string> names = {"char",   "int8",   "uchar", "uint8",   "short",  "int16",
                                                   "ushort", "uint16", "int",   "int32",   "uint",   "uint32",
                                                   "float",  "float32", "double", "float64"};
    const int kind = int(std::find(names.begin(), names.end(), type) - names.begin()) / 2;
    if (fmt == Fmt::ascii) {
        char buf[64];
        const char* pattern = kind == 6 ? "%.9g " : kind == 7 ? "%.17g " : "%.0f ";
        std::snprintf(buf, sizeof buf, pattern, v);
        out += buf;
        return;
    }
    unsigned char b[8];
    size_t n = 0;
    auto raw = [&](auto x) { n = sizeof x, std::memcpy(b, &x, n); };
    switch (kind) {
        case 0: raw(int8_t(v)); break;
        case 1: raw(uint8_t(v)); break;
        case 2: raw(int16_t(v)); break;
        case 3: raw(uint16_t(v)); break;
        case 4: raw(int32_t(v)); break;
        case 5: raw(uint32_t(v)); break;
        case 6: raw(float(v)); break;
        default: raw(double(v)); break;
    }
    if ((fmt == Fmt::be) == (std::endian::native == std::endian::little)) std::reverse(b, b + n);
    out.append(reinterpret_cast<const char*>(b), n);
}

inline std::string make_ply(Fmt fmt, const std::vector<PlyElem>& elems) {
    std::string out = "ply\nformat ";
    out += fmt == Fmt::ascii ? "ascii" : fmt == Fmt::le ? "binary_little_endian" : "binary_big_endian";
    out += " 1.0\ncomment written by loader_test\n";
    for (const PlyElem& e : elems) {
        out += "element " + e.name + " " + std::to_string(e.rows.size()) + "\n";
        for (const PlyProp& p : e.props)
            out += p.count_type.empty()
                       ? "property " + p.type + " " + p.name + "\n"
                       : "property list " + p.count_type + " " + p.type + " " + p.name + "\n";
    }
    out += "end_header\n";
    for (const PlyElem& e : elems)
        for (const auto& row : e.rows) {
            for (size_t i = 0; i < e.props.size(); ++i) {
                const PlyProp& p = e.props[i];
                if (!p.count_type.empty()) put(out, p.count_type, double(row[i].size()), fmt);
                for (double v : row[i]) put(out, p.type, v, fmt);
            }
            if (fmt == Fmt::ascii) out += "\n";
        }
    return out;
}

// The reference content: 6 vertices; a triangle, a quad and a pentagon.
inline const std::vector<Vec3> ref_positions = {{0.5f, -1.25f, 3.0f},  {1.75f, 0.0f, -2.5f}, {-0.125f, 8.0f, 1.0f},
                                         {3.25f, 3.5f, -0.75f}, {0.1f, 0.2f, 0.3f},   {-7.0f, 6.5f, 0.0625f}};
inline const std::vector<std::vector<double>> ref_faces = {{5, 0, 1}, {0, 1, 2, 3}, {4, 3, 5, 1, 0}};
inline const std::vector<uint32_t> ref_indices = {5, 0, 1, 0, 1, 2, 0, 2, 3, 4, 3, 5, 4, 5, 1, 4, 1, 0};

inline PlyElem simple_vertices(const std::string& type = "float") {
    PlyElem e{"vertex", {{type, "x", ""}, {type, "y", ""}, {type, "z", ""}}, {}};
    for (const Vec3& p : ref_positions) e.rows.push_back({{p.x}, {p.y}, {p.z}});
    return e;
}
inline PlyElem simple_faces(const std::string& count_type = "uchar", const std::string& type = "int",
                     const std::string& name = "vertex_indices") {
    PlyElem e{"face", {{type, name, count_type}}, {}};
    for (const auto& f : ref_faces) e.rows.push_back({f});
    return e;
}
inline std::string simple_ply(Fmt fmt) { return make_ply(fmt, {simple_vertices(), simple_faces()}); }

inline void expect_reference(const TriangleMesh& m) {
    EXPECT_EQ(m.positions, ref_positions);
    EXPECT_EQ(m.indices, ref_indices);
    EXPECT_EQ(m.triangle_count(), 6u);
}

}  // namespace thicket::loader_test
