#include "Core/Error.h"
#include "Core/RunMain.h"

#include <gtest/gtest.h>

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
