// The OedometerRelaxation driver's lift-off test: an unload with a negative target stress (tension)
// and adhesive walls (--wall_kc_over_k), on a small periodic bed of cocoa contacts without relaxation
// (load to 4 kPa, unload towards -1e9 Pa, i.e. until the piston comes free or is back at its start
// height, reload):
//  1. cohesive contacts (Luding's law, k/k1 = 5, kc/k = 0.873) and sticky walls: the unload goes on
//     past zero force into tension, at least 5 % of the peak stress (measured 11-12 %, 2026-12-05);
//  2. the same bed with walls that are not sticky: no tension beyond the dashpot's (at most 1 % of
//     the peak) and the unload ends at lift-off, the piston free (zero force) below its start height;
//  3. sticky walls but elastic contacts (k/k1 = 1): Luding's law has no tension without plastic
//     overlap (delta0 = 0), so again at most 1 % of the peak and lift-off;
//  4. sticky walls and a reachable tension (unload:V:-2000 x 0.1 = -200 Pa): the unload ends at the
//     tension (its last sample at most -200 Pa and above -260 Pa), below the start height;
//  5. a negative ramp target, a negative --wall_kc_over_k, Hertz contacts with sticky walls, a creep
//     stress that is not positive, and a creep at the stress reached after an unload into tension are
//     refused (exit 2).
#include <algorithm>
#include <cmath>

#include "IO/Json.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

struct LiftOff {
    double peak = 0, tension = 0, endStrain = 0, endStress = 0;
    int rc = -1;
};

LiftOff run(const std::string& name, std::vector<std::string> extra, const std::string& pull = "-1e9") {
    OedometerRelaxation d;
    std::vector<std::string> args = {"--width", "4", "--fill_height", "5", "--steps", "ramp:5e-5:40000,unload:5e-5:" + pull + ",ramp:5e-5:40000",
                                     "--stress_scale", "0.1", "--relax_C", "0", "--name", name, "--quiet", "--threads", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    LiftOff c;
    c.rc = oedometer_selftest::runDriver(d, args);
    if (c.rc != 0) return c;
    for (const auto& [step, e, s] : oedometer_selftest::samples(d)) {
        if (step == 0) c.peak = std::max(c.peak, s);
        if (step == 1) c.tension = std::max(c.tension, -s), c.endStrain = e, c.endStress = s;  // last sample: the unload's end
    }
    return c;
}

} // namespace

int main() {
    bool ok = true;
    const LiftOff sticky = run("sticky", {"--wall_kc_over_k", "0.873"});
    const LiftOff plain = run("plain", {"--wall_kc_over_k", "0"});
    const LiftOff elastic = run("elastic", {"--wall_kc_over_k", "0.873", "--k_over_k1", "1"});
    const LiftOff reach = run("reach", {"--wall_kc_over_k", "0.873"}, "-2000");
    ok &= check(sticky.rc == 0 && plain.rc == 0 && elastic.rc == 0 && reach.rc == 0,
                "four runs (sticky walls, plain walls, elastic contacts, sticky walls to -200 Pa)");
    if (!ok) return 1;
    for (const auto& [what, c] : {std::pair{"sticky walls", &sticky}, std::pair{"plain walls", &plain}, std::pair{"elastic contacts", &elastic},
                                  std::pair{"sticky walls to -200 Pa", &reach}})
        std::printf("     %s: peak %.5g Pa, largest tension %.4g Pa (%.2f %% of the peak), unload ended at strain %.4g, stress %.4g Pa\n", what,
                    c->peak, c->tension, 100 * c->tension / c->peak, c->endStrain, c->endStress);
    ok &= check(sticky.tension > 0.05 * sticky.peak, "cohesive contacts and sticky walls: tension of at least 5 % of the peak stress on unloading");
    ok &= check(plain.tension < 0.01 * plain.peak, "plain walls: no tension beyond the dashpot's (below 1 % of the peak)");
    ok &= check(plain.endStress == 0 && plain.endStrain > 1e-4, "plain walls: the unload ends at lift-off (zero force) below the start height");
    ok &= check(elastic.tension < 0.01 * elastic.peak, "elastic contacts (k/k1 = 1): no tension (Luding's law needs plastic overlap)");
    ok &= check(elastic.endStress == 0 && elastic.endStrain > 1e-4, "elastic contacts: the unload ends at lift-off below the start height");
    ok &= check(reach.endStress <= -200 && reach.endStress > -260 && reach.endStrain > 1e-4,
                "a reachable tension (-200 Pa): the unload ends there, below the start height");
    const Json proto = readJsonFile("sticky.protocol.json");
    ok &= check(std::abs(proto.at("material").at("wall_kc_N_m").asNumber() - 0.873 * proto.at("material").at("k_N_m").asNumber()) <
                    1e-9 * proto.at("material").at("k_N_m").asNumber(),
                "the protocol file has the wall's kc = 0.873 k");
    ok &= check(std::abs(proto.at("steps").asArray("steps").at(1).at("target_stress_Pa").asNumber() + 1e8) < 1, "the protocol file has the scaled tension target");
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"--steps", "ramp:5e-5:-100"}, {"--wall_kc_over_k", "-0.5"},
          {"--hertz_modulus", "1e8", "--k_over_k1", "1", "--kc_over_k", "0", "--wall_kc_over_k", "0.5"}, {"--steps", "ramp:5e-5:1000,creep:10:-5"},
          {"--width", "4", "--fill_height", "5", "--relax_C", "0", "--wall_kc_over_k", "0.873", "--stress_scale", "0.1", "--threads", "1", "--steps",
           "ramp:5e-5:40000,unload:5e-5:-2000,creep:10"}}) {
        OedometerRelaxation d;
        std::vector<std::string> args = bad;
        args.push_back("--quiet");
        std::string line;
        for (const auto& a : bad) line += " " + a;
        ok &= check(oedometer_selftest::runDriver(d, args) == 2, "refused (exit 2):" + line);
    }
    return ok ? 0 : 1;
}
