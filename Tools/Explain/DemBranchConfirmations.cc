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
#include <random>
#include <sstream>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "Recording.h"


namespace pdpm::explain::dem {

namespace {

/// The branch confirmations' split of the lab branches: the unloads calibrate, the reloads after them
/// are held out. False (status not_run, with the reason) when either is missing.
bool splitBranches(DemResult& d, const std::vector<Branch>& lab, std::vector<std::size_t>& cal, std::vector<std::size_t>& held) {
    for (std::size_t k = 0; k < lab.size(); ++k) (lab[k].phase == Phase::Unload ? cal : held).push_back(k);
    if (cal.empty() || held.empty()) {
        d.status = "not_run";
        d.reason = "the recording needs an unload (calibration) and a reload after it (held out) with a loading before them; it has " +
                   std::to_string(cal.size()) + " usable unload and " + std::to_string(held.size()) + " reload branch(es)";
        return false;
    }
    d.calibrationHolds = static_cast<int>(cal.size());
    d.heldoutHolds = static_cast<int>(held.size());
    return true;
}

/// The protocol's stresses brought into the material's range (at most kDemMaxStress; the comparison
/// is in units of each branch's start stress): sets d.stressScale and returns the protocol's largest
/// target stress (Pa), or sets the status (failed: no protocol; not_run: no stress targets) and
/// returns 0.
double scaleProtocolStress(DemContext& ctx) {
    DemResult& d = ctx.d;
    if (!ctx.protocol) {
        ctx.fail("protocol: " + ctx.protocolError);
        return 0;
    }
    double maxTarget = 0;
    for (const recording::Step& st : ctx.protocol->steps) maxTarget = std::max(maxTarget, st.targetStress);
    if (!(maxTarget > 0)) {  // a protocol without stress targets (the import knew only the strain path)
        d.status = "not_run";
        d.reason = "the protocol's steps have no target stress, and the DEM driver replays a protocol by its stress targets";
        return 0;
    }
    d.stressScale = maxTarget > kDemMaxStress ? kDemMaxStress / maxTarget : 1.0;
    return maxTarget;
}

/// dem/comparison.csv (and .png) of a branch confirmation: every lab branch sample, the reloads held out
/// (predicted by `heldoutJudge`, the one their error is scored with).
void writeBranchComparison(const DemContext& ctx, const std::vector<Branch>& lab, const std::vector<std::vector<Branch>>& all,
                           BranchJudge heldoutJudge = BranchJudge::Stress) {
    std::vector<Compared> rows;
    for (std::size_t k = 0; k < lab.size(); ++k) {
        std::vector<std::vector<double>> pred;
        const BranchJudge judge = lab[k].phase == Phase::Reload ? heldoutJudge : BranchJudge::Stress;
        for (const auto& run : all) pred.push_back(branchPredict(lab, run, k, judge));
        for (std::size_t i = 0; i < lab[k].u.size(); ++i) {
            Compared c{k, lab[k].phase == Phase::Reload, lab[k].e[i], lab[k].s[i], {}};
            for (const auto& p : pred) c.pred.push_back(p[i]);
            rows.push_back(std::move(c));
        }
    }
    writeComparison(ctx.workDir, rows, ctx.d, "axial_strain", "axial strain", ctx.opt.figures);
}

/// How a branch confirmation calibrates its knob.
enum class Calibration {
    UnloadRatio,   ///< secant on the unloading ratio (over the unload samples with y >= yMin)
    Grid,          ///< one run at guess * each grid factor, the smallest calibration error chosen
    Transmission,  ///< secant on ln(bottom/piston) of the first loading, the closest run chosen
};

/// The ingredient a branch confirmation calibrates: a driver flag whose value `base` is the baseline
/// (no effect); in UnloadRatio mode it must make the unloading ratio grow, in Transmission mode the
/// bottom/piston stress transmission fall.
struct BranchKnob {
    std::string mechanism, flag, prefix;  ///< report name, driver flag, run-name prefix
    double base = 0, lo = 0, hi = 0;      ///< baseline value and the range of the augmented runs
    double guess = 0;                     ///< first augmented run (clamped to [lo, hi])
    std::string args;                     ///< fixed arguments of every run
    double DemRun::* field = nullptr;     ///< where a run keeps the knob's value
    double yMin = 0.2;                    ///< the unloading ratio uses the unload samples with y >= yMin
    Calibration calibration = Calibration::UnloadRatio;
    std::vector<double> grid = {};        ///< Grid: the factors of the guess
    /// Transmission: the mould's H/D over the recording's (Janssen's exponent scales with H/D)
    double aspectScale = 1;
    std::string flag2 = {};               ///< a second driver flag given the same value (cohesion: the walls' adhesion)
    bool tension = false;                 ///< report the largest tension over the start stress instead of the unloading ratio
};

/// Largest tension over the branch's start stress, -min(y), on the unload branches in `which` (a lift-off
/// test's unload ends at its largest tension); 0 without tension.
double tensionRatio(const std::vector<Branch>& b, const std::vector<std::size_t>& which) {
    double t = 0;
    for (std::size_t k : which)
        if (k < b.size() && b[k].phase == Phase::Unload)
            for (double y : b[k].y) t = std::max(t, -y);
    return t;
}

const char* calibrationName(Calibration c) {
    switch (c) {
        case Calibration::UnloadRatio: return "unload_ratio_secant";
        case Calibration::Grid: return "unload_error_grid";
        default: return "bottom_over_piston_secant";
    }
}

/// plasticity and wall_friction: the unloads calibrate the knob (plasticity: secant on the unloading
/// ratio; wall_friction: the secant on the loading's bottom/piston transmission where the recording
/// has a bottom sensor, else a grid around the guess chosen by the unload error), the reloads after
/// them are held out (DemConfirmation.h).
DemResult confirmBranches(DemContext& ctx, const BranchKnob& knob, const Recording& rec, const std::string& protocolPath) {
    DemResult& d = ctx.d;
    d.mechanism = knob.mechanism;
    d.calibration = calibrationName(knob.calibration);
    // lab branches: the unloads calibrate, the reloads are held out
    const std::vector<Branch> lab = cycleBranches(rec.t, rec.strain, rec.stress, rec.bottom);
    std::vector<std::size_t> cal, held;
    if (!splitBranches(d, lab, cal, held)) return ctx.finish();
    d.ratioYMin = knob.yMin;
    const double labRatio = unloadRatio(lab, cal, knob.yMin);
    const bool byTransmission = knob.calibration == Calibration::Transmission;
    if (!(labRatio > 0) && !byTransmission && !knob.tension)  // the sensor's calibration and cohesion report it but do not need it
        return ctx.fail("no unloading stiffness could be measured on the calibration branches of the recording");
    if (byTransmission) {
        d.labTransmission = loadingTransmission(rec.t, rec.strain, rec.stress, rec.bottom).slope;
        if (!(d.labTransmission > 0)) return ctx.fail("the recording's bottom stress gives no bottom/piston ratio on its first loading");
    }

    // (Luding's law is piecewise linear in the overlap, so the stress level matters little)
    if (!(scaleProtocolStress(ctx) > 0)) return ctx.finish();

    auto runDem = [&](const std::string& name, double value) -> DemRecord {
        DemRun run;
        run.name = name;
        run.*knob.field = value;
        std::string args = knob.args + " " + knob.flag + " " + fmt(value) + " --stress_scale " + fmt(d.stressScale);
        if (!knob.flag2.empty()) args += " " + knob.flag2 + " " + fmt(value);
        if (!ctx.run(run, protocolPath, args)) return {};
        try {
            DemRecord r = readDemRecord(ctx.workDir + "/" + name);
            d.runs.back().transmission = r.transmission;
            return r;
        } catch (const InputError&) {
            return {};  // an unreadable DEM record: the run counts as failed
        }
    };
    const auto mismatch = [&](const std::string& name) {
        return ctx.fail("DEM run " + name + " failed or its unload/reload branches do not pair with the recording's " +
                        std::to_string(lab.size()) + " (same count, same phase in turn; log: " + name + ".log)");
    };
    std::vector<std::vector<Branch>> all;  // the baseline, then the augmented runs in turn
    std::vector<double> measured;          // each run's calibration quantity (unloading ratio or ln transmission)
    const auto runPaired = [&](const std::string& name, double value) {
        DemRecord r = runDem(name, value);
        all.push_back(std::move(r.branches));
        measured.push_back(byTransmission ? (r.transmission > 0 ? std::log(r.transmission) : std::numeric_limits<double>::quiet_NaN())
                                          : unloadRatio(all.back(), cal, knob.yMin));
        return samePhases(lab, all.back());
    };
    if (!runPaired("dem_baseline", knob.base)) return mismatch("dem_baseline");
    // the recording's value of the calibration quantity, for the DEM mould (the transmission's
    // excess loss over the frictionless DEM bed scaled by the ratio of the aspect ratios H/D)
    double target = labRatio;
    if (byTransmission) {
        const double q0 = measured[0];
        if (!std::isfinite(q0)) return ctx.fail("the frictionless DEM run recorded no bottom stress (log: dem_baseline.log)");
        if (std::log(d.labTransmission) > q0 - 0.01) {
            d.status = "contradicted";
            d.reason = "the recording's bottom/piston stress ratio on loading, " + fmt(d.labTransmission) +
                       ", is not below the frictionless DEM mould's " + fmt(std::exp(q0)) +
                       ": its bottom sensor shows no stress lost to the walls, so wall friction is not what the record shows";
            return ctx.finish();
        }
        target = q0 + (std::log(d.labTransmission) - q0) * knob.aspectScale;
        d.transmissionTarget = std::exp(target);
    }
    const double valueA = std::clamp(knob.guess, knob.lo, knob.hi);
    if (knob.calibration == Calibration::Grid) {
        // a fixed set of values around the guess, chosen by the calibration error alone (a value the
        // clamp to [lo, hi] makes equal to an earlier run's is not run twice)
        std::vector<double> used;
        for (double factor : knob.grid) {
            const double value = std::clamp(knob.guess * factor, knob.lo, knob.hi);
            if (std::find(used.begin(), used.end(), value) != used.end()) continue;
            used.push_back(value);
            const std::string name = knob.prefix + "_" + static_cast<char>('a' + used.size() - 1);
            if (!runPaired(name, value)) return mismatch(name);
        }
    } else {
        if (!runPaired(knob.prefix + "_a", valueA)) return mismatch(knob.prefix + "_a");
        // second run: the secant through (base, baseline's value) and (value of run a, its value)
        // aimed at the recording's
        const double q0 = measured[0], qA = measured[1];
        if (!std::isfinite(qA)) return ctx.fail("DEM run " + knob.prefix + "_a recorded no bottom stress (log: " + knob.prefix + "_a.log)");
        const bool moved = byTransmission ? qA < q0 - 1e-3 : qA > q0 + 1e-3;
        if (!moved) {
            const std::string what = byTransmission ? "bottom/piston stress ratio did not fall" : "unloading ratio did not grow";
            const double v0 = byTransmission ? std::exp(q0) : q0, vA = byTransmission ? std::exp(qA) : qA;
            return ctx.fail("the DEM bed's " + what + " with " + knob.flag.substr(2) + " (" + fmt(v0) + " at " + fmt(knob.base) + ", " +
                            fmt(vA) + " at " + fmt(valueA) + "): no calibration possible");
        }
        const double valueB = std::clamp(knob.base + (valueA - knob.base) * (target - q0) / (qA - q0), knob.lo, knob.hi);
        if (!runPaired(knob.prefix + "_b", valueB)) return mismatch(knob.prefix + "_b");
        // third run when neither hit the recording's value within 10 % of its distance from the
        // neutral value (unloading ratio: 1; transmission: the frictionless bed's), the quantity
        // not being linear in the knob: the secant through runs a and b
        const double qB = measured[2];
        const double tol = byTransmission ? 0.1 * std::max(std::abs(target - q0), 0.01) : 0.1 * std::max(labRatio - 1, 0.05);
        if (std::abs(qA - target) > tol && std::abs(qB - target) > tol && std::abs(qB - qA) > 1e-3 && valueB != valueA) {
            const double valueC = std::clamp(valueA + (valueB - valueA) * (target - qA) / (qB - qA), knob.lo, knob.hi);
            if (!runPaired(knob.prefix + "_c", valueC)) return mismatch(knob.prefix + "_c");
        }
    }

    for (std::size_t q = 0; q < all.size(); ++q) {
        d.runs[q].calibrationRmse = branchRmse(lab, all[q], cal);
        d.runs[q].heldoutRmse = branchRmse(lab, all[q], held);
        if (byTransmission) d.runs[q].heldoutBottomRmse = branchRmse(lab, all[q], held, BranchJudge::BottomStress);
        d.runs[q].macro = knob.tension ? tensionRatio(all[q], cal) : unloadRatio(all[q], cal, knob.yMin);
    }
    d.labMacro = knob.tension ? tensionRatio(lab, cal) : labRatio;
    // the augmented run with the smallest calibration error, or (transmission) the one whose
    // bottom/piston ratio is closest to the recording's
    d.chosen = 1;
    const auto better = [&](std::size_t q, std::size_t c) {
        return byTransmission ? std::abs(measured[q] - target) < std::abs(measured[c] - target)
                              : d.runs[q].calibrationRmse < d.runs[c].calibrationRmse;
    };
    for (std::size_t q = 2; q < d.runs.size(); ++q)
        if (better(q, static_cast<std::size_t>(d.chosen))) d.chosen = static_cast<int>(q);
    ctx.scoreChosen();
    d.heldoutBottomBaseline = d.runs[0].heldoutBottomRmse;
    d.heldoutBottomAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutBottomRmse;
    writeBranchComparison(ctx, lab, all);
    return ctx.finish();
}

} // namespace

DemResult confirmPlasticity(DemContext& ctx, const MechanismResult& plast, const Recording& rec, const std::string& protocolPath) {
    double lam = -1;
    for (std::size_t q = 0; q < plast.params.size(); ++q)
        if (plast.params[q] == pLambda) lam = plast.value[q];
    ctx.d.mechanism = "plasticity";
    if (!(lam > 1)) return ctx.fail("the accepted plasticity term has no unloading stiffness ratio above 1");
    const BranchKnob knob{"plasticity", "--k_over_k1", "dem_plastic", 1, 1.05, kMaxKOverK1, lam, " --relax_C 0 --kc_over_k 0", &DemRun::kOverK1, 0.2};
    return confirmBranches(ctx, knob, rec, protocolPath);
}

DemResult confirmWallFriction(DemContext& ctx, const MechanismResult& wall, const Recording& rec, const std::string& protocolPath) {
    ctx.d.mechanism = "wall_friction";
    double muK = -1;
    for (std::size_t q = 0; q < wall.params.size(); ++q)
        if (wall.params[q] == pMuK) muK = wall.value[q];
    if (!(muK > 0)) return ctx.fail("the accepted wall_friction term has no positive mu_w K");
    if (!ctx.protocol) return ctx.fail("protocol: " + ctx.protocolError);
    const recording::Protocol& proto = *ctx.protocol;
    if (!(proto.diameter > 0) || !(proto.height > 0)) {
        ctx.d.status = "not_run";
        ctx.d.reason = "the protocol's device has no diameter and fill height: the DEM mould's aspect ratio H/D is unknown";
        return ctx.finish();
    }
    // the mould: the recording's H/D at a size the DEM affords. fast: 12 mean diameters across, at
    // least 4 high (a flatter mould widens, up to 24 diameters); ft4: the FT4's 50 mm diameter, at
    // least 4 diameters high. Never higher than 3 D. Where H/D cannot be kept, the report gives both.
    const double aspect = proto.height / proto.diameter, dm = kDemMeanDiameter;
    double D = ctx.opt.mode == "ft4" ? 0.05 : kFastMouldDiameters * dm;
    double H = D * aspect;
    if (H < 4 * dm) {
        H = 4 * dm;
        if (ctx.opt.mode != "ft4") D = std::min(H / aspect, 2 * kFastMouldDiameters * dm);
    }
    H = std::min(H, 3 * D);
    ctx.d.recordingAspect = aspect;
    ctx.d.mouldDiameter = D;
    ctx.d.mouldHeight = H;
    ctx.geometry = " --geometry cylinder --device dem_mould --diameter " + fmt(D) + " --fill_height_m " + fmt(H);
    // fast: ramps at the ft4 preset's strain rate (half the time of the driver's default; the
    // unloading ratio of a 20 mm mould moved by 1-3 % between the two, see the documentation)
    if (ctx.opt.mode != "ft4") ctx.geometry += " --ramp_rate 1";
    // with a bottom sensor: the loading's bottom/piston transmission is Janssen's exp(-4 mu_w K H/D)
    // and falls steadily with mu_w (30 mm mould, H/D ~ 1, three fill seeds: 1.005-1.011 at mu_w = 0,
    // 0.77-0.80 at 0.16-0.2, 0.65-0.70 at 0.26-0.33), so a secant on its logarithm aims at the
    // recording's. The first run: the recording's own Janssen estimate, 2 mu_w K with K ~ 0.5.
    const std::string args = " --relax_C 0 --kc_over_k 0 --k_over_k1 1 --fill_wall_friction 0 --d_mean " + fmt(kDemMeanDiameter);
    const double labT = loadingTransmission(rec.t, rec.strain, rec.stress, rec.bottom).slope;
    if (labT > 0) {
        const double janssen = std::max(-std::log(labT), 0.0) / (4 * aspect);
        BranchKnob knob{"wall_friction", "--wall_friction", "dem_wall", 0, 0.02, kMaxWallFriction,
                        std::clamp(2 * janssen, 0.02, kMaxWallFriction), args, &DemRun::wallFriction, 0.6, Calibration::Transmission};
        knob.aspectScale = (H / D) / aspect;
        return confirmBranches(ctx, knob, rec, protocolPath);
    }
    // without: runs at the guess, half and twice it, chosen by the calibration error. The guess:
    // Janssen's product mu_w K with K ~ 0.5 for a poured bed, at least kMinWallFrictionGuess (the
    // surrogate's muK came out 10 times too small on a DEM-made record). In a mould of about a
    // thousand particles the unloading ratio is not monotone in mu_w (collapses near the peak move the
    // loading tangent by a factor 4 between runs), so no secant can aim at it. Every bed is poured
    // with frictionless walls (--fill_wall_friction 0): all runs compress the same bed and differ in
    // mu_w only.
    const double guess = std::clamp(std::max(2 * muK, kMinWallFrictionGuess), 0.02, kMaxWallFriction);
    const BranchKnob knob{"wall_friction", "--wall_friction", "dem_wall", 0, 0.02, kMaxWallFriction, guess, args,
                          &DemRun::wallFriction, 0.6, Calibration::Grid, {1, 0.5, 2}};
    return confirmBranches(ctx, knob, rec, protocolPath);
}

// ---- cohesion: the tension of a lift-off test ------------------------------------------------------

/// cohesion: Luding adhesion kc/k of the particle pairs and of the walls (--kc_over_k,
/// --wall_kc_over_k), chosen from a grid by the unload error; the protocol must pull on the bed (an
/// unload with a negative target stress), since the DEM replays a protocol by its stress targets and
/// the adhesion shows only in tension (DemConfirmation.h).
DemResult confirmCohesion(DemContext& ctx, const Recording& rec, const std::string& protocolPath) {
    ctx.d.mechanism = "cohesion";
    if (!ctx.protocol) return ctx.fail("protocol: " + ctx.protocolError);
    if (!pullsOnTheBed(*ctx.protocol)) {
        ctx.d.status = "not_run";
        ctx.d.reason = "the protocol has no unload into tension (an unload with a negative target stress: a lift-off test); the DEM "
                       "driver replays a protocol by its stress targets, and adhesion shows in the DEM only where the piston pulls on the bed";
        return ctx.finish();
    }
    BranchKnob knob{"cohesion", "--kc_over_k", "dem_cohesion", 0, 0.05, kMaxKcOverK, 1.0, " --relax_C 0", &DemRun::kcOverK, 0.2,
                    Calibration::Grid, {0.25, 0.5, 1.0}};
    knob.flag2 = "--wall_kc_over_k";
    knob.tension = true;
    return confirmBranches(ctx, knob, rec, protocolPath);
}

// ---- stiffness_nonlinearity: the curvature of the unloading ---------------------------------------

namespace {

/// Samples at the top of an unload branch: the leading run with y >= 0.8, on the samples themselves (the
/// window of unloadStiffnessExponent's tangents; unloadCurvature finds its ends on a running mean).
std::size_t topSamples(const Branch& br) {
    std::size_t top = 0;
    while (top < br.y.size() && br.y[top] >= 0.8) ++top;
    return top;
}

/// Running mean of v over `width` samples centred on each; near the ends the window shrinks on both
/// sides (the first and last samples are their own mean), so that a straight run stays unbiased.
std::vector<double> runningMean(const std::vector<double>& v, int width) {
    const std::size_t n = v.size();
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t h = std::min({static_cast<std::size_t>(width / 2), i, n - 1 - i});
        const std::size_t a = i - h, b = i + h + 1;
        double sum = 0;
        for (std::size_t j = a; j < b; ++j) sum += v[j];
        out[i] = sum / static_cast<double>(b - a);
    }
    return out;
}

} // namespace

double unloadCurvature(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yLow) {
    double sum = 0;
    int n = 0;
    for (std::size_t k : which) {
        if (k >= b.size() || b[k].phase != Phase::Unload) continue;
        const Branch& br = b[k];
        const std::vector<double> ym = runningMean(br.y, kCurvatureSmoothing);
        std::size_t top = 0;
        while (top < ym.size() && ym[top] >= 0.8) ++top;
        std::size_t low = top;
        while (low < ym.size() && ym[low] > yLow) ++low;
        if (top < 3 || low >= ym.size() || !(br.u[low] > 0)) continue;
        const double tangent = -slope(br.u, br.y, 0, top);
        const double secant = (1 - ym[low]) / br.u[low];
        if (tangent > 0 && secant > 0) sum += tangent / secant, ++n;
    }
    return n > 0 ? sum / n : -1;
}

double unloadCurvatureSpread(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yLow, const NoiseModel& noise,
                             int draws) {
    double arVar = noise.arVar, whiteVar = noise.whiteVar;
    if (!(arVar + whiteVar > 0)) arVar = noise.sigma * noise.sigma, whiteVar = 0;
    if (!(arVar + whiteVar > 0) || draws < 2) return 0;
    const double rho = std::clamp(noise.rho, 0.0, 0.999);
    std::mt19937_64 rng(20261207);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<Branch> replica = b;
    std::vector<std::vector<double>> mean(b.size());
    for (std::size_t k : which)
        if (k < b.size()) mean[k] = runningMean(b[k].s, kCurvatureSmoothing);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int q = 0; q < draws; ++q) {
        for (std::size_t k : which) {
            if (k >= b.size() || b[k].phase != Phase::Unload || b[k].s.empty()) continue;
            Branch& r = replica[k];
            double ar = std::sqrt(arVar) * normal(rng);  // the stationary AR(1) part at the first sample
            for (std::size_t i = 0; i < r.s.size(); ++i) {
                if (i > 0) ar = rho * ar + std::sqrt((1 - rho * rho) * arVar) * normal(rng);
                r.s[i] = mean[k][i] + ar + std::sqrt(whiteVar) * normal(rng);
            }
            r.sRef = r.s.front();
            if (!(r.sRef > 0)) continue;
            for (std::size_t i = 0; i < r.s.size(); ++i) r.y[i] = r.s[i] / r.sRef;
        }
        const double c = unloadCurvature(replica, which, yLow);
        if (c > 0) sum += c, sum2 += c * c, ++n;
    }
    if (n < 2) return 0;
    const double m = sum / n;
    return std::sqrt(std::max(0.0, (sum2 - n * m * m) / (n - 1)));
}

/// Pressure exponent of the unloading stiffness: ln(T_hi / T_lo) / ln(S_hi / S_lo) between the unload
/// branches with the highest and the lowest start stress S, T the tangent dsigma/deps at the top
/// (least squares over the samples with y >= 0.8); NaN unless S_hi >= kExponentStressRatio S_lo.
/// Hertzian contacts stiffen with the force (1/3 for a fixed contact network), linear ones do not.
double unloadStiffnessExponent(const std::vector<Branch>& b) {
    const Branch *lo = nullptr, *hi = nullptr;
    for (const Branch& br : b) {
        if (br.phase != Phase::Unload || br.s.empty()) continue;
        if (!lo || br.sRef < lo->sRef) lo = &br;
        if (!hi || br.sRef > hi->sRef) hi = &br;
    }
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    if (!lo || !hi || !(hi->sRef >= kExponentStressRatio * lo->sRef) || !(lo->sRef > 0)) return nan;
    const auto tangent = [](const Branch& br) {
        const std::size_t top = topSamples(br);
        return top >= 3 ? slope(br.e, br.s, 0, top) : nan;
    };
    const double tLo = tangent(*lo), tHi = tangent(*hi);
    if (!(tLo > 0) || !(tHi > 0)) return nan;
    return std::log(tHi / tLo) / std::log(hi->sRef / lo->sRef);
}

/// stiffness_nonlinearity: linear against Hertzian contacts, E* calibrated on the unloading's
/// curvature, scored on the reloads (DemConfirmation.h).
DemResult confirmNonlinearity(DemContext& ctx, const MechanismResult& nonlin, const Recording& rec, const std::string& protocolPath) {
    DemResult& d = ctx.d;
    d.mechanism = "stiffness_nonlinearity";
    d.calibration = "unload_curvature_secant";
    for (std::size_t q = 0; q < nonlin.params.size(); ++q)
        if (nonlin.params[q] == pExpN) d.surrogateValue = nonlin.value[q];
    const std::vector<Branch> lab = cycleBranches(rec.t, rec.strain, rec.stress);
    std::vector<std::size_t> cal, held;
    if (!splitBranches(d, lab, cal, held)) return ctx.finish();
    // the secant ends at 20 % of the start stress, or just above the lowest stress the recording's
    // unloads reach (the DEM runs follow the same protocol, so they reach it too)
    double yMinLab = 1;
    for (std::size_t k : cal)
        for (double y : lab[k].y) yMinLab = std::min(yMinLab, y);
    d.ratioYMin = std::max(kCurvatureLowY, yMinLab + 0.02);
    d.labMacro = d.ratioYMin <= kCurvatureMaxLowY ? unloadCurvature(lab, cal, d.ratioYMin) : -1;
    if (!(d.labMacro > 0)) {
        d.status = "not_run";
        d.reason = "the recording's unloads go down to " + fmt(100 * yMinLab) + " % of their start stress; the unloading curvature needs " +
                   "an unload to at most " + fmt(100 * (kCurvatureMaxLowY - 0.02)) + " % with at least 3 samples above 80 %";
        return ctx.finish();
    }
    d.labMacroSpread = unloadCurvatureSpread(lab, cal, d.ratioYMin, ctx.noise);
    const double maxTarget = scaleProtocolStress(ctx);
    if (!(maxTarget > 0)) return ctx.finish();
    const double eMatch = hertzModulusMatching(kDemContactStiffness, kDemMeanDiameter, maxTarget * d.stressScale);
    const double eLo = eMatch / kHertzSoftest;

    std::vector<std::vector<Branch>> all;
    std::vector<double> curv;
    const auto runDem = [&](const std::string& name, double modulus, double normalScale = 1) {
        DemRun run;
        run.name = name;
        run.hertzModulus = modulus;
        run.normalStiffnessScale = normalScale;
        std::string args = " --material frictional --relax_C 0 --kc_over_k 0 --k_over_k1 1 --d_mean " + fmt(kDemMeanDiameter) +
                           " --stress_scale " + fmt(d.stressScale);
        if (ctx.opt.mode != "ft4") args += " " + std::string(kNonlinearityFastBed);
        if (modulus > 0) args += " --hertz_modulus " + fmt(modulus);
        if (normalScale != 1) args += " --normal_stiffness_scale " + fmt(normalScale);
        std::vector<Branch> br;
        if (ctx.run(run, protocolPath, args)) {
            try {
                br = readDemRecord(ctx.workDir + "/" + name).branches;
            } catch (const InputError&) {
                br.clear();  // an unreadable DEM record: the run counts as failed
            }
        }
        all.push_back(br);
        curv.push_back(unloadCurvature(br, cal, d.ratioYMin));
        d.runs.back().macro = curv.back();
        return samePhases(lab, br) && curv.back() > 0;
    };
    const auto mismatch = [&](const std::string& name) {
        return ctx.fail("DEM run " + name + " failed, its unload/reload branches do not pair with the recording's " +
                        std::to_string(lab.size()) + " or its unloads give no curvature (log: " + name + ".log)");
    };
    if (!runDem("dem_baseline", 0)) return mismatch("dem_baseline");
    if (d.labMacro <= curv[0] + kCurvatureMargin) {
        // a claim against Hertzian contacts needs a curvature that the recording's noise could not
        // have pushed down that far (an inconclusive record runs nothing more)
        if (d.labMacro + kCurvatureSpreads * d.labMacroSpread > curv[0] + kCurvatureMargin) {
            d.status = "inconclusive";
            d.reason = "the recording's unloading curvature, " + num(d.labMacro, 3) + " +- " + num(d.labMacroSpread, 2) +
                       " (the spread its noise gives, sd " + num(ctx.noise.sigma, 3) + " Pa), is not above the linear-contact DEM bed's " +
                       num(curv[0], 3) + " by " + fmt(kCurvatureMargin) + ", but " + fmt(kCurvatureSpreads) +
                       " spreads could hide that much: the noise leaves open whether the unloads are more curved than linear "
                       "contacts make them; a recording with less noise or more samples on the top of its unloads decides";
            return ctx.finish();
        }
        d.status = "contradicted";
        d.reason = "the recording's unloading curvature, " + fmt(d.labMacro) + ", is not above the linear-contact DEM bed's " + fmt(curv[0]) +
                   " by at least " + fmt(kCurvatureMargin) +
                   ": its unloads show no stiffness falling with the force beyond what the packing itself gives, so Hertzian contacts "
                   "are not what the record shows";
        return ctx.finish();
    }
    // Hertzian runs: E* = eMatch / 10; then the secant on the curvature against ln E* through the
    // linear bed (placed at E* = eMatch, where a Hertzian bed measured like the linear one) and run
    // a, aimed at the recording's; a third run from the secant through a and b when neither is within
    // 10 % of the recording's excess over the linear bed
    // (the curvature must grow as E* falls; NaN where the two points do not show that, bed-to-bed
    // scatter being larger than the step)
    const auto secant = [&](double x0, double q0, double x1, double q1) {
        const bool falling = (q1 - q0) * (x1 - x0) < 0 && std::abs(q1 - q0) > 1e-3;
        if (!falling) return std::numeric_limits<double>::quiet_NaN();
        return std::clamp(std::exp(x0 + (x1 - x0) * (d.labMacro - q0) / (q1 - q0)), eLo, eMatch);
    };
    const double eA = eMatch / 10;
    if (!runDem("dem_hertz_a", eA)) return mismatch("dem_hertz_a");
    double eB = secant(std::log(eMatch), curv[0], std::log(eA), curv[1]);
    if (std::isnan(eB)) eB = std::max(eA / 10, eLo);  // run a no more curved than the linear bed (which the recording exceeds): softer
    if (eB != eA) {
        if (!runDem("dem_hertz_b", eB)) return mismatch("dem_hertz_b");
        const double tol = 0.1 * (d.labMacro - curv[0]);
        if (std::abs(curv[1] - d.labMacro) > tol && std::abs(curv[2] - d.labMacro) > tol) {
            // no third run where a and b do not show the trend (the scatter would aim it anywhere)
            const double eC = secant(std::log(eA), curv[1], std::log(eB), curv[2]);
            if (std::isfinite(eC) && eC != eA && eC != eB && !runDem("dem_hertz_c", eC)) return mismatch("dem_hertz_c");
        }
    }
    // the reloads are judged from their own start (DemRuns.h, BranchJudge::StressFromStart): the
    // confirmation's bed is never the record's, and on the u scale the strain another bed's unload
    // recovers sets an offset at the reload's first sample that the contact law does not decide
    // (Documentation/tools-explain.md, "The reload judged from its start")
    const auto score = [&](std::size_t q) {
        d.runs[q].calibrationRmse = branchRmse(lab, all[q], cal);
        d.runs[q].heldoutRmse = branchRmse(lab, all[q], held, BranchJudge::StressFromStart);
        d.runs[q].heldoutUScaleRmse = branchRmse(lab, all[q], held);
    };
    for (std::size_t q = 0; q < all.size(); ++q) score(q);
    d.chosen = 1;
    for (std::size_t q = 2; q < d.runs.size(); ++q)
        if (d.runs[q].calibrationRmse < d.runs[static_cast<std::size_t>(d.chosen)].calibrationRmse) d.chosen = static_cast<int>(q);
    // the control: linear contacts as soft as the chosen Hertzian ones at the top stress (DemConfirmation.h)
    const std::size_t chosen = static_cast<std::size_t>(d.chosen);
    const double scale = hertzSecantStiffness(d.runs[chosen].hertzModulus, kDemMeanDiameter, maxTarget * d.stressScale) /
                         kDemContactStiffness;
    if (runDem("dem_linear_control", 0, scale)) {
        d.control = static_cast<int>(all.size() - 1);
        score(all.size() - 1);
        // the judge: the unloading stiffness's pressure exponent where the recording unloads from two
        // stress levels; else the held-out reload followed from its start (where Hertzian contacts,
        // soft at small forces, and linear ones as soft at the top differ most); the curvature (which
        // hardly tells the law) only where a reload error is missing
        const double labExponent = unloadStiffnessExponent(lab);
        for (std::size_t q = 0; q < all.size(); ++q) d.runs[q].exponent = unloadStiffnessExponent(all[q]);
        d.judgedByExponent = std::isfinite(labExponent) && std::isfinite(d.runs[chosen].exponent) && std::isfinite(d.runs.back().exponent);
        if (std::isfinite(labExponent)) d.labExponent = labExponent;
        const DemRun &hz = d.runs[chosen], &ctl = d.runs.back();
        if (d.judgedByExponent) {
            d.lawJudge = "unload_stiffness_exponent";
            d.contactLaw = favouredLawByMiss(std::abs(hz.exponent - labExponent), std::abs(ctl.exponent - labExponent), kExponentMargin);
        } else if (hz.heldoutRmse > 0 && ctl.heldoutRmse > 0) {
            d.lawJudge = "reload_from_its_start";
            d.contactLaw = favouredLawByRatio(hz.heldoutRmse, ctl.heldoutRmse, kReloadLawRatio);
        } else {
            d.lawJudge = "unload_curvature";
            d.contactLaw = favouredLawByMiss(std::abs(curv[chosen] - d.labMacro), std::abs(curv.back() - d.labMacro), kCurvatureMargin);
        }
    } else {  // the control only qualifies the result: without it the law is not judged
        d.controlNote = "the control run dem_linear_control failed or does not pair with the recording (log: dem_linear_control.log)";
        d.runs.pop_back();
        all.pop_back();
        curv.pop_back();
    }
    ctx.scoreChosen();
    d.heldoutUScaleBaseline = d.runs.front().heldoutUScaleRmse;
    d.heldoutUScaleAugmented = d.runs[chosen].heldoutUScaleRmse;
    writeBranchComparison(ctx, lab, all, BranchJudge::StressFromStart);
    return ctx.finish();
}

} // namespace pdpm::explain::dem

namespace pdpm::explain {

namespace {
/// Mean contact force f = pi d^2 stress / (3 phi Z) of a poured bed of spheres of diameter d (N).
double meanContactForce(double d, double stress) { return std::numbers::pi * d * d * stress / (3 * kDemPackingPhiZ); }
} // namespace

double hertzModulusMatching(double k, double d, double stress) {
    const double delta = meanContactForce(d, stress) / k;  // the linear law's overlap
    return 3 * k / (4 * std::sqrt(0.25 * d * delta));      // (4/3) E* sqrt(R delta) delta = k delta, R = d/4
}

double unloadStiffnessExponent(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s) {
    return dem::unloadStiffnessExponent(dem::cycleBranches(t, e, s));
}

double hertzSecantStiffness(double modulus, double d, double stress) {
    const double f = meanContactForce(d, stress);
    const double delta = std::cbrt(std::pow(3 * f / (4 * modulus * std::sqrt(0.25 * d)), 2));  // f = (4/3) E* sqrt(R) delta^(3/2)
    return f / delta;
}

const char* contactLawName(ContactLaw law) {
    switch (law) {
    case ContactLaw::Hertz: return "hertz";
    case ContactLaw::LinearAsSoft: return "linear_as_soft";
    case ContactLaw::NotTold: break;
    }
    return "not_told";
}

ContactLaw favouredLawByMiss(double hertzMiss, double controlMiss, double margin) {
    if (controlMiss > hertzMiss + margin) return ContactLaw::Hertz;
    if (hertzMiss > controlMiss + margin) return ContactLaw::LinearAsSoft;
    return ContactLaw::NotTold;
}

ContactLaw favouredLawByRatio(double hertzError, double controlError, double ratio) {
    if (controlError >= ratio * hertzError) return ContactLaw::Hertz;
    if (hertzError >= ratio * controlError) return ContactLaw::LinearAsSoft;
    return ContactLaw::NotTold;
}

} // namespace pdpm::explain
