// Shared pieces of the benchmark drivers: timing of the time loop and the two summary lines
//   CASE end ke_J=K contacts=M volume_fraction=V
//   CASE threads=T particle_steps_per_s=X bytes_per_particle=Y
#pragma once
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "Core/DPMBase.h"

namespace pdpm::bench {

/// Peak resident memory of this process (bytes), from /proc/self/status (VmHWM).
inline long peakRssBytes() {
    std::ifstream f("/proc/self/status");
    std::string key;
    while (f >> key) {
        if (key == "VmHWM:") {
            long kb = 0;
            f >> kb;
            return kb * 1024;
        }
    }
    return 0;
}

/// Default start file: ../shared/bench/NAME beside the source tree, or "" if absent.
inline std::string defaultStartFile(const std::string& name) {
    const std::filesystem::path p = std::filesystem::path(PDPM_SOURCE_DIR) / ".." / "shared" / "bench" / name;
    return std::filesystem::exists(p) ? p.lexically_normal().string() : std::string();
}

class LoopTimer {
public:
    void start() { t0_ = std::chrono::steady_clock::now(); }
    void stop() { seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
    double seconds() const { return seconds_; }

private:
    std::chrono::steady_clock::time_point t0_;
    double seconds_ = 0;
};

inline void printSummary(const std::string& tag, DPMBase& d, long steps, double seconds, double solidVolume,
                         double domainVolume) {
    const long contacts = static_cast<long>(d.countContacts());
    const double n = static_cast<double>(d.particles().size());
    std::printf("%s end ke_J=%.6e contacts=%ld volume_fraction=%.4f\n", tag.c_str(), d.kineticEnergy(), contacts,
                solidVolume / domainVolume);
    std::printf("%s threads=%d particle_steps_per_s=%.4e bytes_per_particle=%.0f\n", tag.c_str(), omp_get_max_threads(),
                n * static_cast<double>(steps) / seconds, static_cast<double>(peakRssBytes()) / n);
    std::fprintf(stderr, "%s: %zu neighbour pairs, %ld list builds, kernel data %.0f bytes/particle\n", tag.c_str(),
                 d.neighbourPairs(), d.neighbourBuilds(), static_cast<double>(d.memoryBytes()) / n);
    std::fflush(stdout);
}

} // namespace pdpm::bench
