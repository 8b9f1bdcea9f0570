// The OedometerRelaxation driver's contact viscosity on the lab clock (--contact_viscous_time), the DEM
// ingredient of pdpm-explain's rate_dependence, on the default laterally periodic bed (about 180
// cocoa particles, relaxation off): a ramp that speeds up ten-fold without stopping, then a hold.
//  0. the two runs (with and without the viscosity) compress the same poured bed;
//  1. the protocol file names the law luding-relax-viscous and the viscous time;
//  2. the viscous stress (stress with the viscosity minus without, at the same strain) is there on
//     the slow part and over five times larger after the ten-fold speed-up. Whether it is
//     proportional to the rate this small bed cannot tell: its collapses move the difference by up to
//     300 Pa (measured 2026-12-07 on one bed: E_v = stress / (tau rate) 1.30e6 Pa slow and 0.81e6 Pa
//     fast at the points below, ratio 0.62; 0.93 averaged over the middle half of each part; 1.02 on
//     the full-length protocol of driver-oedometer-relaxation.md). A check that E_v agreed within 35 %
//     passed until 2026-12-06 only because the two runs compressed different beds (the viscous run
//     poured with the viscous law, whose last bits differ) and was dropped when that was fixed;
//  3. in the hold the viscous bed loses most of its excess over the bed without viscosity (the
//     Maxwell branch fades within tau/4 lab seconds), the bed without viscosity almost nothing;
//  4. --contact_viscous_time with Hertz contacts or with another contact law is refused (exit 2).
#include <algorithm>
#include <cmath>

#include "IO/Json.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

struct Run {
    int rc = -1;
    std::vector<oedometer_selftest::Sample> s;
    double height = 0;  ///< bed height at the start (m), for the lab strain rates
    std::size_t particles = 0;
};

constexpr double kSlow = 5e-6, kFast = 5e-5;  // lab piston speeds (m/s)

Run run(const std::string& tau) {
    OedometerRelaxation d;
    Run r;
    r.rc = oedometer_selftest::runDriver(d, {"--steps", "ramp:5e-6:3000,ramp:5e-5:7000,hold:20", "--relax_C", "0", "--contact_viscous_time",
                                             tau, "--name", "tau" + tau, "--quiet", "--threads", "1"});
    if (r.rc != 0) return r;
    r.s = oedometer_selftest::samples(d);
    r.particles = d.particles().size();
    r.height = readJsonFile("tau" + tau + ".protocol.json").at("device").at("height_m").asNumber();
    return r;
}

/// Stress of the loading (steps 0-1) at strain e, linearly interpolated; -1 if not reached.
double stressAt(const Run& r, double e) {
    for (std::size_t i = 1; i < r.s.size(); ++i)
        if (r.s[i].step <= 1 && r.s[i - 1].strain < e && r.s[i].strain >= e) {
            const double w = (e - r.s[i - 1].strain) / (r.s[i].strain - r.s[i - 1].strain);
            return r.s[i - 1].stress + w * (r.s[i].stress - r.s[i - 1].stress);
        }
    return -1;
}

/// First and last stress of protocol step k.
std::pair<double, double> stepEnds(const Run& r, int k) {
    double a = -1, b = -1;
    for (const auto& x : r.s)
        if (x.step == k) {
            if (a < 0) a = x.stress;
            b = x.stress;
        }
    return {a, b};
}

/// Strain where step k begins.
double stepStrain(const Run& r, int k) {
    for (const auto& x : r.s)
        if (x.step == k) return x.strain;
    return -1;
}

} // namespace

int main() {
    bool ok = true;
    const double tau = 0.5;
    const Run plain = run("0"), visc = run("0.5");
    ok &= check(plain.rc == 0 && visc.rc == 0, "the two runs (no viscosity, contact viscous time 0.5 lab s)");
    if (!ok) return 1;
    // the viscous law (and its shorter time step) starts after the pour: both runs compress the same bed
    std::printf("     beds: %zu and %zu particles, %.10g and %.10g m high\n", plain.particles, visc.particles, plain.height, visc.height);
    ok &= check(plain.particles == visc.particles && plain.height == visc.height, "both runs compress the same poured bed");
    const Json proto = readJsonFile("tau0.5.protocol.json");
    ok &= check(proto.at("material").at("contact_law").asString() == "luding-relax-viscous", "the protocol file names luding-relax-viscous");
    ok &= check(proto.at("material").at("contact_viscous_time_s").asNumber() == tau, "the protocol file has the viscous time");

    // the viscous stress on the slow part (half way to where the viscous bed speeds up) and on the
    // fast part (half way between the speed-up and the end of the viscous bed's ramp)
    const double e1 = stepStrain(visc, 1), e2 = stepStrain(visc, 2);
    const double eSlow = 0.5 * e1, eFast = 0.5 * (e1 + e2);
    const double dSlow = stressAt(visc, eSlow) - stressAt(plain, eSlow), dFast = stressAt(visc, eFast) - stressAt(plain, eFast);
    const double rSlow = kSlow / visc.height, rFast = kFast / visc.height;  // lab strain rates (1/s)
    const double evSlow = dSlow / (tau * rSlow), evFast = dFast / (tau * rFast);
    std::printf("     viscous stress: %.4g Pa at strain %.4g (rate %.3g /s), %.4g Pa at %.4g (rate %.3g /s): E_v %.3g and %.3g Pa (ratio %.3g)\n",
                dSlow, eSlow, rSlow, dFast, eFast, rFast, evSlow, evFast, evFast / evSlow);
    ok &= check(dSlow > 0 && dFast > 5 * dSlow, "the viscous stress grows with the rate (over five times after the ten-fold speed-up)");

    // the hold: the viscous excess fades, the plain bed keeps its stress
    const auto [v0, v1] = stepEnds(visc, 2);
    const auto [p0, p1] = stepEnds(plain, 2);
    std::printf("     hold: viscous bed %.5g -> %.5g Pa, plain bed %.5g -> %.5g Pa\n", v0, v1, p0, p1);
    ok &= check(v0 - v1 > 0.5 * dFast, "the viscous bed loses most of its viscous excess in the hold");
    ok &= check(std::abs(p0 - p1) < 0.01 * p0, "the bed without viscosity keeps its stress in the hold (within 1 %)");

    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--contact_viscous_time", "0.5", "--hertz_modulus", "1e8", "--material", "frictional",
                                                      "--quiet"}) == 2,
                    "the viscosity with Hertz contacts refused");
    }
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--contact_viscous_time", "0.5", "--contact_law", "linear-relax", "--quiet"}) == 2,
                    "the viscosity with a law without the viscous branch refused");
    }
    return ok ? 0 : 1;
}
