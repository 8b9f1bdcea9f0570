// The heap policy of simulation programs (Kernel/Core/MemoryPolicy.h): with glibc, a block of 64 kB
// or more is mapped on its own (so it goes back to the system when freed) rather than carved from
// the heap, where glibc's default would keep it once freed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
#include <malloc.h>
#define PDPM_TEST_MALLINFO2 1
#endif

#include "Core/MemoryPolicy.h"

using namespace pdpm;

TEST(MemoryPolicy, MidSizedBlocksAreMappedOnTheirOwn) {
#ifdef PDPM_TEST_MALLINFO2
    if (!applyMemoryPolicy()) GTEST_SKIP() << "policy not applied here (sanitizer allocator or GLIBC_TUNABLES)";
    const std::size_t mappedBefore = mallinfo2().hblkhd;
    std::vector<double>* v = new std::vector<double>(12000, 1.0);  // 96 kB: below glibc's default 128 kB
    const std::size_t mappedDuring = mallinfo2().hblkhd;
    EXPECT_GE(mappedDuring, mappedBefore + 12000 * sizeof(double));
    delete v;
    EXPECT_EQ(mallinfo2().hblkhd, mappedBefore);  // unmapped again: back to the system
#else
    GTEST_SKIP() << "needs glibc >= 2.33 (mallinfo2)";
#endif
}
