// The OedometerRelaxation driver's Hertz contacts (--hertz_modulus), which pdpm-explain's
// stiffness_nonlinearity DEM confirmation uses, on the default laterally periodic bed (about 180
// particles, the non-cohesive frictional material, load to 20 kPa - unload to 1 kPa - reload):
//  1. the protocol file names the law hertz-rolling-relax and the modulus;
//  2. a Hertzian bed (E* = 1e7 Pa), whose contacts soften as the force falls, unloads along a more
//     curved branch than the same bed with linear contacts: the unloading tangent at the top over the
//     secant to 20 % of the start stress (pdpm-explain's estimator) is larger by at least 0.15.
//     Measured 2026-12-04 on this bed: linear 1.235, Hertz 1.576 (E* = 5e7: 1.337, 5e6: 1.582); on
//     beds of about 900 particles, seeds 1-3 and 777: linear 1.08-1.17, Hertz E* = 5e7 1.32-1.41,
//     E* = 5e6 1.66-1.71;
//  3. --hertz_modulus without --k_over_k1 1 --kc_over_k 0 is refused (exit 2).
#include <cmath>

#include "IO/Json.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

struct Unload {
    double curvature = -1;
    int rc = -1;
};

/// Tangent over the top 20 % of the first unload (least squares of stress on strain) over the secant
/// from its start to the first sample at or below 20 % of the start stress.
Unload run(const std::string& modulus) {
    OedometerRelaxation d;
    Unload u;
    std::vector<std::string> args = {"--material", "frictional", "--steps", "ramp:1e-5:20000,unload:1e-5:1000,ramp:1e-5:20000",
                                     "--relax_C", "0", "--kc_over_k", "0", "--k_over_k1", "1", "--name", "e" + modulus, "--quiet",
                                     "--threads", "1"};
    if (modulus != "0") args.insert(args.end(), {"--hertz_modulus", modulus});
    u.rc = oedometer_selftest::runDriver(d, args);
    if (u.rc != 0) return u;
    const auto& rec = d.recordingData();
    const int cs = rec.column("step"), ce = rec.column("axial_strain"), cp = rec.column("axial_stress_Pa");
    std::vector<double> e, s;
    for (const auto& row : rec.rows)
        if (static_cast<int>(row[static_cast<std::size_t>(cs)]) == 1)
            e.push_back(row[static_cast<std::size_t>(ce)]), s.push_back(row[static_cast<std::size_t>(cp)]);
    if (e.size() < 10) return u;
    const double s0 = s.front(), e0 = e.front();
    double mx = 0, my = 0, n = 0;
    std::size_t top = 0;
    while (top < s.size() && s[top] >= 0.8 * s0) mx += e[top], my += s[top], ++n, ++top;
    std::size_t low = top;
    while (low < s.size() && s[low] > 0.2 * s0) ++low;
    if (n < 3 || low >= s.size()) return u;
    mx /= n, my /= n;
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < top; ++i) sxy += (e[i] - mx) * (s[i] - my), sxx += (e[i] - mx) * (e[i] - mx);
    const double tangent = sxy / sxx, secant = (s0 - s[low]) / (e0 - e[low]);
    u.curvature = tangent / secant;
    return u;
}

} // namespace

int main() {
    bool ok = true;
    const Unload lin = run("0"), hz = run("1e7");
    ok &= check(lin.rc == 0 && hz.rc == 0, "both runs (linear, Hertz E* = 1e7 Pa)");
    if (lin.rc != 0 || hz.rc != 0) return 1;
    std::printf("     unloading curvature (tangent at the top / secant to 20 %%): linear %.4g, Hertz %.4g\n", lin.curvature, hz.curvature);
    const Json proto = readJsonFile("e1e7.protocol.json");
    ok &= check(proto.at("material").at("contact_law").asString() == "hertz-rolling-relax", "the protocol file names the Hertz law");
    ok &= check(proto.at("material").at("E_star_Pa").asNumber() == 1e7, "the protocol file has E*");
    ok &= check(lin.curvature > 0 && hz.curvature > lin.curvature + 0.15, "the Hertzian bed unloads along a more curved branch");
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--hertz_modulus", "1e8", "--quiet"}) == 2, "Hertz with the plastic cocoa preset refused");
    }
    return ok ? 0 : 1;
}
