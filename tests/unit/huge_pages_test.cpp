// The pool of 2 MiB-page mappings that the Python module's output arrays live in
// (core/huge_pages.h): aligned, whole pages, and a released mapping taken again by the next
// request of the same length rather than mapped afresh.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "thicket/core/huge_pages.h"

namespace huge_pages_test {

using namespace thicket;

TEST(HugeMappings, AreAlignedWholePagesAndReusedBySize) {
    constexpr size_t kPage = size_t(2) << 20;
    const HugeMapping a = take_huge_mapping(3 * (size_t(1) << 20));  // 3 MiB: two pages
#if defined(__linux__)
    ASSERT_NE(a.start, nullptr);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(a.start) % kPage, 0u);
    EXPECT_EQ(a.length, 2 * kPage);
    std::memset(a.start, 0x5a, a.length);  // every byte is ours
    release_huge_mapping(a);
    const HugeMapping b = take_huge_mapping(4 * (size_t(1) << 20));  // same length: the kept one
    EXPECT_EQ(b.start, a.start);
    EXPECT_EQ(static_cast<unsigned char*>(b.start)[a.length - 1], 0x5a);  // not mapped afresh (zeroed)
    const HugeMapping c = take_huge_mapping(5 * (size_t(1) << 20));  // another length: a new mapping
    EXPECT_NE(c.start, b.start);
    EXPECT_EQ(c.length, 3 * kPage);
    release_huge_mapping(b);
    release_huge_mapping(c);
    // A request whose length overflows size_t is refused rather than wrapped.
    EXPECT_EQ(take_huge_mapping(SIZE_MAX - 5).start, nullptr);
#else
    EXPECT_EQ(a.start, nullptr);
#endif
}

}  // namespace huge_pages_test
