// The heap policy of simulation programs (Kernel/Core/MemoryPolicy.h): with glibc, a block of 64 kB
// or more is mapped on its own (so it goes back to the system when freed) rather than carved from
// a grown heap, where glibc's default would keep it once freed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
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
    constexpr std::size_t kBytes = 96000;  // below glibc's default threshold of 128 kB
    const struct mallinfo2 before = mallinfo2();
    if (before.fordblks >= kBytes) {
        // Free heap space could hold the block (earlier tests in this process), and glibc takes a block
        // from there, policy or not: check in a fresh process (as ctest runs every test) instead.
        if (std::getenv("PDPM_MEMORY_POLICY_CHILD")) GTEST_SKIP() << "even a fresh process has free heap";
        const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();  // not the shell's
        EXPECT_EQ(std::system(("PDPM_MEMORY_POLICY_CHILD=1 '" + self +
                               "' --gtest_filter=MemoryPolicy.MidSizedBlocksAreMappedOnTheirOwn > /dev/null 2>&1")
                                  .c_str()),
                  0);
        return;
    }
    std::vector<double>* v = new std::vector<double>(kBytes / sizeof(double), 1.0);
    EXPECT_GE(mallinfo2().hblkhd, before.hblkhd + kBytes);  // without the policy: 0 more (a grown heap)
    delete v;
    EXPECT_EQ(mallinfo2().hblkhd, before.hblkhd);  // unmapped again: back to the system
#else
    GTEST_SKIP() << "needs glibc >= 2.33 (mallinfo2)";
#endif
}
