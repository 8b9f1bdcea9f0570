#include "Core/Error.h"
#include "Core/RunMain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <new>
#include <stdexcept>

using namespace pdpm;

TEST(RunMain, ReturnsBodyResult) {
    EXPECT_EQ(runMain("prog", [] { return 0; }), 0);
    EXPECT_EQ(runMain("prog", [] { return 7; }), 7);
}

TEST(RunMain, InputErrorIsOneLineAndExitCode2) {
    ::testing::internal::CaptureStderr();
    const int rc = runMain("Demo", []() -> int { throw InputError("--radius_min: value -1 out of range (0, inf)"); });
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(rc, 2);
    EXPECT_EQ(err, "Demo: error: --radius_min: value -1 out of range (0, inf)\n");
}

TEST(RunMain, OtherExceptionsExitCode1) {
    ::testing::internal::CaptureStderr();
    const int rc = runMain("Demo", []() -> int { throw std::runtime_error("disk on fire\nsecond line"); });
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(rc, 1);
    EXPECT_EQ(err, "Demo: error: disk on fire; second line\n");
}

TEST(RunMain, OutOfMemoryIsOneLineAndExitCode2) {
    // sizes come from the input (particle counts, grids, file headers): a request too large for the
    // machine is bad input, not a crash
    ::testing::internal::CaptureStderr();
    const int rc = runMain("Demo", []() -> int { throw std::bad_alloc(); });
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(rc, 2);
    EXPECT_EQ(err.rfind("Demo: error: out of memory", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}
