// The one checked array reader of saved payloads (util/binary_io.h): a count above its bound or
// beyond the bytes left is refused by name before anything is allocated for it.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/util/binary_io.h"

namespace thicket::binary_io_test {
namespace {

std::string payload_of(uint64_t count, const std::vector<uint32_t>& values) {
    std::ostringstream out;
    write_value(out, count);
    write_array(out, values.data(), values.size());
    return out.str();
}

/// What reading one counted uint32 array from `bytes` (at most `most` entries) says.
std::string error_of(const std::string& bytes, uint64_t most) {
    std::istringstream in(bytes);
    PayloadReader reader(in, "test");
    std::vector<uint32_t> v;
    try {
        reader.counted_array<uint64_t>(v, most, "widgets");
        reader.end();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(PayloadReader, ReadsWhatWasWritten) {
    const std::vector<uint32_t> values{7, 8, 9};
    std::ostringstream out;
    write_counted_array<uint64_t>(out, values);
    EXPECT_EQ(out.str(), payload_of(3, values));
    std::istringstream in(out.str());
    PayloadReader reader(in, "test");
    std::vector<uint32_t> back;
    reader.counted_array<uint64_t>(back, 3, "widgets");
    reader.end();
    EXPECT_EQ(back, values);
}

TEST(PayloadReader, RefusesCountsAboveTheBoundOrBeyondTheBytesLeft) {
    EXPECT_EQ(error_of(payload_of(4, {1, 2, 3, 4}), 3), "test payload claims 4 widgets, at most 3 for this scene");
    // A count of 2^60 is refused from the bytes left, not by failing to allocate 4 EiB.
    EXPECT_EQ(error_of(payload_of(uint64_t(1) << 60, {1}), PayloadReader::kAnyCount),
              "test payload truncated in widgets: 1152921504606846976 entries of 4 bytes, 4 bytes left");
    EXPECT_EQ(error_of(payload_of(2, {1}), 2), "test payload truncated in widgets: 2 entries of 4 bytes, 4 bytes left");
    EXPECT_EQ(error_of(payload_of(1, {1, 2}), 2), "test payload has trailing bytes");
    EXPECT_EQ(error_of(std::string(5, '\0'), 2), "test payload truncated in widgets");
}

}  // namespace
}  // namespace thicket::binary_io_test
