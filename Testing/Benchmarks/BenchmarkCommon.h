// Shared pieces of the benchmark drivers (decks of ../shared/bench/README.md): the deck's contact
// law, the start file, timing of the time loop only, and the two summary lines
//   CASE end ke_J=K contacts=M volume_fraction=V
//   CASE threads=T particle_steps_per_s=X bytes_per_particle=Y
#pragma once
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
// mallinfo2 (the heap figures of PDPM_MEMTRACE) exists from glibc 2.33 on; <cstdio> defines __GLIBC__
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
#include <malloc.h>
#define PDPM_HAVE_MALLINFO2 1
#endif

#include "Core/DPMBase.h"
#include "Core/Error.h"
#include "IO/NumberFormat.h"
#include "IO/XyzrReader.h"

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

/// A benchmark deck: the deck's contact law (both decks), --start and --steps, the deck's time
/// step, no output files; the time loop is timed and the summary printed after it.
class DeckBenchmark : public DPMBase {
public:
    DeckBenchmark(const std::string& program, const std::string& description, const std::string& tag,
                  const std::string& startFile, long steps, double dt)
        : DPMBase(program, description), tag_(tag) {
        parameters().add("start", &start_, defaultStartFile(startFile),
                         "start file (*.xyzr); empty: prepare an equivalent configuration");
        parameters().add("steps", &steps_, steps, "-", "number of time steps", Range::atLeast(1));
        parameters().setDefault("dt", fmt(dt));
        parameters().setDefault("time_max", "1");             // replaced by steps * dt
        parameters().setDefault("max_initial_overlap", "1");  // the decks are compressed packings
        disableFileOutput();
    }

protected:
    /// Deck contact law: k_n = 1e5 N/m, absolute gamma_n = 0.28 kg/s, k_t = 2/7 k_n, mu = 0.5.
    void addDeckSpecies() {
        ContactParameters p;
        p.k = 1.0e5;
        p.gamma = 0.28;
        p.kt = 2.0 / 7.0 * p.k;
        p.muS = p.muD = 0.5;
        addSpecies("glass", 2000, p);
        setContactLaw("linear");
    }
    void addParticles(const std::vector<Vec3>& x, const std::vector<double>& r) {
        particles().reserve(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) addParticle(x[i], r[i]);
        solid_ = 0;
        for (double ri : r) solid_ += 4.0 / 3.0 * std::numbers::pi * ri * ri * ri;
        setTimeMax(timeStep() * static_cast<double>(steps_));
        setSaveEvery(timeMax());
    }
    /// PDPM_MEMTRACE=1: memory lines (VmHWM, VmRSS, RssAnon, RssFile) on stderr at set-up, before
    /// the loop and whenever the peak grows during it (to see which step sets the peak).
    void actionsAfterTimeStep() override {
        if (!memTrace_) return;
        const long h = peakRssBytes();
        if (h != lastPeak_) {
            memLine("step");
            lastPeak_ = h;
        }
    }
    void memLine(const char* where) const {
        if (!memTrace_) return;
        std::ifstream f("/proc/self/status");
        std::string line, out;
        while (std::getline(f, line))
            for (const char* key : {"VmHWM", "VmRSS", "RssAnon", "RssFile"})
                if (line.rfind(key, 0) == 0) out += " " + line;
        std::fprintf(stderr, "%s memory at %s, step %ld:%s\n", tag_.c_str(), where, step(), out.c_str());
#ifdef PDPM_HAVE_MALLINFO2
        const struct mallinfo2 mi = mallinfo2();
        std::fprintf(stderr, "  heap arena %zu kB, in use %zu kB, free %zu kB, mmapped %zu kB (%zu blocks), top %zu kB, kernel %zu kB\n",
                     mi.arena / 1024, mi.uordblks / 1024, mi.fordblks / 1024, mi.hblkhd / 1024, mi.hblks, mi.keepcost / 1024, memoryBytes() / 1024);
#endif
    }
    /// Volume in which the volume fraction of the summary line is measured.
    virtual double measuredVolume() const = 0;

    void actionsBeforeTimeLoop() override {
        memLine("loop start");
        t0_ = std::chrono::steady_clock::now();
    }
    void actionsAfterSolve() override {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        const long contacts = static_cast<long>(countContacts());
        const double n = static_cast<double>(particles().size());
        std::printf("%s end ke_J=%.6e contacts=%ld volume_fraction=%.4f\n", tag_.c_str(), kineticEnergy(), contacts,
                    solid_ / measuredVolume());
        std::printf("%s threads=%d particle_steps_per_s=%.4e bytes_per_particle=%.0f\n", tag_.c_str(),
                    omp_get_max_threads(), n * static_cast<double>(step()) / seconds,
                    static_cast<double>(peakRssBytes()) / n);
        std::fprintf(stderr, "%s: %zu neighbour pairs, %ld list builds, kernel data %.0f bytes/particle\n",
                     tag_.c_str(), neighbourPairs(), neighbourBuilds(), static_cast<double>(memoryBytes()) / n);
        std::fflush(stdout);
    }

    std::string tag_, start_;
    bool memTrace_ = std::getenv("PDPM_MEMTRACE") != nullptr;
    long lastPeak_ = 0;
    long steps_ = 0;
    double solid_ = 0;
    std::chrono::steady_clock::time_point t0_;
};

} // namespace pdpm::bench
