// Speed of the coarse-graining library: one snapshot of N particles (random dense packing in a
// periodic box, contacts between all pairs closer than 1.05 d) onto an n³ grid, width w = d.
// Usage: pdpm-cg-benchmark [N=100000] [n=50] [threads=2]. Not a test: prints the timings.
#include "Cli.h"
#include "CoarseGraining.h"
#include "Core/Error.h"

#include <omp.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

const char* const kUsage =
    "Usage: pdpm-cg-benchmark [N] [n] [threads]\n"
    "Times the coarse-graining of one snapshot of N random particles (with 3 N contacts) onto an n^3 grid.\n"
    "  N        particles, 2 … 10000000 (default 100000)\n"
    "  n        grid cells per direction, 1 … 215 (n^3 at most the pdpm-cg limit of 1e7 cells; default 50)\n"
    "  threads  OpenMP threads, 1 … 4096 (default 2)\n";

/// The positional argument k (1-based) as an integer in lo..hi, or `def` when it is absent.
int intArgument(int argc, char** argv, int k, const char* what, int def, long lo, long hi) {
    if (argc <= k) return def;
    const std::string s = argv[k];
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
        inputError(std::string(what) + ": '" + s + "' is not an integer (see --help)");
    if (v < lo || v > hi)
        inputError(std::string(what) + ": " + s + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

int run(int argc, char** argv) {
    for (int k = 1; k < argc; ++k)
        if (std::string(argv[k]) == "--help" || std::string(argv[k]) == "-h") {
            std::cout << kUsage;
            return 0;
        }
    if (argc > 4) inputError(std::string("unexpected argument '") + argv[4] + "' (at most N, n and threads; see --help)");
    const int N = intArgument(argc, argv, 1, "N (particles)", 100000, 2, 10000000);
    const int n = intArgument(argc, argv, 2, "n (grid cells per direction)", 50, 1, 215);
    const int threads = intArgument(argc, argv, 3, "threads", 2, 1, 4096);
    omp_set_num_threads(threads);
    const double d = 1, phi = 0.6;
    const double L = std::cbrt(N * 3.14159265358979 / 6 * d * d * d / phi);
    ParticleSnapshot s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {L, L, L};
    s.periodic[0] = s.periodic[1] = s.periodic[2] = true;
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(0, 1);
    for (int k = 0; k < N; ++k) {
        s.x.push_back({L * U(rng), L * U(rng), L * U(rng)});
        s.v.push_back({U(rng), U(rng), U(rng)});
        s.r.push_back(0.5 * d);
        s.m.push_back(1);
    }
    // ~6 contacts per particle (3 per particle in the list): random neighbours at distance d
    ContactSnapshot c;
    for (int k = 0; k < 3 * N; ++k) {
        ContactRecord r;
        r.i = int(U(rng) * N) % N;
        r.j = (r.i + 1 + int(U(rng) * (N - 1))) % N;
        const double ct = 2 * U(rng) - 1, ph = 6.283185307 * U(rng), st = std::sqrt(1 - ct * ct);
        r.normal = {st * std::cos(ph), st * std::sin(ph), ct};
        r.branch = d * r.normal;
        r.fn = 1;
        c.contacts.push_back(r);
    }
    CgConfig cfg;
    cfg.width = d;
    cfg.n[0] = cfg.n[1] = cfg.n[2] = n;
    auto t0 = std::chrono::steady_clock::now();
    CgResult a = coarseGrain(cfg, s);
    auto t1 = std::chrono::steady_clock::now();
    CgResult b = coarseGrain(cfg, s, &c);
    auto t2 = std::chrono::steady_clock::now();
    const double ta = std::chrono::duration<double>(t1 - t0).count(), tb = std::chrono::duration<double>(t2 - t1).count();
    std::cout << "N = " << N << " particles, " << c.contacts.size() << " contacts, grid " << n << "^3, w = d, box L = "
              << L << " d, threads = " << threads << "\n"
              << "particles only (density, momentum, kinetic stress, fabric, coordination): " << ta << " s\n"
              << "particles + contacts (adds contact stress): " << tb << " s\n";
    return a.rho.empty() || b.rho.empty();
}

} // namespace

int main(int argc, char** argv) { return runTool("pdpm-cg-benchmark", [&] { return run(argc, argv); }); }
