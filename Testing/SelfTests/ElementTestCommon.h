// Shared helpers of the element-test self-tests: run a driver in-process with a command line, read
// its RUN.macro.csv, and report checks.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "IO/Csv.h"

namespace etest {

inline int failures = 0;

inline void check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    if (!ok) ++failures;
}

template <class Driver>
int runDriver(std::vector<std::string> args) {
    Driver d;
    args.insert(args.begin(), "selftest");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    return d.run(static_cast<int>(args.size()), argv.data());
}

struct Series {
    std::vector<double> x, y;
};

/// Rows of column `y` against column `x` where `keep(row)` holds.
template <class Keep>
Series select(const pdpm::CsvTable& t, const std::string& x, const std::string& y, Keep keep) {
    Series s;
    const int ix = t.column(x), iy = t.column(y);
    for (const auto& r : t.rows)
        if (keep(r)) {
            s.x.push_back(r[ix]);
            s.y.push_back(r[iy]);
        }
    return s;
}

/// Spearman rank correlation (no ties expected).
inline double rankCorrelation(const Series& s) {
    const std::size_t n = s.x.size();
    if (n < 3) return 0;
    auto ranks = [&](const std::vector<double>& v) {
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i) {
            double k = 0;
            for (std::size_t j = 0; j < n; ++j) k += (v[j] < v[i]) + 0.5 * (j != i && v[j] == v[i]);
            r[i] = k;
        }
        return r;
    };
    const auto rx = ranks(s.x), ry = ranks(s.y);
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i) { mx += rx[i]; my += ry[i]; }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxy = 0, sxx = 0, syy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sxy += (rx[i] - mx) * (ry[i] - my);
        sxx += (rx[i] - mx) * (rx[i] - mx);
        syy += (ry[i] - my) * (ry[i] - my);
    }
    return sxy / std::sqrt(sxx * syy);
}

inline double meanOver(const Series& s, double lo, double hi) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i)
        if (s.x[i] >= lo && s.x[i] <= hi) { sum += s.y[i]; ++n; }
    return n ? sum / n : std::nan("");
}

} // namespace etest
