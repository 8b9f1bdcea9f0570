// The OedometerRelaxation driver's mould wall friction (--wall_friction) and pour wall friction
// (--fill_wall_friction), which pdpm-explain's wall_friction DEM confirmation uses, in a small
// cylindrical mould (D = 15 mm, 6 mean diameters; elastic cocoa contacts without adhesion and
// relaxation; load to 4 kPa, unload, reload):
//  1. --fill_wall_friction 0 pours the same bed whatever --wall_friction is (the first recorded
//     sample, volume fraction and piston height, is bitwise the same for mu_w = 0 and 0.4);
//  2. frictionless walls carry nothing: the bottom stress exceeds the piston stress by the bed's
//     weight over the area, rho_s phi g H (both averaged over the first loading's samples above half
//     its peak stress; within 25 %: 0-9 % on four fill seeds, 2026-12-03);
//  3. with mu_w = 0.4 the walls carry part of the load: bottom/piston at the peak is below 0.9, and
//     the wall shear per bed area that the vertical force balance needs, piston - bottom + weight/area,
//     is at most Coulomb's 4 mu_w (h/D) sigma_lat (every wall contact sliding; sigma_lat the mean
//     radial stress on the wall) and at least 0.15 of it (0.32-0.66 at the peak over five fill seeds);
//  4. the protocol file records mu_w (device.wall_friction) and the pour's (extra.fill_wall_friction);
//     --fill_wall_friction -0.5 is refused (exit 2).
#include <cmath>

#include "IO/Json.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

constexpr double kD = 0.015;

struct Peak {
    int rc = -1;
    double phi0 = 0, z0 = 0;                    // first sample: volume fraction, piston height
    double piston = 0, bottom = 0, lateral = 0;  // stresses at the peak of the first loading (Pa)
    double h = 0, phiPeak = 0;                  // bed height and volume fraction at the peak
    double excess = 0, weight = 0;              // means of bottom - piston and rho_s phi g H (Pa) over the upper half of the first loading
};

Peak run(const std::string& mu) {
    OedometerRelaxation d;
    Peak p;
    p.rc = oedometer_selftest::runDriver(
        d, {"--geometry", "cylinder", "--diameter", "0.015", "--fill_height_m", "0.015", "--steps", "ramp:5e-5:40000,unload:5e-5:0,ramp:5e-5:40000",
            "--stress_scale", "0.1", "--relax_C", "0", "--kc_over_k", "0", "--k_over_k1", "1", "--wall_friction", mu, "--fill_wall_friction", "0",
            "--ramp_rate", "1", "--name", "w" + mu, "--quiet", "--vtk", "0", "--ene", "0", "--threads", "1"});
    if (p.rc != 0) return p;
    const auto& rec = d.recordingData();
    const auto col = [&](const char* n) { return static_cast<std::size_t>(rec.column(n)); };
    const std::size_t cs = col("step"), cp = col("axial_stress_Pa"), cb = col("bottom_stress_Pa"), cl = col("lateral_stress_Pa"),
                      cf = col("volume_fraction"), cz = col("piston_position_m");
    p.phi0 = rec.rows.front()[cf];
    p.z0 = rec.rows.front()[cz];
    for (const auto& row : rec.rows)
        if (row[cs] == 0 && row[cp] > p.piston) p.piston = row[cp], p.bottom = row[cb], p.lateral = row[cl], p.h = row[cz], p.phiPeak = row[cf];
    int n = 0;
    for (const auto& row : rec.rows)
        if (row[cs] == 0 && row[cp] >= 0.5 * p.piston) {
            p.excess += row[cb] - row[cp];
            p.weight += 1427 * row[cf] * 9.81 * row[cz];  // cocoa grain density (Table 5.3)
            ++n;
        }
    p.excess /= n;
    p.weight /= n;
    return p;
}

} // namespace

int main() {
    bool ok = true;
    const Peak a = run("0"), b = run("0.4");
    ok &= check(a.rc == 0 && b.rc == 0, "both runs (mu_w = 0 and 0.4)");
    if (a.rc != 0 || b.rc != 0) return 1;
    ok &= check(a.phi0 == b.phi0 && a.z0 == b.z0, "--fill_wall_friction 0: the same poured bed for mu_w = 0 and 0.4");
    std::printf("     mu_w 0:   bottom - piston %.4g Pa, bed weight/area %.4g Pa (means over the upper half of the loading)\n", a.excess, a.weight);
    ok &= check(std::abs(a.excess - a.weight) < 0.25 * a.weight, "frictionless walls: bottom - piston = the bed's weight per area");
    const double ratio = b.bottom / b.piston, shear = b.piston - b.bottom + 1427 * b.phiPeak * 9.81 * b.h,
                 coulomb = 4 * 0.4 * (b.h / kD) * b.lateral;
    std::printf("     mu_w 0.4: bottom/piston %.4g; wall shear per bed area %.4g Pa, Coulomb's limit %.4g Pa (mobilised %.3g)\n", ratio, shear,
                coulomb, shear / coulomb);
    ok &= check(ratio < 0.9, "mu_w 0.4: the walls carry part of the load (bottom/piston < 0.9)");
    ok &= check(shear <= coulomb && shear >= 0.15 * coulomb, "mu_w 0.4: the wall shear is within Coulomb's limit 4 mu_w (h/D) sigma_lat, and not negligible");
    const Json proto = readJsonFile("w0.4.protocol.json");
    ok &= check(proto.at("device").at("wall_friction").asNumber() == 0.4 && proto.at("extra").at("fill_wall_friction").asNumber() == 0,
                "the protocol file records mu_w and the pour's mu_w");
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--fill_wall_friction", "-0.5", "--quiet"}) == 2, "fill mu_w = -0.5 refused");
    }
    return ok ? 0 : 1;
}
