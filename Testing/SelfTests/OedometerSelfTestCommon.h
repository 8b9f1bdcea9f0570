// Shared helpers of the Oedometer* self-tests: run the OedometerRelaxation driver in-process.
#pragma once
#include <cstdio>
#include <string>
#include <vector>

#include "../../Drivers/OedometerRelaxation/OedometerRelaxation.h"

namespace oedometer_selftest {

inline int runDriver(pdpm::OedometerRelaxation& d, std::vector<std::string> args) {
    args.insert(args.begin(), "OedometerRelaxation");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return d.run(static_cast<int>(argv.size()), argv.data());
}

/// One sample of a driver run's recording: protocol step, axial strain, axial stress (Pa).
struct Sample {
    int step;
    double strain, stress;
};
inline std::vector<Sample> samples(const pdpm::OedometerRelaxation& d) {
    const auto& rec = d.recordingData();
    const int cs = rec.column("step"), ce = rec.column("axial_strain"), cp = rec.column("axial_stress_Pa");
    std::vector<Sample> out;
    for (const auto& row : rec.rows)
        out.push_back({static_cast<int>(row[static_cast<std::size_t>(cs)]), row[static_cast<std::size_t>(ce)], row[static_cast<std::size_t>(cp)]});
    return out;
}

inline bool check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    return ok;
}

} // namespace oedometer_selftest
