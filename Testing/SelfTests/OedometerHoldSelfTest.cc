// OedometerRelaxation, small laterally periodic bed (frictional, non-cohesive material), ramp to
// 5 kPa then a hold of 300 lab seconds at constant piston position, twice:
//  1. relaxation off (relax_C 0): the ramp reaches the target; the hold starts within 5 % of it (the
//     hold's f_max is the stress after the mechanical settling at fixed piston); the axial stress
//     during the hold stays within 5 % of its start value (one eighth of the relaxing drop below),
//     and the run is quasi-static (Ek/Ep <= 1e-4 at the end of the hold).
//     Why 5 % and not the 1 %: this bed has 79 particles, and a single rearrangement event
//     moves its stress by more than 1 %. Eight seeds of this run (Release build, 2026-12-01): hold
//     start 1.95 % below the target at worst, largest deviation during the hold 1.71, 0.53, 0.18,
//     0.30, 0.10, 0.13, 0.10, 0.22 % (the 1.71 % with a rearrangement event, max E_k/E_p 1.5e-3);
//     the sanitizer build's realisation gave 1.17 %. The 1 % figure is checked at FT4 scale
//     (5331 particles) by Testing/Validation/oedometer_validation.sh.
//  2. relaxation on (C = 0.0792, t0 = 0.2894 s, Table 4.4 R1 lambdameter): the stress decays, the
//     fitted macroscopic C of Eq. 4.3 is within 30 % of the contact C, and the decay is at least
//     half of the contact-level prediction 1 - (1 + 300/t0)^(-C); E_k/E_p <= 1e-4 in at least 95 %
//     of the samples taken while the lab clock ran (each sample above starts a clock pause, a
//     rearrangement event), and the pauses cost less DEM time than the hold itself.
//  3. a short response time (C = 0.0206, t0 = 0.2 ms: Table 4.5's limestone), hold of 1 lab second,
//     with the contacts relaxing in the holds only (--relax_in_ramps 0): every contact the ramp loaded
//     starts the hold at clock 0, so the bed loses at least half the contact-level drop by t = 10 t0
//     (measured 0.92 of it); and relaxing in the ramp as well (the default): the contacts start
//     the hold aged by the ramp (about C over its relative loading rate, ~0.2 lab s here), and the bed
//     loses less than a quarter of that early drop (measured 0.10 of it).
// Also: the loading curve stiffens and the hold is at constant strain (Fig. 4.4b shape), and the
// written recording and protocol files pass the format validator.
#include <cmath>

#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

int main() {
    bool ok = true;
    const std::vector<std::string> common = {"--material", "frictional", "--width", "4", "--fill_height", "5",
                                             "--steps", "ramp:5e-5:5000,hold:300", "--quiet", "--threads", "1"};
    double C = 0.0792, t0 = 0.2894;
    {
        OedometerRelaxation d;
        auto args = common;
        args.insert(args.end(), {"--relax_C", "0", "--name", "off"});
        ok &= check(oedometer_selftest::runDriver(d, args) == 0, "run without relaxation");
        ok &= check(d.holds().size() == 1, "one hold");
        if (d.holds().size() == 1) {
            const auto& h = d.holds()[0];
            double worst = 0;
            for (double s : h.s) worst = std::max(worst, std::abs(s / h.stressStart - 1));
            std::printf("     relaxation off: stress %.6g -> %.6g Pa, largest deviation %.3g %%, max Ek/Ep %.3g\n",
                        h.stressStart, h.stressEnd, 100 * worst, h.maxEkEp);
            const auto& r0 = d.recordingData();
            const int cs = r0.column("step"), ca = r0.column("axial_stress_Pa");
            double rampMax = 0;
            for (const auto& row : r0.rows)
                if (cs >= 0 && ca >= 0 && row[static_cast<std::size_t>(cs)] == 0) rampMax = std::max(rampMax, row[static_cast<std::size_t>(ca)]);
            std::printf("     ramp ends at %.6g Pa\n", rampMax);
            ok &= check(rampMax >= 5000, "the ramp reaches the target stress");
            ok &= check(std::abs(h.stressStart / 5000 - 1) <= 0.05, "hold starts within 5 % of the target stress");
            ok &= check(worst < 0.05, "stress constant within 5 % during the hold without relaxation (relaxing drop: ~40 %)");
            const auto& rec = d.recordingData();
            const int c = rec.column("Ek_over_Ep");
            ok &= check(c >= 0 && rec.rows.back()[static_cast<std::size_t>(c)] <= 1e-4, "quasi-static at the end (Ek/Ep <= 1e-4)");
        }
        recording::Recording back;
        ok &= check(recording::checkRecording(readWholeFile("off.recording.csv"), &back).empty(), "recording file valid");
        ok &= check(recording::readProtocol("off.protocol.json").steps.size() == 2, "protocol file valid, 2 steps");
    }
    {
        OedometerRelaxation d;
        auto args = common;
        args.insert(args.end(), {"--relax_C", "0.0792", "--relax_t0", "0.2894", "--name", "on"});
        ok &= check(oedometer_selftest::runDriver(d, args) == 0, "run with relaxation");
        if (d.holds().size() == 1) {
            const auto& h = d.holds()[0];
            const double drop = 1 - h.stressEnd / h.stressStart;
            const double predicted = 1 - std::pow(1 + h.labDuration / t0, -C);
            std::printf("     relaxation on: drop %.4g %% (contact level %.4g %%), fit C = %.4g, t0 = %.4g s, rms %.3g\n",
                        100 * drop, 100 * predicted, h.fit.C, h.fit.t0, h.fit.rms);
            ok &= check(drop > 0.5 * predicted, "stress decays by at least half the contact-level prediction");
            ok &= check(h.fit.ok && std::abs(h.fit.C - C) < 0.3 * C, "fitted macroscopic C within 30 % of the contact C");
            ok &= check(h.fit.rms < 0.02, "Eq. 4.3 describes the hold curve (rms < 0.02)");
            const double above = h.samples > 0 ? double(h.samplesAbove) / double(h.samples) : 1.0;
            const double holdDem = 0.02 * std::log1p(h.labDuration / t0);  // log clock, hold_tau 0.02 s
            std::printf("     max Ek/Ep during the hold %.3g, %.3g %% of %ld clock-running samples above 1e-4, "
                        "%ld clock pauses (%ld ended by hold_settle_max) costing %.3g DEM s (hold %.3g DEM s)\n",
                        h.maxEkEp, 100 * above, h.samples, h.pauses, h.forcedResumes, h.pauseDem, holdDem);
            // Rearrangement events (a force chain giving way as contacts relax, a rattler dropping
            // through a pore) are instantaneous in lab time: the clock pauses while they last.
            ok &= check(h.samples > 100 && above <= 0.05, "quasi-static while the lab clock runs (Ek/Ep <= 1e-4 in >= 95 % of samples)");
            ok &= check(h.pauseDem < holdDem, "clock pauses cost less DEM time than the hold");
            // Fig. 4.4b shape: the loading curve stiffens (stress at half the ramp's strain well below
            // half its final stress; 0.01-0.10 of it measured on three seeds), and the hold is a
            // vertical drop at constant strain.
            const auto& rec = d.recordingData();
            const int cs = rec.column("step"), ce = rec.column("axial_strain"), ca = rec.column("axial_stress_Pa");
            double eEnd = 0, sEnd = 0, sHalf = 0;
            for (const auto& row : rec.rows)
                if (row[static_cast<std::size_t>(cs)] == 0) eEnd = row[static_cast<std::size_t>(ce)], sEnd = row[static_cast<std::size_t>(ca)];
            for (const auto& row : rec.rows)
                if (row[static_cast<std::size_t>(cs)] == 0 && row[static_cast<std::size_t>(ce)] <= 0.5 * eEnd) sHalf = row[static_cast<std::size_t>(ca)];
            std::printf("     ramp: stress %.4g Pa at half of the final strain %.4g (final stress %.4g Pa)\n", sHalf, eEnd, sEnd);
            ok &= check(eEnd > 0 && sHalf < 0.4 * sEnd, "the loading curve stiffens (stress at half the strain < 0.4 of the final)");
            ok &= check(h.strainEnd == h.strainStart, "the hold is at constant strain");
        } else {
            ok &= check(false, "one hold");
        }
    }
    {
        const double Cs = 0.0206, t0s = 2e-4;
        double early[2] = {-1, -1};  // bed's loss at t = 10 t0 over the contact law's, relax_in_ramps 0 / 1
        for (int inRamps = 0; inRamps < 2; ++inRamps) {
            OedometerRelaxation d;
            auto args = common;
            for (std::size_t k = 0; k + 1 < args.size(); ++k)
                if (args[k] == "--steps") args[k + 1] = "ramp:5e-5:5000,hold:1";
            args.insert(args.end(), {"--relax_C", "0.0206", "--relax_t0", "2e-4", "--relax_in_ramps",
                                     inRamps ? "1" : "0", "--name", inRamps ? "short_t0_ramps" : "short_t0"});
            ok &= check(oedometer_selftest::runDriver(d, args) == 0, "run with a short response time");
            const auto& rec = d.recordingData();
            const int cs = rec.column("step"), ct = rec.column("time_s"), ca = rec.column("axial_stress_Pa");
            double tStart = -1, sStart = 0;
            for (const auto& row : rec.rows) {
                if (row[static_cast<std::size_t>(cs)] != 1) continue;
                const double t = row[static_cast<std::size_t>(ct)], sv = row[static_cast<std::size_t>(ca)];
                if (tStart < 0) tStart = t, sStart = sv;
                if (t - tStart >= 10 * t0s) {
                    early[inRamps] = (1 - sv / sStart) / (1 - std::pow(11.0, -Cs));
                    break;
                }
            }
        }
        std::printf("     t0 = 0.2 ms: bed loss at t = 10 t0 over the contact law's: %.3g (holds only), %.3g (ramps too)\n", early[0], early[1]);
        ok &= check(early[0] >= 0.5, "relaxing in the holds only, the bed loses >= half the contact-level drop by t = 10 t0");
        ok &= check(early[1] >= -1 && early[1] < 0.25, "relaxing in the ramps too, the ramp-aged contacts lose < a quarter of it by t = 10 t0");
    }
    return ok ? 0 : 1;
}
