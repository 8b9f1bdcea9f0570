#include "Core/Progress.h"

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

using namespace pdpm;

TEST(Progress, QuietPrintsNothing) {
    std::ostringstream os;
    ProgressReporter p(true, os);
    p.setInterval(0);
    p.setCheckEvery(1);
    p.start(0, 1);
    for (long i = 0; i < 100; ++i) p.update(i * 0.01, i);
    p.finish(100);
    EXPECT_EQ(os.str(), "");
    EXPECT_EQ(p.printed(), 0);
}

TEST(Progress, NonTerminalStreamPrintsLines) {
    std::ostringstream os;
    ProgressReporter p(false, os);
    EXPECT_FALSE(p.interactive());  // a stringstream is not a terminal
    p.setInterval(0);
    p.setCheckEvery(1);
    p.start(0, 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    p.update(0.5, 10);
    p.update(1.0, 20);
    p.finish(40);
    const std::string s = os.str();
    EXPECT_EQ(s.find('\r'), std::string::npos);
    EXPECT_NE(s.find(" 50.0%"), std::string::npos) << s;
    EXPECT_NE(s.find("steps/s"), std::string::npos) << s;
    EXPECT_NE(s.find("ETA"), std::string::npos) << s;
    EXPECT_NE(s.find("t = 1 of 2 s"), std::string::npos) << s;
    EXPECT_EQ(s.back(), '\n');
    EXPECT_EQ(p.printed(), 3);
}

TEST(Progress, TerminalModeRefreshesInPlace) {
    std::ostringstream os;
    ProgressReporter p(false, os);
    p.setInteractive(true);
    p.setInterval(0);
    p.setCheckEvery(1);
    p.start(0, 1);
    p.update(0.25, 1);
    p.update(0.5, 2);
    p.finish(4);
    const std::string s = os.str();
    EXPECT_EQ(s[0], '\r');
    EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1);  // only the final newline
    EXPECT_EQ(s.back(), '\n');
    EXPECT_EQ(std::count(s.begin(), s.end(), '\r'), 3);
}

TEST(Progress, RateLimited) {
    std::ostringstream os;
    ProgressReporter p(false, os);
    p.setInteractive(true);
    p.setInterval(3600);  // an hour: no machine, however loaded or sanitised, gets there in this loop
    p.start(0, 1);
    for (long i = 0; i < 100000; ++i) p.update(i * 1e-5, i);
    EXPECT_EQ(p.printed(), 0);
    EXPECT_EQ(os.str(), "");
}

TEST(Progress, ChecksClockOnlyEvery64Calls) {
    std::ostringstream os;
    ProgressReporter p(false, os);
    p.setInterval(0);
    p.start(0, 1);
    for (long i = 1; i <= 63; ++i) p.update(i * 1e-3, i);
    EXPECT_EQ(p.printed(), 0);
    p.update(0.064, 64);
    EXPECT_EQ(p.printed(), 1);
}

TEST(Progress, Formatting) {
    EXPECT_EQ(ProgressReporter::formatDuration(0), "0:00:00");
    EXPECT_EQ(ProgressReporter::formatDuration(3725), "1:02:05");
    EXPECT_EQ(ProgressReporter::formatDuration(-1), "--:--:--");
    const std::string line = ProgressReporter::formatLine(0.5, 0.5, 1.0, 1234, 61);
    EXPECT_NE(line.find(" 50.0%"), std::string::npos) << line;
    EXPECT_NE(line.find("1234 steps/s"), std::string::npos) << line;
    EXPECT_NE(line.find("ETA 0:01:01"), std::string::npos) << line;
}
