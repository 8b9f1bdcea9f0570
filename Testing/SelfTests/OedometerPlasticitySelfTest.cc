// The OedometerRelaxation driver's Luding plasticity flag (--k_over_k1) and protocol stress scale
// (--stress_scale), which pdpm-explain's plasticity DEM confirmation uses, on a small periodic bed
// (cocoa contacts without adhesion and relaxation, load - unload to zero - reload):
//  1. the targets of --steps are multiplied by --stress_scale (peak stress 40 kPa x 0.1 = 4 kPa);
//  2. k/k1 = 5 sets k1 = k/5 (protocol file) and leaves more of the peak strain after the unload
//     than elastic contacts (k/k1 = 1): measured 94 % against 65 % (2026-12-02);
//  3. the unloading branch is stiffer than the loading branch with plastic contacts, by much more
//     than with elastic contacts (secant of the unload over the secant of the load);
//  4. k/k1 between 0 and 1 (0.5) and kc/k between -1 and 0 (-0.5) are refused (exit 2).
#include <cmath>

#include "IO/Json.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

struct Cycle {
    double peakStress = 0, peakStrain = 0, unloadedStrain = 0;
    int rc = -1;
};

Cycle run(const std::string& ratio) {
    OedometerRelaxation d;
    Cycle c;
    c.rc = oedometer_selftest::runDriver(d, {"--width", "4", "--fill_height", "5", "--steps", "ramp:5e-5:40000,unload:5e-5:0,ramp:5e-5:40000",
                                             "--stress_scale", "0.1", "--relax_C", "0", "--kc_over_k", "0", "--k_over_k1", ratio,
                                             "--name", "k" + ratio, "--quiet", "--threads", "1"});
    if (c.rc != 0) return c;
    for (const auto& [step, e, s] : oedometer_selftest::samples(d)) {
        if (step == 0 && s > c.peakStress) c.peakStress = s, c.peakStrain = e;
        if (step == 1) c.unloadedStrain = e;  // last sample of the unload
    }
    return c;
}

} // namespace

int main() {
    bool ok = true;
    const Cycle el = run("1"), pl = run("5");
    ok &= check(el.rc == 0 && pl.rc == 0, "both runs (k/k1 = 1 and 5)");
    if (el.rc != 0 || pl.rc != 0) return 1;
    for (const Cycle* c : {&el, &pl})
        std::printf("     peak %.5g Pa at strain %.4g, strain after unloading %.4g (%.1f %% of the peak strain)\n", c->peakStress,
                    c->peakStrain, c->unloadedStrain, 100 * c->unloadedStrain / c->peakStrain);
    ok &= check(el.peakStress >= 4000 && el.peakStress < 4400 && pl.peakStress >= 4000 && pl.peakStress < 4400,
                "--stress_scale 0.1 brings the 40 kPa target to 4 kPa");
    const Json proto = readJsonFile("k5.protocol.json");
    const double k = proto.at("material").at("k_N_m").asNumber(), k1 = proto.at("material").at("k1_N_m").asNumber();
    ok &= check(std::abs(k1 - k / 5) < 1e-9 * k, "k/k1 = 5 gives k1 = k/5 in the protocol file");
    ok &= check(std::abs(proto.at("steps").asArray("steps").at(0).at("target_stress_Pa").asNumber() - 4000) < 1e-6, "the protocol file has the scaled target");
    const double keepEl = el.unloadedStrain / el.peakStrain, keepPl = pl.unloadedStrain / pl.peakStrain;
    ok &= check(keepPl > 0.85 && keepPl > keepEl + 0.15, "plastic contacts keep more of the peak strain after unloading");
    // unload secant over load secant
    const double ratioEl = el.peakStrain / (el.peakStrain - el.unloadedStrain), ratioPl = pl.peakStrain / (pl.peakStrain - pl.unloadedStrain);
    std::printf("     unload/load secant stiffness: %.3g (k/k1 = 1), %.3g (k/k1 = 5)\n", ratioEl, ratioPl);
    ok &= check(ratioPl > 3 * ratioEl, "the unloading branch is much stiffer than loading with plastic contacts");
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--k_over_k1", "0.5", "--quiet"}) == 2, "k/k1 = 0.5 refused");
    }
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--kc_over_k", "-0.5", "--quiet"}) == 2, "kc/k = -0.5 refused");
    }
    return ok ? 0 : 1;
}
