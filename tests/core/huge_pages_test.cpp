// HugePageAllocator: large blocks start on a 2 MiB boundary (where the kernel can back them
// with huge pages), small ones are ordinary; the vectors behave as any std::vector.
#include "harness/core/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>

using namespace pxh;

TEST(HugePages, LargeBlocksAreAlignedToTwoMebibytesAndKeepTheirContents) {
    for (size_t n : {size_t(64) << 10, size_t(1) << 20, (size_t(3) << 20) + 7}) {  // floats
        HugePageVector<float> v(n);
        EXPECT_EQ(reinterpret_cast<uintptr_t>(v.data()) % (size_t(2) << 20), 0u) << n;
        std::iota(v.begin(), v.end(), 0.0f);
        HugePageVector<float> copy = v;  // a copy allocates its own block
        EXPECT_NE(copy.data(), v.data());
        EXPECT_EQ(reinterpret_cast<uintptr_t>(copy.data()) % (size_t(2) << 20), 0u) << n;
        EXPECT_EQ(copy.front(), 0.0f);
        EXPECT_EQ(copy[n / 2], float(n / 2));
        EXPECT_EQ(copy.back(), float(n - 1));
    }
}

TEST(HugePages, SmallBlocksAndGrowthWork) {
    HugePageVector<int> v;
    for (int k = 0; k < 200000; ++k) v.push_back(k);  // reallocates across the 256 KiB threshold
    ASSERT_EQ(v.size(), 200000u);
    long long sum = 0;
    for (int x : v) sum += x;
    EXPECT_EQ(sum, 199999LL * 200000LL / 2);
    HugePageVector<double> empty;
    empty.reserve(0);
    EXPECT_TRUE(empty.empty());
}
