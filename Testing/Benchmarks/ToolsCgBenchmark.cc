// Speed of the coarse-graining library: one snapshot of N particles (random dense packing in a
// periodic box, contacts between all pairs closer than 1.05 d) onto an n³ grid, width w = d.
// Usage: pdpm-cg-benchmark [N=100000] [n=50] [threads=2]. Not a test: prints the timings.
#include "CoarseGraining.h"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>

using namespace pdpm;
using namespace pdpm::tools;

int main(int argc, char** argv) {
    const int N = argc > 1 ? std::atoi(argv[1]) : 100000;
    const int n = argc > 2 ? std::atoi(argv[2]) : 50;
    const int threads = argc > 3 ? std::atoi(argv[3]) : 2;
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
