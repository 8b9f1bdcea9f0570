// OedometerRelaxation, history effect of thesis Fig. 4.8 in a small laterally periodic bed
// (frictional material, 79 particles): ramp to 2.5 kPa, hold T1, ramp to 5 kPa, hold 300 s, with
// T1 = 300 s and T1 = 1800 s, and the relaxation clock memory m = 0.1 (--relax_memory; a reload
// f_ref -> f_new shortens a contact's clock by (f_ref/f_new)^(1/m)).
//  - The first hold is the same bed under the same loading: its drop 250 s into the hold is bitwise the
//    same in both runs, and after 300 s the same to the sampling, as in the thesis ("the first step
//    does not change").
//  - The second hold's drop after 300 s is smaller after the longer first hold. Expected size, one
//    contact that doubles its force: clock after the reload 300 s * 2^-10 = 0.29 s against
//    1800 s * 2^-10 = 1.76 s, drop 1 - ((t0 + t_s + 300)/(t0 + t_s))^-C = 0.389 against 0.325, a
//    16 % smaller drop. The check asks for at least 7 % (less than half of that); without memory
//    (m = 0, the clock restarts at every load increase) the same comparison scattered by -1.5, -0.2
//    and +0.9 % over three seeds (Documentation/driver-oedometer-relaxation.md), so 7 % is far
//    outside what the bed's noise can produce, and the check fails if the clock forgets.
//  - Table 4.4 trend (fitted C falls from R1 to R5) on a 268-particle cocoa bed, protocol 1.
#include <cmath>

#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

/// Relative stress drop `after` lab seconds into hold `h` (linear interpolation between samples; a
/// hold that ends at `after` may end a hair before it, see ConfinedCompression's end-of-step test).
double dropAfter(const OedometerHold& h, double after) {
    const double target = h.labStart + after;
    if (h.t.empty() || target < h.t.front()) return std::nan("");
    if (target >= h.t.back()) return target - h.t.back() <= 1e-6 * after ? 1 - h.s.back() / h.stressStart : std::nan("");
    for (std::size_t i = 1; i < h.t.size(); ++i)
        if (h.t[i] >= target) {
            const double w = (target - h.t[i - 1]) / (h.t[i] - h.t[i - 1]);
            return 1 - ((1 - w) * h.s[i - 1] + w * h.s[i]) / h.stressStart;
        }
    return std::nan("");
}

} // namespace

int main() {
    bool ok = true;
    double first[2] = {0, 0}, second[2] = {0, 0}, early[2] = {0, 0};
    const char* holds[2] = {"300", "1800"};
    for (int run = 0; run < 2; ++run) {
        OedometerRelaxation d;
        const std::string steps = std::string("ramp:5e-5:2500,hold:") + holds[run] + ",ramp:5e-5:5000,hold:300";
        std::vector<std::string> args = {"--material", "frictional", "--width", "4", "--fill_height", "5",
                                         "--steps", steps, "--relax_memory", "0.1", "--quiet", "--threads", "1",
                                         "--name", std::string("first_hold_") + holds[run]};
        ok &= check(oedometer_selftest::runDriver(d, args) == 0, std::string("run with a first hold of ") + holds[run] + " s");
        if (d.holds().size() != 2) {
            ok &= check(false, "two holds");
            continue;
        }
        first[run] = dropAfter(d.holds()[0], 300);
        early[run] = dropAfter(d.holds()[0], 250);
        if (run == 0)
            std::printf("     first hold 300 s: fitted C %.5f (t0 %.4g s), second hold C %.5f (t0 %.4g s)\n",
                        d.holds()[0].fit.C, d.holds()[0].fit.t0, d.holds()[1].fit.C, d.holds()[1].fit.t0);
        second[run] = dropAfter(d.holds()[1], 300);
        std::printf("     first hold %s s: drop after 300 s %.5f (first hold), %.5f (second hold); max Ek/Ep %.3g, %.3g\n",
                    holds[run], first[run], second[run], d.holds()[0].maxEkEp, d.holds()[1].maxEkEp);
    }
    ok &= check(first[0] > 0.1, "the first hold relaxes (drop after 300 s > 10 %)");
    // Identical trajectories up to 300 s: at 250 s both runs interpolate between the same samples (bitwise
    // equal); at 300 s the shorter hold ends on a sample of its own while the longer one interpolates.
    std::printf("     first hold: drop after 250 s %.12f and %.12f, after 300 s %.9f and %.9f\n", early[0], early[1],
                first[0], first[1]);
    ok &= check(early[0] == early[1], "first hold: the same drop after 250 s in both runs (bitwise)");
    ok &= check(std::abs(first[0] - first[1]) <= 1e-5, "first hold: the same drop after 300 s (to the sampling, 1e-5)");
    const double change = second[1] / second[0] - 1;
    std::printf("     second hold: drop %.5f after a 300 s first hold, %.5f after 1800 s (%+.2f %%; one contact: -16 %%)\n",
                second[0], second[1], 100 * change);
    ok &= check(change < -0.07, "a longer previous hold reduces the next hold's drop by more than 7 %");
    // The fitted C of the two holds is printed, not checked: in this bed it also falls without memory
    // (0.0774 -> 0.0732, -5 %), as much as the memory is expected to add (about -8 %), so a check could
    // not tell the two apart; the Table 4.4 trend is checked on a larger bed below.
    {
        // Table 4.4 trend, small version: cocoa bed 6 d wide (268 particles), protocol 1 (five steps of
        // 5 kPa, 300 s holds), memory 0.1. Measured at the validation (2026-12-01): fitted C 0.0599 ->
        // 0.0418 from R1 to R5 (-30 %; thesis lambdameter -30 %); without memory the same bed gives
        // 0.0593, 0.0597, 0.0583, 0.0588, 0.0557 (-6 %; an earlier realisation -2 % with 6 % scatter
        // between steps). The check asks for -15 %, half the expected fall, and fails without memory.
        OedometerRelaxation d;
        std::vector<std::string> args = {"--protocol", "1", "--width", "6", "--fill_height", "8", "--relax_memory", "0.1",
                                         "--quiet", "--threads", "1", "--name", "trend"};
        ok &= check(oedometer_selftest::runDriver(d, args) == 0, "protocol 1, cocoa bed, memory 0.1");
        const auto& h = d.holds();
        if (h.size() == 5) {
            std::printf("     fitted C R1..R5: %.4f %.4f %.4f %.4f %.4f\n", h[0].fit.C, h[1].fit.C, h[2].fit.C, h[3].fit.C,
                        h[4].fit.C);
            ok &= check(h[0].fit.ok && h[4].fit.ok && h[4].fit.C < 0.85 * h[0].fit.C,
                        "Table 4.4 trend: fitted C of R5 at least 15 % below R1's");
        } else {
            ok &= check(false, "five holds");
        }
    }
    std::printf("%s\n", ok ? "OedometerHistorySelfTest passed" : "OedometerHistorySelfTest FAILED");
    return ok ? 0 : 1;
}
