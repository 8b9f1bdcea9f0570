// One-line progress report of a running simulation on stderr:
//   "  42.0%  t = 0.0042 of 0.01 s   12345 steps/s   ETA 0:00:05"
// On a terminal the line is refreshed in place ('\r') at most once per second; when the stream is
// not a terminal (log file, CI) a new line is printed at most every 10 s. update() is cheap enough
// to call every time step: it reads the clock only every 64 calls.
#pragma once
#include <chrono>
#include <functional>
#include <iostream>
#include <string>

namespace pdpm {

class ProgressReporter {
public:
    using Clock = std::chrono::steady_clock;

    /// `quiet` silences all output. Whether `os` is a terminal is detected for std::cerr/std::cout
    /// only (other streams count as not a terminal); override with setInteractive().
    explicit ProgressReporter(bool quiet, std::ostream& os = std::cerr);

    void start(double tStart, double tEnd);
    void update(double t, long step);
    void finish(long step);

    /// Force terminal ('\r') or log (new line) mode.
    void setInteractive(bool interactive) { interactive_ = interactive; }
    bool interactive() const { return interactive_; }
    /// Minimum wall time between two printed updates (default 1 s on a terminal, 10 s otherwise).
    void setInterval(double seconds) { interval_ = seconds; intervalSet_ = true; }
    /// Check the clock every `n` calls of update() (default 64; 1 in tests).
    void setCheckEvery(int n) { checkEvery_ = n < 1 ? 1 : n; }

    /// Optional source of the completed fraction (read only when a line is printed). A driver
    /// whose end is not a fixed time (a protocol of ramps and holds) reports its own progress;
    /// a negative value falls back to the time fraction.
    void setFractionSource(std::function<double()> source) { fractionSource_ = std::move(source); }
    /// Text printed in front of every line (e.g. the run name); empty by default.
    void setLabel(std::string label) { label_ = std::move(label); }

    /// Number of lines/refreshes printed so far (for tests).
    long printed() const { return printed_; }

    /// The text of a progress line (no '\r'/'\n'), exposed for tests.
    static std::string formatLine(double fraction, double t, double tEnd, double stepsPerSecond,
                                  double etaSeconds);
    /// "H:MM:SS", or "--:--:--" when unknown.
    static std::string formatDuration(double seconds);

private:
    void print(double t, long step, Clock::time_point now);
    double intervalSeconds() const;

    bool quiet_;
    std::ostream& os_;
    bool interactive_ = false;
    bool intervalSet_ = false;
    double interval_ = 1.0;
    int checkEvery_ = 64;
    int calls_ = 0;
    double tStart_ = 0, tEnd_ = 0;
    double lastT_ = 0;
    long startStep_ = -1;
    long lastStep_ = 0;
    Clock::time_point startTime_{};
    Clock::time_point lastPrint_{};
    long printed_ = 0;
    std::size_t lastLength_ = 0;
    std::function<double()> fractionSource_;
    std::string label_;
    bool started_ = false;
};

} // namespace pdpm
