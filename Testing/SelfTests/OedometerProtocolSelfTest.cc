// OedometerRelaxation protocol steps other than ramp + hold, on small beds:
//  1. Load - unload - reload - creep (laterally periodic, frictional, relaxation on):
//     the unload ends at its target stress with the piston moved back up but a residual strain left;
//     the reload reaches its target again; during the creep step (constant applied stress) the stress
//     stays within 3 % of the creep stress while the strain grows (relaxing contacts creep).
//  2. Restart: the same protocol stopped half-way (--time_max) and resumed from RUN.restart writes a
//     recording byte-identical to the straight run's; its half-way restart file with a driver key
//     edited into an impossible value (resealed) is refused with exit code 2.
//  3. Cylindrical mould with wall friction: the mould wall carries part of the load (bottom stress
//     below piston stress plus the bed's weight) but no more than Janssen's fully mobilised share,
//     and the lateral stress on the mould is positive and below the axial stress.
#include <cmath>
#include <numbers>

#include "IO/AtomicFile.h"
#include "IO/RestartSeal.h"
#include "OedometerSelfTestCommon.h"

using namespace pdpm;
using oedometer_selftest::check;

namespace {

double columnAt(const recording::Recording& rec, const std::string& name, std::size_t row) {
    const int c = rec.column(name);
    return c < 0 ? std::nan("") : rec.rows[row][static_cast<std::size_t>(c)];
}

/// Last row of protocol step `step` (-1 if none).
long lastRowOfStep(const recording::Recording& rec, int step) {
    long last = -1;
    for (std::size_t r = 0; r < rec.rows.size(); ++r)
        if (static_cast<int>(columnAt(rec, "step", r)) == step) last = static_cast<long>(r);
    return last;
}

} // namespace

int main() {
    bool ok = true;
    const std::vector<std::string> common = {"--material", "frictional", "--width", "4", "--fill_height", "5",
                                             "--steps", "ramp:5e-5:4000,unload:5e-5:1000,ramp:5e-5:4000,creep:200",
                                             "--relax_C", "0.0792", "--relax_t0", "0.2894", "--quiet", "--threads", "1"};
    double demEnd = 0;
    // Beds too large to be made, and an output interval below the clock's resolution: one error line
    // (exit code 2) or a normal run, never a crash (the particle count was cast from a double beyond
    // size_t) or an endless loop (the next output time never moved).
    for (const char* huge : {"--width", "--fill_height"}) {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {huge, "1e10", "--quiet", "--threads", "1"}) == 2,
                    std::string(huge) + " 1e10 is refused (exit code 2)");
    }
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--d_mean", "1e300", "--quiet", "--threads", "1"}) == 2,
                    "--d_mean 1e300 is refused (exit code 2)");
    }
    {
        // a piston that moves 16 % of a grain per step: one error line before the loop (before: it
        // ran with exit code 0; 1e300 printed a warning line, then NaN)
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--width", "3", "--fill_height", "2", "--ramp_rate", "1e5", "--time_max", "2e-4",
                                                      "--quiet", "--threads", "1", "--name", "fast_ramp"}) == 2,
                    "--ramp_rate 1e5 is refused (exit code 2)");
        OedometerRelaxation e;
        ok &= check(oedometer_selftest::runDriver(e, {"--width", "3", "--fill_height", "2", "--ramp_rate", "50", "--time_max", "2e-4",
                                                      "--quiet", "--threads", "1", "--name", "fast_ramp_ok"}) == 0,
                    "--ramp_rate 50 (100 times the default) runs");
    }
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--width", "3", "--fill_height", "2", "--save_every", "1e-300", "--time_max", "2e-4",
                                                      "--name", "tiny_interval", "--restart_output", "1", "--quiet", "--threads", "1"}) == 0,
                    "--save_every 1e-300 runs (an output every step)");
        OedometerRelaxation e;  // and its own restart file reads back
        ok &= check(oedometer_selftest::runDriver(e, {"--restart", "tiny_interval.restart", "--name", "tiny_interval", "--time_max", "3e-4",
                                                      "--quiet", "--threads", "1"}) == 0,
                    "the --save_every 1e-300 run resumes from its restart file");
    }
    {
        OedometerRelaxation d;
        auto args = common;
        args.insert(args.end(), {"--name", "cycle", "--restart_output", "1"});
        ok &= check(oedometer_selftest::runDriver(d, args) == 0, "load-unload-reload-creep run");
        const auto& rec = d.recordingData();
        const long r0 = lastRowOfStep(rec, 0), r1 = lastRowOfStep(rec, 1), r2 = lastRowOfStep(rec, 2);
        ok &= check(r0 >= 0 && r1 > r0 && r2 > r1, "all four steps recorded");
        if (r0 >= 0 && r1 > r0 && r2 > r1) {
            const double e0 = columnAt(rec, "axial_strain", r0), e1 = columnAt(rec, "axial_strain", r1);
            const double s1 = columnAt(rec, "axial_stress_Pa", r1), s2 = columnAt(rec, "axial_stress_Pa", r2);
            std::printf("     peak strain %.4g, after unload %.4g at %.4g Pa, reload %.4g Pa\n", e0, e1, s1, s2);
            ok &= check(s1 <= 1000 && s1 > 0, "unload ends at its target stress (<= 1 kPa, still in contact)");
            ok &= check(e1 < e0, "the piston moved back up during the unload");
            ok &= check(e1 > 0.2 * e0, "a residual strain remains after unloading");
            ok &= check(s2 >= 4000, "the reload reaches its target");
        }
        ok &= check(d.holds().size() == 1 && d.holds()[0].creep, "one creep step");
        if (d.holds().size() == 1) {
            const auto& h = d.holds()[0];
            double worst = 0;
            // after the first 10 % of the step (the stress controller settles)
            for (std::size_t k = 0; k < h.t.size(); ++k)
                if (h.t[k] - h.labStart > 0.1 * h.labDuration) worst = std::max(worst, std::abs(h.s[k] / h.stressStart - 1));
            std::printf("     creep: stress %.6g -> %.6g Pa (largest deviation %.3g %%), strain %.6g -> %.6g\n",
                        h.stressStart, h.stressEnd, 100 * worst, h.strainStart, h.strainEnd);
            ok &= check(worst < 0.03, "creep holds the stress within 3 %");
            ok &= check(h.strainEnd > h.strainStart, "the bed creeps (strain grows at constant stress)");
        }
        demEnd = d.time();
    }
    {
        // Stop half-way (DEM time), then resume from the restart file.
        OedometerRelaxation a;
        auto args = common;
        args.insert(args.end(), {"--name", "part", "--restart_output", "1", "--time_max", fmt(0.5 * demEnd)});
        ok &= check(oedometer_selftest::runDriver(a, args) == 0, "first half");
        const std::string half = readWholeFile("part.restart");
        // the machine's state edited into values no run can have (file resealed, so the checksum
        // passes): refused with exit code 2 before anything runs
        const std::string bottomWall = restartValue(half, "bottomWall");
        ok &= check(!bottomWall.empty(), "part.restart holds bottomWall");
        // pistonZ 1 % above where the piston wall is (ran to the end before, the piston jumping)
        const std::string pistonZ = restartValue(half, "pistonZ");
        ok &= check(!pistonZ.empty(), "part.restart holds pistonZ");
        const std::string pistonOff = pistonZ.empty() ? "1" : fmt(1.01 * std::stod(pistonZ));
        const std::pair<std::string, std::string> edits[] = {
            {"stepIndex", "0.5"}, {"settling", "2"}, {"pistonWall", bottomWall}, {"recRow", "1"}, {"labScale", "-1"},
            {"pistonZ", pistonOff}, {"labTime", "1e300"}};  // labTime: far beyond the protocol (ran before)
        for (const auto& [key, bad] : edits) {
            const std::string edited = withRestartValue(half, key, bad);
            ok &= check(!edited.empty(), "part.restart holds " + key);
            if (edited.empty()) continue;
            writeWholeFile("edited.restart", edited);
            OedometerRelaxation e;
            // (--time_max beyond the file's: else the stored one, reached, refuses every edit alike)
            ok &= check(oedometer_selftest::runDriver(e, {"--restart", "edited.restart", "--name", "edited", "--quiet", "--time_max", "1e30"}) == 2,
                        "a restart with " + key + " '" + bad + "' is refused (exit code 2)");
        }
        {
            // a key of the driver state renamed (the section's line count still holds): the missing
            // field is refused, not left at the value the driver's set-up gave it
            std::string renamed = half;
            const std::size_t at = renamed.find("\nlabTime ");
            ok &= check(at != std::string::npos, "part.restart holds labTime");
            if (at != std::string::npos) {
                renamed.replace(at, 9, "\nlabClock ");
                writeWholeFile("renamed.restart", resealRestartText(renamed));
                OedometerRelaxation e;
                ok &= check(oedometer_selftest::runDriver(e, {"--restart", "renamed.restart", "--name", "renamed", "--quiet", "--time_max", "1e30"}) == 2,
                            "a restart without labTime is refused (exit code 2)");
            }
        }
        OedometerRelaxation b;
        ok &= check(oedometer_selftest::runDriver(b, {"--restart", "part.restart", "--name", "part", "--time_max", "1e30", "--quiet"}) == 0,
                    "resumed from part.restart");
        const std::string straight = readWholeFile("cycle.recording.csv"), resumed = readWholeFile("part.recording.csv");
        ok &= check(!straight.empty() && straight == resumed, "restarted recording is byte-identical to the straight run's");
    }
    {
        OedometerRelaxation d;
        ok &= check(oedometer_selftest::runDriver(d, {"--geometry", "cylinder", "--diameter", "0.02", "--fill_height_m", "0.015",
                                                      "--wall_friction", "0.5", "--material", "frictional", "--relax_C", "0",
                                                      "--steps", "ramp:5e-5:3000,hold:10", "--name", "mould", "--quiet",
                                                      "--threads", "1"}) == 0,
                    "cylindrical mould run");
        const auto& rec = d.recordingData();
        const long r = lastRowOfStep(rec, 0);
        if (r >= 0) {
            const double top = columnAt(rec, "axial_stress_Pa", r), bottom = columnAt(rec, "bottom_stress_Pa", r);
            const double lateral = columnAt(rec, "lateral_stress_Pa", r), h = columnAt(rec, "piston_position_m", r);
            const double D = 0.02, A = 0.25 * std::numbers::pi * D * D;
            double weight = 0;
            for (double m : d.particles().m) weight += 9.81 * m;
            // Load balance: piston + weight = bottom + mould friction. The mould's share cannot exceed
            // Janssen's fully mobilised value 1 - exp(-4 mu_w K h / D) with K = lateral / axial.
            const double load = top + weight / A, share = 1 - bottom / load;
            const double janssen = 1 - std::exp(-4 * 0.5 * (lateral / top) * h / D);
            std::printf("     mould: piston %.5g Pa, bottom %.5g Pa, weight %.4g Pa, lateral %.5g Pa (K = %.3g); mould carries "
                        "%.3g %% of the load (Janssen limit %.3g %%)\n",
                        top, bottom, weight / A, lateral, lateral / top, 100 * share, 100 * janssen);
            ok &= check(share > 0.03, "wall friction: the mould carries part of the load (bottom < piston + weight)");
            ok &= check(share < janssen, "the mould's share stays below Janssen's fully mobilised limit");
            ok &= check(lateral > 0 && lateral < top, "lateral stress positive and below the axial stress");
        } else {
            ok &= check(false, "ramp recorded");
        }
    }
    return ok ? 0 : 1;
}
