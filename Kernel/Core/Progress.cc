#include "Core/Progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace pdpm {

namespace {

bool streamIsTerminal(const std::ostream& os) {
    if (&os == &std::cerr || &os == &std::clog) return ::isatty(STDERR_FILENO) == 1;
    if (&os == &std::cout) return ::isatty(STDOUT_FILENO) == 1;
    return false;
}

double seconds(ProgressReporter::Clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

} // namespace

ProgressReporter::ProgressReporter(bool quiet, std::ostream& os)
    : quiet_(quiet), os_(os), interactive_(streamIsTerminal(os)) {}

double ProgressReporter::intervalSeconds() const {
    if (intervalSet_) return interval_;
    return interactive_ ? 1.0 : 10.0;
}

void ProgressReporter::start(double tStart, double tEnd) {
    tStart_ = tStart;
    tEnd_ = tEnd;
    lastT_ = tStart;
    startStep_ = -1;
    lastStep_ = 0;
    calls_ = 0;
    printed_ = 0;
    lastLength_ = 0;
    startTime_ = lastPrint_ = Clock::now();
    started_ = true;
}

void ProgressReporter::update(double t, long step) {
    if (quiet_) return;
    if (!started_) start(t, t);
    if (startStep_ < 0) startStep_ = step;
    lastT_ = t;
    lastStep_ = step;
    if (++calls_ < checkEvery_) return;
    calls_ = 0;
    const auto now = Clock::now();
    if (seconds(now - lastPrint_) >= intervalSeconds()) print(t, step, now);
}

std::string ProgressReporter::formatDuration(double s) {
    if (!std::isfinite(s) || s < 0 || s > 1e8) return "--:--:--";
    const long total = static_cast<long>(std::llround(s));
    char buf[48];
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", total / 3600, (total / 60) % 60, total % 60);
    return buf;
}

std::string ProgressReporter::formatLine(double fraction, double t, double tEnd,
                                         double stepsPerSecond, double etaSeconds) {
    char buf[160];
    const double pct = 100.0 * std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
    const double rate = std::isfinite(stepsPerSecond) ? stepsPerSecond : 0.0;
    const std::string eta = formatDuration(etaSeconds);
    if (tEnd > 0)
        std::snprintf(buf, sizeof buf, "%5.1f%%  t = %.6g of %.6g s  %.4g steps/s  ETA %s", pct, t, tEnd, rate, eta.c_str());
    else  // no fixed end time (fraction from the driver)
        std::snprintf(buf, sizeof buf, "%5.1f%%  t = %.6g s  %.4g steps/s  ETA %s", pct, t, rate, eta.c_str());
    return buf;
}

void ProgressReporter::print(double t, long step, Clock::time_point now) {
    const double span = tEnd_ - tStart_;
    double fraction = span > 0 ? std::clamp((t - tStart_) / span, 0.0, 1.0) : 1.0;
    const double external = fractionSource_ ? fractionSource_() : -1.0;
    if (external >= 0) fraction = std::min(external, 1.0);
    const double elapsed = seconds(now - startTime_);
    const double rate = elapsed > 0 ? static_cast<double>(step - startStep_) / elapsed : 0.0;
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : -1.0;
    const std::string line = label_ + formatLine(fraction, t, external >= 0 ? 0.0 : tEnd_, rate, eta);
    if (interactive_) {
        os_ << '\r' << line;
        if (line.size() < lastLength_) os_ << std::string(lastLength_ - line.size(), ' ');
        lastLength_ = line.size();
    } else {
        os_ << line << '\n';
    }
    os_.flush();
    lastPrint_ = now;
    ++printed_;
}

void ProgressReporter::finish(long step) {
    if (quiet_ || !started_) return;
    const auto now = Clock::now();
    const double span = tEnd_ - tStart_;
    double fraction = span > 0 ? std::clamp((lastT_ - tStart_) / span, 0.0, 1.0) : 1.0;
    const double external = fractionSource_ ? fractionSource_() : -1.0;
    if (external >= 0) fraction = std::min(external, 1.0);
    const double elapsed = seconds(now - startTime_);
    const long first = startStep_ < 0 ? step : startStep_;
    const double rate = elapsed > 0 ? static_cast<double>(step - first) / elapsed : 0.0;
    char buf[200];
    if (external >= 0)
        std::snprintf(buf, sizeof buf, "%5.1f%%  t = %.6g s  %ld steps in %s (%.4g steps/s)", 100.0 * fraction, lastT_,
                      step - first, formatDuration(elapsed).c_str(), rate);
    else
        std::snprintf(buf, sizeof buf, "%5.1f%%  t = %.6g of %.6g s  %ld steps in %s (%.4g steps/s)", 100.0 * fraction,
                      lastT_, tEnd_, step - first, formatDuration(elapsed).c_str(), rate);
    const std::string line = label_ + buf;
    if (interactive_) {
        os_ << '\r' << line;
        if (line.size() < lastLength_) os_ << std::string(lastLength_ - line.size(), ' ');
    } else {
        os_ << line;
    }
    os_ << '\n';
    os_.flush();
    ++printed_;
    started_ = false;
}

} // namespace pdpm
