// Self-test: UniaxialCyclic from a start configuration written by IsotropicCompression (the unloading
// branch at v = 0.70), N = 500, frictional (mu = 0.5), fast cycle. Checks: the test starts at the
// saved volume fraction, reaches v_max, returns to v_i; on loading p_nd grows with v and the active
// axis carries the largest stress (sigma_zz > sigma_xx, sigma_yy), the deviatoric strain equals
// ln(v / v_i) in every row (x, y fixed) and its engineering form 1 - v_i/v, and the macro CSV has
// the thesis' columns.
#include <algorithm>
#include <filesystem>

#include "../../Drivers/IsotropicCompression/IsotropicCompression.h"
#include "../../Drivers/UniaxialCyclic/UniaxialCyclic.h"
#include "ElementTestCommon.h"

int main() {
    using namespace etest;
    int rc = runDriver<IsotropicCompression>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "iso", "--particles", "500",
                                              "--period", "0.02", "--outputs", "20", "--save_fractions", "0.70"});
    check(rc == 0 && std::filesystem::exists("iso/IsotropicCompression.unload_0.700.restart"),
          "IsotropicCompression wrote the start configuration");
    if (failures) return 1;
    rc = runDriver<UniaxialCyclic>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "uni", "--name", "uni", "--start",
                                    "iso/IsotropicCompression.unload_0.700.restart", "--period", "0.02",
                                    "--outputs", "60", "--save_fractions", ""});
    check(rc == 0, "UniaxialCyclic exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable t = pdpm::readCsv("uni/uni.macro.csv");
    const int tau = t.column("tau"), v = t.column("volume_fraction"), ed = t.column("eps_dev"),
              ee = t.column("eps_dev_eng");
    double vStart = 0, vPeak = 0, worstTrue = 0, worstEng = 0;
    int testRows = 0;
    for (const auto& r : t.rows) {
        if (r[tau] <= 0) vStart = r[v];
        vPeak = std::max(vPeak, r[v]);
    }
    // x and y fixed, the solid volume constant: L_z/L_z0 = v_i/v in every row, so eps_dev = ln(v/v_i)
    // (true strain, Eq. 2.4) and eps_dev_eng = 1 - v_i/v (chapter 3's Eq. 3.2) hold to round-off
    for (const auto& r : t.rows)
        if (r[tau] > 0) {
            ++testRows;
            worstTrue = std::max(worstTrue, std::fabs(r[ed] - std::log(r[v] / vStart)));
            worstEng = std::max(worstEng, std::fabs(r[ee] - (1 - vStart / r[v])));
        }
    check(std::fabs(vStart - 0.70) < 0.003, "test starts at v_i = 0.70 (" + std::to_string(vStart) + ")");
    check(std::fabs(vPeak - 0.82) < 1e-3, "loading reaches v_max = 0.82 (" + std::to_string(vPeak) + ")");
    check(testRows > 10 && worstTrue < 1e-9,
          "eps_dev = ln(v/v_i) in every row of the test (largest difference " + std::to_string(worstTrue) + ")");
    check(testRows > 10 && worstEng < 1e-9,
          "eps_dev_eng = 1 - v_i/v in every row of the test (largest difference " + std::to_string(worstEng) + ")");
    check(std::fabs(t.rows.back()[v] - vStart) < 1e-3, "unloading returns to v_i");
    auto loading = [&](const std::vector<double>& r) { return r[tau] > 0.05 && r[tau] <= 0.5; };
    const Series p = select(t, "volume_fraction", "p_nd", loading);
    check(rankCorrelation(p) > 0.98, "p_nd grows with v on loading (rank correlation " +
                                         std::to_string(rankCorrelation(p)) + ")");
    const Series sx = select(t, "tau", "sigma_xx", loading), sz = select(t, "tau", "sigma_zz", loading);
    int zLargest = 0;
    for (std::size_t i = 0; i < sx.y.size(); ++i) zLargest += sz.y[i] > sx.y[i];
    check(zLargest == static_cast<int>(sx.y.size()), "sigma_zz > sigma_xx throughout loading");
    const Series s = select(t, "tau", "s_dev", loading);
    check(!s.y.empty() && meanOver(s, 0.3, 0.5) > 0.1, "s_dev > 0.1 late in loading (" +
                                                         std::to_string(meanOver(s, 0.3, 0.5)) + ")");
    for (const char* col : {"F_dev_star", "C_star", "phi_r", "f_wsl", "mobilisation", "sig_theta1"}) check(t.hasColumn(col), col);
    return failures ? 1 : 0;
}
