// .npy reading and writing: round trips, NumPy's exact header layout, and every malformed input
// failing with an Error that names the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/util/npy.h"

namespace npy_test {

namespace fs = std::filesystem;
using namespace thicket;

// Outside the anonymous namespace: the TEST_F classes derive from it (-Wsubobject-linkage in unity builds).
class NpyTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("thicket_npy_test_" + std::to_string(getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    static std::string read_all(const std::string& p) {
        std::ifstream in(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    static void write_raw(const std::string& p, const std::string& bytes) {
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    // A .npy file with the given header dictionary text and data, in format `major`.0.
    static std::string npy_bytes(const std::string& dict, const std::string& data, int major = 1) {
        std::string header = dict;
        const size_t prefix = major == 1 ? 10 : 12;
        while ((prefix + header.size() + 1) % 64) header += ' ';
        header += '\n';
        std::string out("\x93NUMPY", 6);
        out += char(major);
        out += char(0);
        const size_t len = header.size();
        for (size_t i = 0; i < (major == 1 ? 2u : 4u); ++i) out += char((len >> (8 * i)) & 0xFF);
        return out + header + data;
    }
    static std::string float_bytes(const std::vector<float>& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
    }

    // Expects `f` to throw an Error whose message contains the path and `needle`.
    template <class F>
    static void expect_error(F&& f, const std::string& p, const std::string& needle) {
        try {
            f();
            ADD_FAILURE() << "no error for " << p << " (expected one mentioning '" << needle << "')";
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(p), std::string::npos) << "message does not name the file: " << msg;
            EXPECT_NE(msg.find(needle), std::string::npos) << "message lacks '" << needle << "': " << msg;
        }
    }

    fs::path dir_;
};

namespace {

std::vector<float> ramp(size_t n) {
    std::vector<float> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = float(i) * 0.5f - 3.25f;
    return v;
}

}  // namespace

TEST_F(NpyTest, Float32RoundTripWithNumpyHeaderLayout) {
    const std::vector<float> values = ramp(3 * 8);
    const std::string p = path("rays.npy");
    write_npy_f32(p, {3, 8}, values);
    const std::string bytes = read_all(p);
    // Byte for byte what numpy.save writes for a float32 (3, 8) array.
    const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }";
    EXPECT_EQ(bytes, npy_bytes(dict, float_bytes(values)));
    EXPECT_EQ(bytes.substr(8, 2), std::string("v\0", 2));  // header length 118: data at byte 128

    const NpyFloatArray a = read_npy_matrix(p, 8);
    EXPECT_EQ(a.shape, (std::vector<size_t>{3, 8}));
    EXPECT_EQ(a.values, values);
    const NpyHeader h = read_npy_header(p);
    EXPECT_EQ(h.data_offset % 64, 0u);
    EXPECT_EQ(h.descr, "<f4");
    EXPECT_FALSE(h.fortran_order);
}

// An NpyFile reads its header once and its data from the same open file: a file replaced
// between the header and the data (as `numpy.save` or our writers do, by rename) cannot give a
// header of one array and the data of another.
TEST_F(NpyTest, OneOpenFileGivesHeaderAndDataOfTheSameArray) {
    const std::string p = path("a.npy");
    write_npy_f32(p, {3, 8}, ramp(24));
    NpyFile file(p);
    EXPECT_FALSE(file.holds_float64());
    write_npy_f32(p, {1, 8}, std::vector<float>(8, 7.0f));  // replaced on disk
    const NpyFloatArray a = file.read_matrix(8);
    EXPECT_EQ(a.shape, (std::vector<size_t>{3, 8}));
    EXPECT_EQ(a.values, ramp(24));
    EXPECT_EQ(read_npy_matrix(p, 8).shape, (std::vector<size_t>{1, 8}));  // a new open sees the new one
}

TEST_F(NpyTest, OtherShapesAndEmptyArrays) {
    const std::string p = path("a.npy");
    write_npy_f32(p, {5}, ramp(5));
    EXPECT_NE(read_all(p).find("'shape': (5,), }"), std::string::npos);
    EXPECT_EQ(read_npy_float(p).values, ramp(5));

    write_npy_f32(p, {0, 8}, {});
    const NpyFloatArray empty = read_npy_matrix(p, 8);
    EXPECT_EQ(empty.shape, (std::vector<size_t>{0, 8}));
    EXPECT_TRUE(empty.values.empty());

    write_npy_f32(p, {2, 3, 4}, ramp(24));
    EXPECT_EQ(read_npy_float(p).shape, (std::vector<size_t>{2, 3, 4}));
    expect_error([&] { write_npy_f32(p, {2, 3}, ramp(5)); }, p, "does not match");
}

TEST_F(NpyTest, Uint8RoundTrip) {
    const std::vector<uint8_t> flags = {1, 0, 0, 1, 1, 0, 1};
    const std::string p = path("occluded.npy");
    write_npy_u8(p, flags);
    EXPECT_EQ(read_all(p).substr(10, 41), "{'descr': '|u1', 'fortran_order': False, ");
    EXPECT_EQ(read_npy_u8(p), flags);
    EXPECT_EQ(read_npy_header(p).data_offset % 64, 0u);
}

TEST_F(NpyTest, HitsRoundTripKeepsMissesAndFieldOrder) {
    std::vector<Hit> hits(3);
    hits[0] = Hit{1.5f, 0.25f, 0.5f, 7u};
    hits[1] = Hit{};  // miss: t = +inf, prim = kNoPrim
    hits[2] = Hit{1e-3f, 0.0f, 1.0f, 123456u};
    const std::string p = path("hits.npy");
    write_npy_hits(p, hits);
    const std::string bytes = read_all(p);
    EXPECT_NE(bytes.find(std::string("'descr': ") + kNpyHitsDescr), std::string::npos);
    const NpyHeader h = read_npy_header(p);
    EXPECT_EQ(h.data_offset % 64, 0u);
    ASSERT_EQ(bytes.size(), h.data_offset + 3 * 16);
    // Record layout t, prim, u, v.
    uint32_t prim = 0;
    std::memcpy(&prim, bytes.data() + h.data_offset + 4, 4);
    EXPECT_EQ(prim, 7u);

    const std::vector<Hit> back = read_npy_hits(p);
    ASSERT_EQ(back.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(back[i].t, hits[i].t);
        EXPECT_EQ(back[i].prim, hits[i].prim);
        EXPECT_EQ(back[i].u, hits[i].u);
        EXPECT_EQ(back[i].v, hits[i].v);
    }
    EXPECT_TRUE(std::isinf(back[1].t));
    EXPECT_EQ(back[1].prim, kNoPrim);
}

TEST_F(NpyTest, ReadsFloat64AndVersions2And3) {
    const std::string p = path("f8.npy");
    const std::vector<double> d = {0.1, -2.5, 1e30, 3.0};
    const std::string data(reinterpret_cast<const char*>(d.data()), d.size() * 8);
    write_raw(p, npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 4), }", data));
    const NpyFloatArray a = read_npy_matrix(p, 4);
    ASSERT_EQ(a.values.size(), 4u);
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ(a.values[i], float(d[i]));

    for (int major : {2, 3}) {
        const std::string q = path(major == 2 ? "v2.npy" : "v3.npy");
        write_raw(q, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }", float_bytes(ramp(4)),
                               major));
        EXPECT_EQ(read_npy_header(q).major, major);
        EXPECT_EQ(read_npy_float(q).values, ramp(4));
    }
    // Key order, quoting and spacing vary between writers; Python 2 wrote long integers as 3L.
    const std::string r = path("odd.npy");
    write_raw(r, npy_bytes("{\"shape\":(2L,2L),\"fortran_order\":False,\"descr\":\"<f4\"}", float_bytes(ramp(4))));
    EXPECT_EQ(read_npy_float(r).values, ramp(4));
}

TEST_F(NpyTest, MalformedFilesNameTheFileAndTheProblem) {
    const std::string ok_data = float_bytes(ramp(16));
    struct Case {
        const char* name;
        std::string bytes;
        const char* needle;
    };
    const std::vector<Case> cases = {
        {"empty", "", "not a .npy file"},
        {"magic", "PK\x03\x04 this is a zip file, not an array", "not a .npy file"},
        {"version", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }", ok_data, 4),
         "version 4.0"},
        {"header_cut", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }", "").substr(0, 40),
         "truncated .npy header"},
        {"syntax", npy_bytes("{'descr' '<f4', 'fortran_order': False, 'shape': (2, 8), }", ok_data), "expected ':'"},
        {"unterminated", npy_bytes("{'descr': '<f4, 'fortran_order': False, 'shape': (2, 8), }", ok_data),
         "malformed"},
        {"no_shape", npy_bytes("{'descr': '<f4', 'fortran_order': False, }", ok_data), "no 'shape' key"},
        {"extra_key", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), 'x': 1, }", ok_data),
         "unexpected key 'x'"},
        {"fortran", npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 8), }", ok_data), "Fortran"},
        {"negative", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (-2, 8), }", ok_data),
         "non-negative"},
        {"int_dtype", npy_bytes("{'descr': '<i4', 'fortran_order': False, 'shape': (2, 8), }", ok_data), "'<i4'"},
        {"big_endian", npy_bytes("{'descr': '>f4', 'fortran_order': False, 'shape': (2, 8), }", ok_data),
         "big-endian"},
        {"truncated", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }", ok_data.substr(0, 60)),
         "truncated"},
        {"trailing", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }", ok_data + "xyz"),
         "unexpected bytes"},
        {"wrong_shape", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 7), }", ok_data.substr(0, 56)),
         "(2, 7) is not (N, 8)"},
        {"one_dim", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (16,), }", ok_data),
         "(16,) is not (N, 8)"},
        {"huge", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387904, 8), }", ok_data),
         "too large"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string p = path(std::string(c.name) + ".npy");
        write_raw(p, c.bytes);
        expect_error([&] { read_npy_matrix(p, 8); }, p, c.needle);
    }
    expect_error([&] { read_npy_matrix(path("missing.npy"), 8); }, path("missing.npy"), "no such file");
}

TEST_F(NpyTest, TypedReadersRejectOtherDtypes) {
    const std::string f = path("floats.npy");
    write_npy_f32(f, {4}, ramp(4));
    expect_error([&] { read_npy_u8(f); }, f, "'<f4'");
    expect_error([&] { read_npy_hits(f); }, f, "not the hits dtype");

    const std::string h = path("hits.npy");
    write_npy_hits(h, std::vector<Hit>(2));
    expect_error([&] { read_npy_float(h); }, h, "structured");

    const std::string u = path("u8_2d.npy");
    write_raw(u, npy_bytes("{'descr': '|u1', 'fortran_order': False, 'shape': (2, 2), }", "abcd"));
    expect_error([&] { read_npy_u8(u); }, u, "not (N,)");
}

TEST_F(NpyTest, FailedWriteNamesThePathAndLeavesNothing) {
    const std::string p = path("no/such/dir/out.npy");
    expect_error([&] { write_npy_u8(p, std::vector<uint8_t>{1, 2}); }, p, "cannot write");
    // Replacing an existing file is all or nothing: the old content stays until the rename.
    const std::string q = path("out.npy");
    write_npy_u8(q, std::vector<uint8_t>{1, 2, 3});
    write_npy_u8(q, std::vector<uint8_t>{4});
    EXPECT_EQ(read_npy_u8(q), std::vector<uint8_t>{4});
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u) << "temporary files left behind";
}

}  // namespace npy_test
