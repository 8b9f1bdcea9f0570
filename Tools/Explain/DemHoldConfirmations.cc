#include "DemRuns.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "Recording.h"


namespace pdpm::explain::dem {

DemResult confirmRelaxation(DemContext& ctx, const MechanismResult& relax, const Recording& rec, const std::string& protocolPath) {
    DemResult& d = ctx.d;
    d.mechanism = "contact_relaxation";
    double C = -1, t0 = -1;
    for (std::size_t q = 0; q < relax.params.size(); ++q) {
        if (relax.params[q] == pRelaxC) C = relax.value[q];
        if (relax.params[q] == pRelaxT0) t0 = relax.value[q];
    }
    if (!(C > 0) || !(t0 > 0)) return ctx.fail("the accepted contact_relaxation term has no positive C and t0");

    // lab holds, alternately calibration and held-out
    const std::vector<LabHold> lab = labHolds(rec);
    std::vector<std::size_t> cal, held;
    for (std::size_t k = 0; k < lab.size(); ++k) (k % 2 == 0 ? cal : held).push_back(k);
    if (held.empty()) {
        d.status = "not_run";
        d.reason = "the recording has fewer than two holds: no held-out hold to score the DEM re-run on";
        return ctx.finish();
    }
    d.calibrationHolds = static_cast<int>(cal.size());
    d.heldoutHolds = static_cast<int>(held.size());

    // Whether the contacts also relax while a ramp loads them is decided by run a, like C: relaxing in
    // the ramps, a contact the ramp loads more slowly than it relaxes stops restarting its clock and
    // reaches the hold aged, by about C over the ramp's relative loading rate (seconds at the thesis'
    // ramps). A hold of aged contacts relaxes on their time scale, not on t0: when the Eq. 4.3 fits of
    // run a's calibration holds give a t0 more than kRampAgedT0Ratio times the surrogate's (the lab
    // holds', from the stop), run b lets the contacts relax in the holds only, so that every contact
    // the ramp loaded starts the hold at clock 0 (the thesis' limestone, t0 0.2 ms: run a's holds fit
    // t0 = 0.1-0.35 s). Otherwise run b relaxes in the ramps too, as run a (cocoa, t0 0.18 s: run a's
    // holds 0.20-0.23 s), which also makes the later holds relax less, as the cocoa records do.
    auto runDem = [&](const std::string& name, double relaxC, bool inRamps) -> std::vector<DemHold> {
        DemRun run;
        run.name = name;
        run.relaxC = relaxC;
        run.relaxT0 = t0;
        run.relaxInRamps = inRamps;
        const std::string args = " --relax_C " + fmt(relaxC) + " --relax_t0 " + fmt(t0) + (inRamps ? "" : " --relax_in_ramps 0");
        if (!ctx.run(run, protocolPath, args)) return {};
        try {
            return readDemHolds(ctx.workDir + "/" + name);
        } catch (const InputError&) {
            return {};  // an unreadable DEM record: the run counts as failed
        }
    };
    auto macroC = [&](const std::vector<DemHold>& run) {  // mean fitted C of the DEM calibration holds (-1: none)
        double sum = 0;
        int n = 0;
        for (std::size_t k : cal)
            if (run[k].fitC > 0) sum += run[k].fitC, ++n;
        return n > 0 ? sum / n : -1.0;
    };
    const std::vector<DemHold> base = runDem("dem_baseline", 0, true);
    if (base.size() < lab.size()) return ctx.fail("baseline DEM run failed or has fewer holds than the recording (log: dem_baseline.log)");
    const std::vector<DemHold> augA = runDem("dem_relax_a", C, true);
    if (augA.size() < lab.size()) return ctx.fail("augmented DEM run failed (log: dem_relax_a.log)");
    const double macroA = macroC(augA) > 0 ? macroC(augA) : C;
    std::vector<double> t0s;  // run a's fitted hold t0 over the contact t0, calibration holds
    for (std::size_t k : cal)
        if (augA[k].fitT0 > 0) t0s.push_back(augA[k].fitT0 / t0);
    if (!t0s.empty()) {
        std::sort(t0s.begin(), t0s.end());
        const std::size_t m = t0s.size() / 2;
        d.rampAgedT0Ratio = t0s.size() % 2 ? t0s[m] : 0.5 * (t0s[m - 1] + t0s[m]);
    }
    const bool inRampsB = !(d.rampAgedT0Ratio > kRampAgedT0Ratio);
    // the second C brings the bed's macroscopic C (a fraction of the contacts') to the surrogate's
    const double C2 = C * C / macroA;
    const std::vector<DemHold> augB = runDem("dem_relax_b", C2, inRampsB);
    if (augB.size() < lab.size()) return ctx.fail("augmented DEM run failed (log: dem_relax_b.log)");

    const std::vector<const std::vector<DemHold>*> all = {&base, &augA, &augB};
    for (std::size_t q = 0; q < all.size(); ++q) {
        d.runs[q].calibrationRmse = holdRmse(lab, *all[q], cal);
        d.runs[q].heldoutRmse = holdRmse(lab, *all[q], held);
        if (q > 0) d.runs[q].macro = q == 1 ? macroA : macroC(*all[q]);
    }
    d.chosen = d.runs[2].calibrationRmse < d.runs[1].calibrationRmse ? 2 : 1;
    ctx.scoreChosen();
    writeHoldComparison(ctx, lab, all);
    return ctx.finish();
}

namespace {
/// Mean stress drop of the holds in `which` over the last third of each lab hold, a fraction of the
/// stress at the stop: the lab's own (dem null) or the DEM's prediction of it.
double holdDrop(const std::vector<LabHold>& lab, const std::vector<DemHold>* dem, const std::vector<std::size_t>& which) {
    double sum = 0;
    int n = 0;
    for (std::size_t k : which) {
        const LabHold& h = lab[k];
        if (!(h.s0 > 0) || h.t.size() < 3) continue;
        double m = 0;
        std::size_t c = 0;
        for (std::size_t i = 2 * h.t.size() / 3; i < h.t.size(); ++i, ++c) m += dem ? interpolate((*dem)[k], h.t[i]) : h.s[i] / h.s0;
        sum += 1 - m / static_cast<double>(c);
        ++n;
    }
    return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}
} // namespace

/// rate_dependence: the contact viscous time (--contact_viscous_time) calibrated on the lab holds
/// (DemConfirmation.h).
DemResult confirmRate(DemContext& ctx, const MechanismResult& rate, const Recording& rec, const std::string& protocolPath) {
    DemResult& d = ctx.d;
    d.mechanism = "rate_dependence";
    double tauMacro = -1;
    for (std::size_t q = 0; q < rate.params.size(); ++q)
        if (rate.params[q] == pTauV) tauMacro = rate.value[q];
    if (!(tauMacro > 0)) return ctx.fail("the accepted rate_dependence term has no positive tau_v");
    const std::vector<LabHold> lab = labHolds(rec, true);
    std::vector<std::size_t> cal, held;
    for (std::size_t k = 0; k < lab.size(); ++k) (k % 2 == 0 ? cal : held).push_back(k);
    if (held.empty()) {
        d.status = "not_run";
        d.reason = "the recording has fewer than two holds: the viscous stress shows where a hold stops the piston, and there is "
                   "no held-out hold to score the DEM re-run on";
        return ctx.finish();
    }
    d.calibrationHolds = static_cast<int>(cal.size());
    d.heldoutHolds = static_cast<int>(held.size());
    const std::vector<RateChange> labChanges = speedChanges(rec.t, rec.strain, rec.stress);
    d.rateChanges = static_cast<int>(labChanges.size());
    d.labRateStep = meanRateStep(labChanges);
    d.labMacro = holdDrop(lab, nullptr, cal);

    const auto clampTau = [](double tau) { return std::clamp(tau, 1e-3, kMaxContactViscousTime); };
    auto runDem = [&](const std::string& name, double tau) -> std::vector<DemHold> {
        DemRun run;
        run.name = name;
        run.viscTime = tau;
        if (!ctx.run(run, protocolPath, " --relax_C 0 --contact_viscous_time " + fmt(tau))) return {};
        try {
            std::vector<double> t, e, s;
            readDemSeries(ctx.workDir + "/" + name, t, e, s);
            d.runs.back().rateStep = meanRateStep(speedChanges(t, e, s));
            return readDemHolds(ctx.workDir + "/" + name);
        } catch (const InputError&) {
            return {};  // an unreadable DEM record: the run counts as failed
        }
    };
    const std::vector<DemHold> base = runDem("dem_baseline", 0);
    if (base.size() < lab.size()) return ctx.fail("baseline DEM run failed or has fewer holds than the recording (log: dem_baseline.log)");
    const double tauA = clampTau(tauMacro / kRateMacroOverContact);
    const std::vector<DemHold> augA = runDem("dem_viscous_a", tauA);
    if (augA.size() < lab.size()) return ctx.fail("augmented DEM run failed (log: dem_viscous_a.log)");
    std::vector<const std::vector<DemHold>*> all = {&base, &augA};
    // the secant of the hold drop through the baseline and run a, aimed at the recording's (the drop
    // grows about in proportion to the viscous time); no second run when it does not grow, or when the
    // recording's holds lose no more than the baseline's
    const double drop0 = holdDrop(lab, &base, cal), dropA = holdDrop(lab, &augA, cal);
    std::vector<DemHold> augB;
    if (dropA > drop0 && d.labMacro > drop0) {
        const double tauB = clampTau(tauA * (d.labMacro - drop0) / (dropA - drop0));
        if (std::abs(tauB / tauA - 1) > 0.05) {
            augB = runDem("dem_viscous_b", tauB);
            if (augB.size() < lab.size()) return ctx.fail("augmented DEM run failed (log: dem_viscous_b.log)");
            all.push_back(&augB);
        }
    }
    for (std::size_t q = 0; q < all.size(); ++q) {
        d.runs[q].calibrationRmse = holdRmse(lab, *all[q], cal);
        d.runs[q].heldoutRmse = holdRmse(lab, *all[q], held);
        d.runs[q].macro = holdDrop(lab, all[q], cal);
    }
    d.chosen = all.size() > 2 && d.runs[2].calibrationRmse < d.runs[1].calibrationRmse ? 2 : 1;
    ctx.scoreChosen();
    writeHoldComparison(ctx, lab, all);
    return ctx.finish();
}

} // namespace pdpm::explain::dem

namespace pdpm::explain {

std::vector<RateChange> speedChanges(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s) {
    std::vector<RateChange> out;
    constexpr std::size_t kMinSide = 8;
    for (const PhaseSegment& seg : detectPhases(t, e)) {
        if (seg.phase != Phase::Load && seg.phase != Phase::Reload) continue;
        const std::size_t b = seg.begin, n = seg.end - seg.begin;
        if (n < 2 * kMinSide) continue;
        // prefix sums of 1, t, e, t^2, t e, e^2 for the squared error of a straight line over any range
        std::vector<double> S1(n + 1), St(n + 1), Se(n + 1), Stt(n + 1), Ste(n + 1), See(n + 1);
        const double t0 = t[b], e0 = e[b];
        for (std::size_t i = 0; i < n; ++i) {
            const double x = t[b + i] - t0, y = e[b + i] - e0;
            S1[i + 1] = S1[i] + 1, St[i + 1] = St[i] + x, Se[i + 1] = Se[i] + y;
            Stt[i + 1] = Stt[i] + x * x, Ste[i + 1] = Ste[i] + x * y, See[i + 1] = See[i] + y * y;
        }
        // squared error, slope and intercept (at t0) of the least-squares line over samples [i, j)
        const auto line = [&](std::size_t i, std::size_t j, double& slope, double& icept) {
            const double m = S1[j] - S1[i], sx = St[j] - St[i], sy = Se[j] - Se[i];
            const double sxx = Stt[j] - Stt[i] - sx * sx / m, sxy = Ste[j] - Ste[i] - sx * sy / m, syy = See[j] - See[i] - sy * sy / m;
            slope = sxx > 0 ? sxy / sxx : 0;
            icept = (sy - slope * sx) / m;
            return std::max(0.0, syy - (sxx > 0 ? sxy * sxy / sxx : 0));
        };
        double best = std::numeric_limits<double>::infinity();
        std::size_t split = 0;
        for (std::size_t c = kMinSide; c + kMinSide <= n; ++c) {
            double a, ai, r, ri;
            const double err = line(0, c, a, ai) + line(c, n, r, ri);
            if (err < best) best = err, split = c;
        }
        double rateL, iL, rateR, iR;
        line(0, split, rateL, iL);
        line(split, n, rateR, iR);
        if (!(rateL > 0) || !(rateR > 0) || std::max(rateL / rateR, rateR / rateL) < kRateChangeFactor) continue;
        // where the two pieces meet: the time and strain of the change
        const double tx = (iR - iL) / (rateL - rateR), ec = e0 + iL + rateL * tx;
        // the stress step at the change: straight lines of stress against strain on each side, over the
        // last 40 % of the samples before it and from an eighth to a half of those after it (the stress
        // a viscosity adds builds up over the first samples after a speed-up), at the strain where the
        // two pieces of strain against time meet
        const std::size_t c = b + split, nR = n - split;
        const auto fitAt = [&](std::size_t i0, std::size_t i1) {  // the fitted stress at ec of samples [i0, i1)
            double m = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
            for (std::size_t i = i0; i < i1; ++i) {
                const double x = e[i] - ec;
                m += 1, sx += x, sy += s[i], sxx += x * x, sxy += x * s[i];
            }
            const double den = m * sxx - sx * sx;
            return den > 0 ? (sy * sxx - sx * sxy) / den : std::numeric_limits<double>::quiet_NaN();  // the intercept at x = 0
        };
        const double L = fitAt(c - std::max<std::size_t>(4, 2 * split / 5), c), R = fitAt(c + nR / 8, c + std::max<std::size_t>(nR / 8 + 4, nR / 2));
        if (!std::isfinite(L) || !std::isfinite(R) || !(L > 0)) continue;
        RateChange rc;
        rc.index = c;
        rc.time = t0 + tx;
        rc.rateRatio = rateR / rateL;
        rc.step = (rc.rateRatio > 1 ? 1 : -1) * (R - L) / L;
        out.push_back(rc);
    }
    return out;
}

double meanRateStep(const std::vector<RateChange>& changes) {
    if (changes.empty()) return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    for (const RateChange& c : changes) sum += c.step;
    return sum / static_cast<double>(changes.size());
}

} // namespace pdpm::explain
