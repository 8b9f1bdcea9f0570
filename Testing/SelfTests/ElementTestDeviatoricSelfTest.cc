// Self-test: DeviatoricD2 (self-prepared at v_i = 0.70, N = 500, frictionless), D2 pure shear to
// eps_dev = 0.3. Checks: volume is conserved, eps_dev reaches 0.3, s_dev rises from its initial value
// and then saturates (the mean over eps_dev in [0.15, 0.22] and over [0.22, 0.3] agree within 25 %,
// and both exceed 1.5 times the mean over eps_dev <= 0.01 and 0.1), the major stress eigenvector turns to z (compression).
// Then a short triaxial run: the lateral stresses stay at their start value within 15 % while z is
// compressed.
#include "../../Drivers/Deviatoric/DeviatoricD2.h"
#include "ElementTestCommon.h"

int main() {
    using namespace etest;
    int rc = runDriver<DeviatoricD2>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "d2", "--particles", "500", "--mu", "0",
                                      "--rate", "10", "--eps_dev_max", "0.3", "--outputs", "60"});
    check(rc == 0, "DeviatoricD2 exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable t = pdpm::readCsv("d2/DeviatoricD2.macro.csv");
    const int tau = t.column("tau");
    auto test = [&](const std::vector<double>& r) { return r[tau] >= 0; };
    const Series vf = select(t, "eps_dev", "volume_fraction", test);
    double dv = 0;
    for (double y : vf.y) dv = std::max(dv, std::fabs(y - vf.y.front()));
    check(dv < 1e-9, "volume conserved during D2 (max change " + std::to_string(dv) + ")");
    check(std::fabs(vf.x.back() - 0.3) < 1e-4, "eps_dev reaches 0.3 (" + std::to_string(vf.x.back()) + ")");
    const Series s = select(t, "eps_dev", "s_dev", test);
    const double s0 = meanOver(s, 0, 0.01), a = meanOver(s, 0.15, 0.22), b = meanOver(s, 0.22, 0.3);
    check(a > 1.5 * s0 && b > 1.5 * s0 && a > 0.1, "s_dev rises (start " + std::to_string(s0) + ", late " + std::to_string(b) + ")");
    check(std::fabs(a - b) < 0.25 * b, "s_dev saturates (" + std::to_string(a) + " vs " + std::to_string(b) + ")");
    const Series th = select(t, "eps_dev", "sig_theta1", test);
    check(meanOver(th, 0.1, 0.3) < 20, "major stress axis near z (" + std::to_string(meanOver(th, 0.1, 0.3)) + " deg)");

    rc = runDriver<DeviatoricD2>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "tri", "--particles", "500", "--mode", "triaxial",
                                  "--rate", "5", "--eps_dev_max", "0.05", "--outputs", "40"});
    check(rc == 0, "triaxial exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable u = pdpm::readCsv("tri/DeviatoricD2.macro.csv");
    const int ut = u.column("tau");
    const Series sxx = select(u, "tau", "sigma_xx", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const Series syy = select(u, "tau", "sigma_yy", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const Series szz = select(u, "tau", "sigma_zz", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const double goal = 0.5 * (sxx.y.front() + syy.y.front());
    const double lateEnd = 0.5 * (meanOver(sxx, 0.5, 1.0) + meanOver(syy, 0.5, 1.0));
    check(std::fabs(lateEnd / goal - 1) < 0.15, "triaxial lateral stress held (" + std::to_string(lateEnd / goal) + " of goal)");
    check(meanOver(szz, 0.5, 1.0) > 1.2 * lateEnd, "triaxial axial stress exceeds lateral stress");
    return failures ? 1 : 0;
}
