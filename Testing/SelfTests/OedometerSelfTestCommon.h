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

inline bool check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    return ok;
}

} // namespace oedometer_selftest
