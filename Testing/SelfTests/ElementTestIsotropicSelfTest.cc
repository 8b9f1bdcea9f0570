// Self-test: IsotropicCompression, frictionless, N = 500, fast cycle (T = 0.02 s). Checks on the loading
// branch above jamming (v >= 0.68): C* >= 6 (isostatic limit of frictionless spheres, Sec. 2.5.1) and
// rising with v, p_nd rising with v (Eq. 2.14), E_k/E_p small at high density; restart files at the
// requested v_i on both branches; the cycle returns to v0.
#include <filesystem>

#include "../../Drivers/IsotropicCompression/IsotropicCompression.h"
#include "ElementTestCommon.h"

int main() {
    using namespace etest;
    const int rc = runDriver<IsotropicCompression>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "out", "--particles", "500",
                                                    "--mu", "0", "--period", "0.02", "--outputs", "60",
                                                    "--save_fractions", "0.70,0.75"});
    check(rc == 0, "driver exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable t = pdpm::readCsv("out/IsotropicCompression.macro.csv");
    const int tau = t.column("tau"), v = t.column("volume_fraction");
    auto loadingAbove = [&](const std::vector<double>& r) { return r[tau] > 0 && r[tau] <= 0.5 && r[v] >= 0.68; };
    const Series c = select(t, "volume_fraction", "C_star", loadingAbove);
    const Series p = select(t, "volume_fraction", "p_nd", loadingAbove);
    check(c.x.size() >= 8, "at least 8 loading rows above v = 0.68 (" + std::to_string(c.x.size()) + ")");
    double cmin = 1e9;
    for (double y : c.y) cmin = std::min(cmin, y);
    check(cmin >= 6.0, "C* >= 6 on loading above jamming (min " + std::to_string(cmin) + ")");
    const double rc1 = rankCorrelation(c), rp = rankCorrelation(p);
    check(rc1 > 0.9, "C* increases with v (rank correlation " + std::to_string(rc1) + ")");
    check(rp > 0.98, "p_nd increases with v (rank correlation " + std::to_string(rp) + ")");
    const Series top = select(t, "volume_fraction", "C_star", [&](const std::vector<double>& r) { return r[v] > 0.8; });
    check(!top.y.empty() && top.y.front() > 8.0, "C* > 8 at v > 0.8 (thesis: about 9.5 at 0.82)");
    const Series e = select(t, "volume_fraction", "Ek_over_Ep", [&](const std::vector<double>& r) { return r[v] > 0.72; });
    double emax = 0;
    for (double y : e.y) emax = std::max(emax, y);
    check(!e.y.empty() && emax < 0.05, "E_k/E_p < 0.05 above v = 0.72 (max " + std::to_string(emax) + ")");
    const double vEnd = t.rows.back()[v];
    check(std::fabs(vEnd - 0.64) < 1e-3, "cycle ends at v0 = 0.64 (" + std::to_string(vEnd) + ")");
    for (const char* f : {"out/IsotropicCompression.load_0.700.restart", "out/IsotropicCompression.load_0.750.restart",
                          "out/IsotropicCompression.unload_0.700.restart", "out/IsotropicCompression.unload_0.750.restart"})
        check(std::filesystem::exists(f), std::string("restart file ") + f);
    return failures ? 1 : 0;
}
