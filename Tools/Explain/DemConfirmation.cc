#include "DemConfirmation.h"

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

namespace pdpm::explain {

namespace {

namespace fs = std::filesystem;

/// One hold of the lab recording: time since its start and stress.
struct LabHold {
    std::vector<double> t, s;
    double s0 = 0, tStart = 0;  ///< tStart: recording time of the hold's first sample
};

/// Hold curves of a DEM run, normalised: g(t) = sigma(t)/sigma(0), t from the clock start.
struct DemHold {
    std::vector<double> t, g;
    double fitC = -1, fitT0 = -1;  ///< the driver's Eq. 4.3 fit of the hold (-1: none)
};

double interpolate(const DemHold& h, double t) {
    if (h.t.empty()) return 1;
    if (t <= h.t.front()) return h.g.front();
    if (t >= h.t.back()) return h.g.back();
    const auto it = std::upper_bound(h.t.begin(), h.t.end(), t);
    const std::size_t k = static_cast<std::size_t>(it - h.t.begin());
    const double w = (t - h.t[k - 1]) / (h.t[k] - h.t[k - 1]);
    return (1 - w) * h.g[k - 1] + w * h.g[k];
}

std::vector<DemHold> readDemHolds(const std::string& base) {
    const std::vector<recording::HoldSummary> holds = recording::protocolHolds(recording::readProtocol(base + ".protocol.json"));
    const recording::Recording rec = recording::readRecording(base + ".recording.csv");
    const int ct = rec.column("time_s"), cs = rec.column("axial_stress_Pa"), cstep = rec.column("step");
    if (ct < 0 || cs < 0 || cstep < 0) inputError(base + ".recording.csv: missing time_s/axial_stress_Pa/step");
    std::vector<DemHold> out;
    for (const recording::HoldSummary& h : holds) {
        if (!h.position) continue;
        DemHold d;
        d.fitC = h.fitC;
        d.fitT0 = h.fitT0;
        d.t.push_back(0);
        d.g.push_back(1);
        for (const auto& row : rec.rows)
            if (row[static_cast<std::size_t>(cstep)] == h.step && row[static_cast<std::size_t>(ct)] > h.labStart) {
                d.t.push_back(row[static_cast<std::size_t>(ct)] - h.labStart);
                d.g.push_back(h.stressStart > 0 ? row[static_cast<std::size_t>(cs)] / h.stressStart : 1);
            }
        out.push_back(std::move(d));
    }
    return out;
}

/// DEM prediction of sample i of lab hold k.
double holdPredict(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, std::size_t k, std::size_t i) {
    return lab[k].s0 * interpolate(dem[k], lab[k].t[i]);
}

/// RMSE (Pa) of the DEM prediction over the lab holds with index in `which`.
double holdRmse(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, const std::vector<std::size_t>& which) {
    double ss = 0;
    std::size_t n = 0;
    for (std::size_t k : which) {
        if (k >= dem.size()) return -1;
        for (std::size_t i = 0; i < lab[k].t.size(); ++i) {
            const double e = lab[k].s[i] - holdPredict(lab, dem, k, i);
            ss += e * e;
            ++n;
        }
    }
    return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : -1;
}

/// One compared lab sample: the item (hold or branch), whether it was held out, the abscissa of the
/// figure (recording time or strain), the lab stress and each run's prediction.
struct Compared {
    std::size_t item = 0;
    bool heldout = false;
    double x = 0, lab = 0;
    std::vector<double> pred;
};

/// DIR/comparison.csv and, with gnuplot, DIR/comparison.png: the lab samples the DEM runs were
/// scored on, with every run's prediction (baseline, a, b; the chosen run in the figure's title).
void writeComparison(const std::string& dir, const std::vector<Compared>& rows, const DemResult& d, const std::string& xName,
                     const std::string& xLabel, bool figures) {
    std::ostringstream os;
    os << "item,role," << xName << ",lab_stress_Pa";
    for (const DemRun& r : d.runs) os << ',' << r.name << "_Pa";
    os << '\n' << std::setprecision(10);
    for (const Compared& c : rows) {
        os << c.item + 1 << ',' << (c.heldout ? "heldout" : "calibration") << ',' << c.x << ',' << c.lab;
        for (double p : c.pred) os << ',' << p;
        os << '\n';
    }
    const std::string csv = dir + "/comparison.csv", png = dir + "/comparison.png";
    writeWholeFile(csv, os.str());
    if (!figures || d.chosen < 0) return;
    const int col = 5 + d.chosen;
    std::ostringstream g;
    g << "set terminal pngcairo size 1000,600 noenhanced\nset output " << gnuplotQuote(png + ".tmp") << "\n"
      << "set datafile separator ','\nset xlabel '" << xLabel << "'\nset ylabel 'axial stress (Pa)'\nset key left top\n"
      << "set title 'DEM confirmation (" << d.mechanism << "): held-out RMSE " << std::setprecision(4) << d.heldoutBaseline << " -> "
      << d.heldoutAugmented << " Pa; open symbols: held out'\n"
      << "plot " << gnuplotQuote(csv) << " every ::1 u 3:(stringcolumn(2) eq 'calibration' ? $4 : 1/0) w p pt 7 ps 0.5 lc rgb '#777777' t 'recording (calibration)', "
      << "'' every ::1 u 3:(stringcolumn(2) eq 'heldout' ? $4 : 1/0) w p pt 6 ps 0.7 lc rgb '#000000' t 'recording (held out)', "
      << "'' every ::1 u 3:5 w p pt 1 ps 0.5 lc rgb 'blue' t 'DEM " << d.runs[0].name << "', "
      << "'' every ::1 u 3:" << col << " w p pt 2 ps 0.5 lc rgb 'red' t 'DEM " << d.runs[static_cast<std::size_t>(d.chosen)].name << "'\n";
    writeWholeFile(dir + "/comparison.gp", g.str());
    runGnuplot(dir + "/comparison.gp", {png});
}

// ---- plasticity: unload and reload branches in normalised coordinates ---------------------------

/// One branch below the largest strain (an unload, or the reload that follows it), in the
/// coordinates of its reference point (strain e_ref and stress s_ref where the unload began, loading
/// tangent E_load before it): u = (e_ref - e) E_load / s_ref, y = s / s_ref. A linear elastic
/// material unloads along y = 1 - u; one whose unloading is lambda times stiffer along y = 1 - lambda u.
struct Branch {
    Phase phase = Phase::Unload;
    double sRef = 0;
    std::vector<double> u, y, s, e;  ///< s, e: stress (Pa) and strain of the samples
    std::vector<double> b;           ///< bottom stress (Pa) of the samples, when recorded
};

/// Least-squares slope of y against x over [i0, i1).
double slope(const std::vector<double>& x, const std::vector<double>& y, std::size_t i0, std::size_t i1) {
    const double n = static_cast<double>(i1 - i0);
    double mx = 0, my = 0;
    for (std::size_t i = i0; i < i1; ++i) mx += x[i], my += y[i];
    mx /= n, my /= n;
    double sxy = 0, sxx = 0;
    for (std::size_t i = i0; i < i1; ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxx > 0 ? sxy / sxx : 0;
}

/// Unload and reload branches of a record, in order (holds are not branches). The reference is
/// taken where an unload follows a loading (holds in between ignored) and kept for the unloads and
/// reloads after it until the next loading; branches without a usable reference (no loading of at
/// least 3 samples before them, a non-positive stress or loading tangent at the start) are skipped.
std::vector<Branch> cycleBranches(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                  const std::vector<double>& bottom = {}) {
    std::vector<Branch> out;
    const std::vector<PhaseSegment> ph = detectPhases(t, e);
    const PhaseSegment* lastLoad = nullptr;
    bool afterLoad = false, valid = false;
    double eRef = 0, sRef = 0, eLoad = 0;
    for (const PhaseSegment& seg : ph) {
        if (seg.phase == Phase::Hold) continue;
        if (seg.phase == Phase::Load) {
            lastLoad = &seg;
            afterLoad = true;
            valid = false;
            continue;
        }
        if (seg.phase == Phase::Unload && afterLoad) {
            afterLoad = false;
            valid = false;
            if (lastLoad->end - lastLoad->begin < 3) continue;
            // loading tangent: the samples of the last loading in its top 20 % of stress (at least 3)
            const double top = *std::max_element(s.begin() + static_cast<long>(lastLoad->begin), s.begin() + static_cast<long>(lastLoad->end));
            std::size_t i0 = lastLoad->end;
            while (i0 > lastLoad->begin && (s[i0 - 1] >= 0.8 * top || lastLoad->end - i0 < 3)) --i0;
            eLoad = slope(e, s, i0, lastLoad->end);
            eRef = e[seg.begin];
            sRef = s[seg.begin];
            valid = eLoad > 0 && sRef > 0;
        }
        if (!valid) continue;
        Branch b;
        b.phase = seg.phase;
        b.sRef = sRef;
        for (std::size_t i = seg.begin; i < seg.end; ++i) {
            b.u.push_back((eRef - e[i]) * eLoad / sRef);
            b.y.push_back(s[i] / sRef);
            b.s.push_back(s[i]);
            b.e.push_back(e[i]);
            if (bottom.size() == s.size()) b.b.push_back(bottom[i]);
        }
        out.push_back(std::move(b));
    }
    return out;
}

/// Whether a DEM run's branches pair with the lab's: the same number, the same phase at each index.
bool samePhases(const std::vector<Branch>& lab, const std::vector<Branch>& dem) {
    if (lab.size() != dem.size()) return false;
    for (std::size_t k = 0; k < lab.size(); ++k)
        if (lab[k].phase != dem[k].phase) return false;
    return true;
}

/// The branch as a function y(u): samples sorted by u (linear interpolation, constant outside).
double branchAt(const std::vector<std::pair<double, double>>& uy, double u) {
    if (uy.empty()) return 0;
    if (u <= uy.front().first) return uy.front().second;
    if (u >= uy.back().first) return uy.back().second;
    const auto it = std::upper_bound(uy.begin(), uy.end(), std::make_pair(u, -std::numeric_limits<double>::infinity()));
    const auto& [u1, y1] = *it;
    const auto& [u0, y0] = *(it - 1);
    return u1 > u0 ? y0 + (y1 - y0) * (u - u0) / (u1 - u0) : y1;
}

/// DEM predictions of every sample of lab branch k: s_pred = s_ref,lab * y_DEM(u_lab); with `bottom`,
/// of its bottom stress: b_pred = s_ref,lab * (b / s_ref)_DEM(u_lab) (empty when a record lacks it).
std::vector<double> branchPredict(const std::vector<Branch>& lab, const std::vector<Branch>& dem, std::size_t k, bool bottom = false) {
    if (bottom && (dem[k].b.size() != dem[k].u.size() || lab[k].b.size() != lab[k].u.size())) return {};
    std::vector<std::pair<double, double>> uy;
    for (std::size_t i = 0; i < dem[k].u.size(); ++i) uy.emplace_back(dem[k].u[i], bottom ? dem[k].b[i] / dem[k].sRef : dem[k].y[i]);
    std::sort(uy.begin(), uy.end());
    std::vector<double> out;
    for (double u : lab[k].u) out.push_back(lab[k].sRef * branchAt(uy, u));
    return out;
}

/// RMSE (Pa) of the DEM branches predicting the lab branches with index in `which` (with `bottom`:
/// their bottom stress; -1 when a record lacks it).
double branchRmse(const std::vector<Branch>& lab, const std::vector<Branch>& dem, const std::vector<std::size_t>& which,
                  bool bottom = false) {
    double ss = 0;
    std::size_t n = 0;
    for (std::size_t k : which) {
        if (k >= dem.size()) return -1;
        const std::vector<double> pred = branchPredict(lab, dem, k, bottom);
        if (pred.size() != lab[k].u.size()) return -1;
        for (std::size_t i = 0; i < pred.size(); ++i) {
            const double err = (bottom ? lab[k].b[i] : lab[k].s[i]) - pred[i];
            ss += err * err;
            ++n;
        }
    }
    return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : -1;
}

/// Unloading stiffness over loading tangent measured on the unload branches in `which`: the slope
/// lambda of 1 - y = lambda u through the origin over the samples with y >= yMin (plasticity: 0.2,
/// the tail near zero stress left out; wall_friction: 0.6, the top of the unload where the wall
/// shear turns round). The same estimator on the lab and on the DEM record.
double unloadRatio(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yMin) {
    double suy = 0, suu = 0;
    for (std::size_t k : which) {
        if (k >= b.size() || b[k].phase != Phase::Unload) continue;
        for (std::size_t i = 0; i < b[k].u.size(); ++i)
            if (b[k].y[i] >= yMin) suy += b[k].u[i] * (1 - b[k].y[i]), suu += b[k].u[i] * b[k].u[i];
    }
    return suu > 0 ? suy / suu : -1;
}

/// A DEM run's record: its unload/reload branches and its loading transmission.
struct DemRecord {
    std::vector<Branch> branches;
    double transmission = -1;
};

DemRecord readDemRecord(const std::string& base) {
    const recording::Recording rec = recording::readRecording(base + ".recording.csv");
    const int ct = rec.column("time_s"), cs = rec.column("axial_stress_Pa"), ce = rec.column("axial_strain"),
              cb = rec.column("bottom_stress_Pa");
    if (ct < 0 || cs < 0 || ce < 0) inputError(base + ".recording.csv: missing time_s/axial_strain/axial_stress_Pa");
    if (rec.rows.size() < 10) inputError(base + ".recording.csv: fewer than 10 samples");
    std::vector<double> t, e, s, b;
    for (const auto& row : rec.rows) {
        t.push_back(row[static_cast<std::size_t>(ct)]);
        e.push_back(row[static_cast<std::size_t>(ce)]);
        s.push_back(row[static_cast<std::size_t>(cs)]);
        if (cb >= 0) b.push_back(row[static_cast<std::size_t>(cb)]);
    }
    DemRecord out;
    out.branches = cycleBranches(t, e, s, b);
    out.transmission = loadingTransmission(t, e, s, b).slope;
    return out;
}

/// Shared set-up of the DEM runs: the driver, the work directory and the clock.
struct DemContext {
    const DemOptions& opt;
    std::string driver, workDir;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    DemResult& d;
    /// geometry arguments of every run (empty: the driver's default laterally periodic bed; ft4: the
    /// FT4 mould, without the preset's protocol: the recording's is used)
    std::string geometry = opt.mode == "ft4" ? " --geometry cylinder --device ft4 --diameter 0.05 --fill_height_m 0.05" : "";
    /// the recording's protocol, read once (null when it could not be read: protocolError says why)
    const recording::Protocol* protocol = nullptr;
    std::string protocolError = "";

    /// Runs the driver with the recording's protocol and `args`; false when it failed.
    bool run(DemRun run, const std::string& protocolPath, const std::string& args) {
        std::ostringstream cmd;
        cmd << shellQuote(driver) << " --protocol_file " << shellQuote(protocolPath) << args << " --output " << shellQuote(workDir) << " --name "
            << run.name << " --threads " << opt.threads << " --quiet --vtk 0 --ene 0";
        cmd << geometry;
        if (opt.mode == "ft4") cmd << " --hold_tau 0.005 --ramp_rate 1";  // the driver's ft4 preset's numerical settings
        run.command = cmd.str();
        const auto t1 = std::chrono::steady_clock::now();
        const int rc = std::system((run.command + " > " + shellQuote(workDir + "/" + run.name + ".log") + " 2>&1").c_str());
        run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        d.runs.push_back(run);
        return rc == 0;
    }
    DemResult fail(const std::string& why) {
        d.status = "failed";
        d.reason = why;
        return finish();
    }
    DemResult finish() {
        d.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return d;
    }
};

/// dem/comparison.csv (and .png) of a hold confirmation: every lab hold sample, the odd holds held out.
void writeHoldComparison(const DemContext& ctx, const std::vector<LabHold>& lab, const std::vector<const std::vector<DemHold>*>& all) {
    std::vector<Compared> rows;
    for (std::size_t k = 0; k < lab.size(); ++k)
        for (std::size_t i = 0; i < lab[k].t.size(); ++i) {
            Compared c{k, k % 2 == 1, lab[k].tStart + lab[k].t[i], lab[k].s[i], {}};
            for (const auto* run : all) c.pred.push_back(holdPredict(lab, *run, k, i));
            rows.push_back(std::move(c));
        }
    writeComparison(ctx.workDir, rows, ctx.d, "time_s", "time (s)", ctx.opt.figures);
}

/// Where the piston stopped before the hold that begins at sample `stop` at strain eHold: straight lines
/// of strain and stress against time over the second half of the ramp segment `ramp` before it, or,
/// where the ramp changed its speed (speedChanges, `changes`), over the samples after the last change
/// but its first eighth (at least 4 samples). The stop's time is where the strain line reaches eHold
/// (kept between the ramp's last sample and the hold's first), its stress the stress line's there.
/// False when there are fewer samples.
bool rampStop(const Recording& rec, const PhaseSegment& ramp, std::size_t stop, double eHold, const std::vector<RateChange>& changes,
              double& tStop, double& sStop) {
    const std::size_t n = ramp.end - ramp.begin;
    if (n < 8) return false;
    std::size_t from = ramp.begin + n / 2;
    for (const RateChange& c : changes)
        if (c.index > ramp.begin && c.index < ramp.end) from = c.index + (ramp.end - c.index) / 8;
    const std::size_t to = std::min(ramp.end, stop);
    if (to < from + 4) return false;
    double m = 0, sx = 0, se = 0, ss = 0, sxx = 0, sxe = 0, sxs = 0;
    for (std::size_t i = from; i < to; ++i) {
        const double x = rec.t[i] - rec.t[stop];
        m += 1, sx += x, se += rec.strain[i], ss += rec.stress[i], sxx += x * x, sxe += x * rec.strain[i], sxs += x * rec.stress[i];
    }
    const double den = m * sxx - sx * sx;
    if (!(den > 0)) return false;
    const double re = (m * sxe - sx * se) / den, ie = (se - re * sx) / m;  // strain = ie + re x
    const double rs = (m * sxs - sx * ss) / den, is = (ss - rs * sx) / m;  // stress = is + rs x
    double x = re != 0 ? (eHold - ie) / re : 0.0;
    x = std::clamp(x, rec.t[to - 1] - rec.t[stop], 0.0);
    tStop = rec.t[stop] + x;
    sStop = is + rs * x;
    return std::isfinite(sStop) && sStop > 0;
}

/// The lab recording's position holds (from each hold's first sample), in order. With `stopFromRamp`
/// the hold's clock starts where the piston stopped and its stress at the start is the ramp's there
/// (rampStop; a stress lost within a sample or two of the stop, as a viscous one, has gone before the
/// hold's first sample), else at its first sample, with the stress of its own first samples.
std::vector<LabHold> labHolds(const Recording& rec, bool stopFromRamp = false) {
    std::vector<LabHold> lab;
    const std::vector<PhaseSegment> phases = detectPhases(rec.t, rec.strain);
    const std::vector<RateChange> changes = stopFromRamp ? speedChanges(rec.t, rec.strain, rec.stress) : std::vector<RateChange>{};
    for (std::size_t q = 0; q < phases.size(); ++q) {
        const PhaseSegment& found = phases[q];
        if (found.phase != Phase::Hold || found.end - found.begin < 5) continue;
        // from the hold's first sample (holdExtent): the DEM hold curves start where the piston stops,
        // and a lab hold started a few samples late has already lost the fast part of its relaxation,
        // which the DEM curve would then take off a second time
        const PhaseSegment seg = holdExtent(rec.strain, found);
        LabHold h;
        for (std::size_t i = seg.begin; i < seg.end; ++i) {
            h.t.push_back(rec.t[i] - rec.t[seg.begin]);
            h.s.push_back(rec.stress[i]);
        }
        // the stress at the start: the first sample where the start is exact (the mean of the first
        // three would already hold part of the fast relaxation), else the mean of three against noise
        const double eh = rec.strain[seg.end - 1];
        const bool exact = atHoldStrain(rec.strain[seg.begin], eh);
        h.s0 = exact ? h.s[0] : (h.s[0] + h.s[1] + h.s[2]) / 3;
        h.tStart = rec.t[seg.begin];
        double tStop, sStop;
        if (stopFromRamp && q > 0 && phases[q - 1].phase != Phase::Hold && rampStop(rec, phases[q - 1], seg.begin, eh, changes, tStop, sStop)) {
            for (double& t : h.t) t += rec.t[seg.begin] - tStop;
            h.s0 = sStop;
            h.tStart = tStop;
        }
        lab.push_back(std::move(h));
    }
    return lab;
}

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
    d.heldoutBaseline = d.runs[0].heldoutRmse;
    d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
    d.status = "done";
    writeHoldComparison(ctx, lab, all);
    return ctx.finish();
}

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

/// Time, strain and stress columns of a DEM run's record.
void readDemSeries(const std::string& base, std::vector<double>& t, std::vector<double>& e, std::vector<double>& s) {
    const recording::Recording rec = recording::readRecording(base + ".recording.csv");
    const int ct = rec.column("time_s"), cs = rec.column("axial_stress_Pa"), ce = rec.column("axial_strain");
    if (ct < 0 || cs < 0 || ce < 0) inputError(base + ".recording.csv: missing time_s/axial_strain/axial_stress_Pa");
    for (const auto& row : rec.rows) {
        t.push_back(row[static_cast<std::size_t>(ct)]);
        e.push_back(row[static_cast<std::size_t>(ce)]);
        s.push_back(row[static_cast<std::size_t>(cs)]);
    }
}

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
    d.heldoutBaseline = d.runs[0].heldoutRmse;
    d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
    d.status = "done";
    writeHoldComparison(ctx, lab, all);
    return ctx.finish();
}

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

/// dem/comparison.csv (and .png) of a branch confirmation: every lab branch sample, the reloads held out.
void writeBranchComparison(const DemContext& ctx, const std::vector<Branch>& lab, const std::vector<std::vector<Branch>>& all) {
    std::vector<Compared> rows;
    for (std::size_t k = 0; k < lab.size(); ++k) {
        std::vector<std::vector<double>> pred;
        for (const auto& run : all) pred.push_back(branchPredict(lab, run, k));
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
        if (byTransmission) d.runs[q].heldoutBottomRmse = branchRmse(lab, all[q], held, true);
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
    d.heldoutBaseline = d.runs[0].heldoutRmse;
    d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
    d.heldoutBottomBaseline = d.runs[0].heldoutBottomRmse;
    d.heldoutBottomAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutBottomRmse;
    d.status = "done";
    writeBranchComparison(ctx, lab, all);
    return ctx.finish();
}

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

/// Samples at the top of an unload branch: the leading run with y >= 0.8 (the unloading tangent's window).
std::size_t topSamples(const Branch& br) {
    std::size_t top = 0;
    while (top < br.y.size() && br.y[top] >= 0.8) ++top;
    return top;
}

/// Curvature of the unload branches in `which`: the unloading tangent at the top (least-squares slope
/// of y on u over the samples with y >= 0.8) over the secant from the top to where y first reaches
/// yLow, averaged over the branches. A straight unloading gives 1; Hertzian contacts, whose stiffness
/// falls with the force, a larger value (the same estimator on the lab and on the DEM record).
double unloadCurvature(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yLow) {
    double sum = 0;
    int n = 0;
    for (std::size_t k : which) {
        if (k >= b.size() || b[k].phase != Phase::Unload) continue;
        const Branch& br = b[k];
        const std::size_t top = topSamples(br);
        std::size_t low = top;
        while (low < br.y.size() && br.y[low] > yLow) ++low;
        if (top < 3 || low >= br.y.size() || !(br.u[low] > 0)) continue;
        const double tangent = -slope(br.u, br.y, 0, top);
        const double secant = (1 - br.y[low]) / br.u[low];
        if (tangent > 0 && secant > 0) sum += tangent / secant, ++n;
    }
    return n > 0 ? sum / n : -1;
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
    const auto score = [&](std::size_t q) {
        d.runs[q].calibrationRmse = branchRmse(lab, all[q], cal);
        d.runs[q].heldoutRmse = branchRmse(lab, all[q], held);
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
        // stress levels, else the curvature (which hardly tells the law)
        const double labExponent = unloadStiffnessExponent(lab);
        for (std::size_t q = 0; q < all.size(); ++q) d.runs[q].exponent = unloadStiffnessExponent(all[q]);
        d.judgedByExponent = std::isfinite(labExponent) && std::isfinite(d.runs[chosen].exponent) && std::isfinite(d.runs.back().exponent);
        if (std::isfinite(labExponent)) d.labExponent = labExponent;
        d.contactLawDistinguished =
            d.judgedByExponent
                ? std::abs(d.runs.back().exponent - labExponent) > std::abs(d.runs[chosen].exponent - labExponent) + kExponentMargin
                : std::abs(curv.back() - d.labMacro) > std::abs(curv[chosen] - d.labMacro) + kCurvatureMargin;
    } else {  // the control only qualifies the result: without it the law is not judged
        d.controlNote = "the control run dem_linear_control failed or does not pair with the recording (log: dem_linear_control.log)";
        d.runs.pop_back();
        all.pop_back();
        curv.pop_back();
    }
    d.heldoutBaseline = d.runs[0].heldoutRmse;
    d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
    d.status = "done";
    writeBranchComparison(ctx, lab, all);
    return ctx.finish();
}

} // namespace

namespace {
/// Mean contact force f = pi d^2 stress / (3 phi Z) of a poured bed of spheres of diameter d (N).
double meanContactForce(double d, double stress) { return std::numbers::pi * d * d * stress / (3 * kDemPackingPhiZ); }
} // namespace

double hertzModulusMatching(double k, double d, double stress) {
    const double delta = meanContactForce(d, stress) / k;  // the linear law's overlap
    return 3 * k / (4 * std::sqrt(0.25 * d * delta));      // (4/3) E* sqrt(R delta) delta = k delta, R = d/4
}

double unloadStiffnessExponent(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s) {
    return unloadStiffnessExponent(cycleBranches(t, e, s));
}

double hertzSecantStiffness(double modulus, double d, double stress) {
    const double f = meanContactForce(d, stress);
    const double delta = std::cbrt(std::pow(3 * f / (4 * modulus * std::sqrt(0.25 * d)), 2));  // f = (4/3) E* sqrt(R) delta^(3/2)
    return f / delta;
}

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

std::string defaultDemDriver() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "OedometerRelaxation";
    return (self.parent_path() / "OedometerRelaxation").string();
}

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

namespace {
/// The reason of a `not_supported` status.
std::string notWired(const std::string& mechanism) {
    return "the DEM re-run is implemented for contact_relaxation, plasticity, wall_friction, stiffness_nonlinearity, cohesion and "
           "rate_dependence; " +
           mechanism + " maps to a driver ingredient (Documentation/tools-explain.md) that is not wired yet";
}
} // namespace

DemResult confirmWithDem(const ExplainResult& r, const Recording& rec, const std::string& protocolPath,
                         const DemOptions& opt, const std::string& workDir) {
    DemResult d;
    if (opt.mode == "off") {
        d.reason = "switched off (--dem off)";
        return d;
    }
    if (r.mechanisms.empty()) {
        d.status = "not_needed";
        d.reason = "no mechanism was accepted, so there is nothing to add to the DEM model";
        return d;
    }
    recording::Protocol proto;
    std::string protoError;
    try {
        proto = recording::readProtocol(protocolPath);
    } catch (const InputError& e) {
        protoError = e.what();
    }
    // the first accepted mechanism with a DEM counterpart; wall_friction only when the protocol gives
    // the device's size (the mould's H/D), else a later one is preferred (it still gets its not_run
    // when it is the only one)
    const MechanismResult* m = nullptr;
    const MechanismResult* wallWithoutSize = nullptr;
    const MechanismResult* cohesionWithoutPull = nullptr;  // cohesion on a protocol without an unload into tension
    const MechanismResult* nonlinearity = nullptr;
    for (const auto& mr : r.mechanisms) {
        if (!demSupported(mr.comp)) continue;
        if (mr.comp == kCohesion && (!protoError.empty() || !pullsOnTheBed(proto))) {  // it would only say not_run
            if (!cohesionWithoutPull) cohesionWithoutPull = &mr;
            continue;
        }
        if (mr.comp == kNonlinearity) {  // last choice: every other ingredient changes the loading curve too
            if (!nonlinearity) nonlinearity = &mr;
            continue;
        }
        if (mr.comp == kWallFriction && !wallWithoutSize) {
            if (!protoError.empty() || !(proto.diameter > 0 && proto.height > 0)) {
                wallWithoutSize = &mr;
                continue;
            }
        }
        m = &mr;
        break;
    }
    if (!m) m = nonlinearity;
    if (!m) m = wallWithoutSize;
    if (!m) m = cohesionWithoutPull;
    if (!opt.mechanism.empty()) {  // the user's choice among the accepted mechanisms
        m = nullptr;
        for (const auto& mr : r.mechanisms)
            if (opt.mechanism == compName(mr.comp)) m = &mr;
        if (!m) {
            d.mechanism = opt.mechanism;
            d.reason = "--dem_mechanism " + opt.mechanism + " was not accepted by the explanation, so there is nothing to confirm";
            return d;
        }
        if (!demSupported(m->comp)) {
            d.status = "not_supported";
            d.mechanism = opt.mechanism;
            d.reason = notWired(d.mechanism);
            return d;
        }
    }
    if (!m) {
        d.status = "not_supported";
        d.mechanism = compName(r.mechanisms.front().comp);
        d.reason = notWired(d.mechanism);
        return d;
    }
    DemContext ctx{opt, opt.driver.empty() ? defaultDemDriver() : opt.driver, workDir, std::chrono::steady_clock::now(), d};
    if (protoError.empty()) ctx.protocol = &proto;
    ctx.protocolError = protoError;
    if (::access(ctx.driver.c_str(), X_OK) != 0) {
        d.status = "not_run";
        d.mechanism = compName(m->comp);
        d.reason = "driver executable not found: " + ctx.driver + " (give --dem_driver)";
        return d;
    }
    fs::create_directories(workDir);
    switch (m->comp) {
        case kRelaxation: return confirmRelaxation(ctx, *m, rec, protocolPath);
        case kPlasticity: return confirmPlasticity(ctx, *m, rec, protocolPath);
        case kNonlinearity: return confirmNonlinearity(ctx, *m, rec, protocolPath);
        case kCohesion: return confirmCohesion(ctx, rec, protocolPath);
        case kRate: return confirmRate(ctx, *m, rec, protocolPath);
        default: return confirmWallFriction(ctx, *m, rec, protocolPath);
    }
}

bool pullsOnTheBed(const recording::Protocol& p) {
    for (const recording::Step& st : p.steps)
        if (st.kind == recording::Step::Kind::Unload && st.targetStress < 0) return true;
    return false;
}

bool demSupported(int comp) {
    return comp == kRelaxation || comp == kPlasticity || comp == kWallFriction || comp == kNonlinearity || comp == kCohesion ||
           comp == kRate;
}

Json demJson(const DemResult& d) {
    Json j = Json::object();
    j.set("status", d.status);
    if (!d.reason.empty()) j.set("reason", d.reason);
    if (!d.mechanism.empty()) j.set("mechanism", d.mechanism);
    const auto num = [](double x) { return x >= 0 && std::isfinite(x) ? Json(x) : Json(); };
    const bool plastic = d.mechanism == "plasticity", wall = d.mechanism == "wall_friction";
    const bool hertz = d.mechanism == "stiffness_nonlinearity", coh = d.mechanism == "cohesion", branches = plastic || wall || hertz || coh;
    const bool rate = d.mechanism == "rate_dependence";
    const auto finite = [](double x) { return std::isfinite(x) ? Json(x) : Json(); };
    j.set("heldout_rmse_baseline", num(d.heldoutBaseline));
    j.set("heldout_rmse_augmented", num(d.heldoutAugmented));
    if (d.status == "done") {
        j.set("heldout_reduction", d.heldoutBaseline > 0 ? Json(1 - d.heldoutAugmented / d.heldoutBaseline) : Json());
        j.set(branches ? "calibration_branches" : "calibration_holds", d.calibrationHolds);
        j.set(branches ? "heldout_branches" : "heldout_holds", d.heldoutHolds);
        j.set("chosen_run", d.runs[static_cast<std::size_t>(d.chosen)].name);
        if (branches) j.set("stress_scale", d.stressScale);
        if (rate) {
            j.set("recording_hold_drop_calibration_holds", finite(d.labMacro));
            j.set("recording_speed_changes", d.rateChanges);
            j.set("recording_speed_change_step", finite(d.labRateStep));
        } else if (!branches) {  // contact_relaxation: the probe that decides whether run b's contacts relax in the ramps
            j.set("run_a_hold_t0_over_contact_t0", num(d.rampAgedT0Ratio));
            j.set("ramp_aged_t0_ratio_threshold", kRampAgedT0Ratio);
        }
        if (plastic || wall) {
            j.set("recording_unload_stiffness_ratio_calibration_branches", num(d.labMacro));
            j.set("unload_ratio_min_y", d.ratioYMin);
        }
        if (coh) j.set("recording_tension_over_start_stress_calibration_branches", num(d.labMacro));
        if (hertz) {
            j.set("surrogate_exponent_n", num(d.surrogateValue));
            if (d.control >= 0) {
                j.set("control_run", d.runs[static_cast<std::size_t>(d.control)].name);
                j.set("contact_law_distinguished", d.contactLawDistinguished);
                j.set("contact_law_judged_by", d.judgedByExponent ? "unload_stiffness_exponent" : "unload_curvature");
            } else if (!d.controlNote.empty()) {
                j.set("control_note", d.controlNote);
            }
            if (std::isfinite(d.labExponent)) j.set("recording_unload_stiffness_exponent", d.labExponent);
        }
        if (wall) {
            j.set("mould_diameter_m", d.mouldDiameter);
            j.set("mould_height_m", d.mouldHeight);
            j.set("recording_aspect_ratio_H_over_D", d.recordingAspect);
        }
    }
    if (branches && !d.calibration.empty()) j.set("calibration", d.calibration);
    if (hertz && d.labMacro > 0) {
        j.set("recording_unload_curvature_calibration_branches", d.labMacro);
        j.set("curvature_secant_to_y", d.ratioYMin);
    }
    if (d.labTransmission > 0) j.set("recording_bottom_over_piston_loading", d.labTransmission);
    if (d.transmissionTarget > 0) j.set("bottom_over_piston_target", d.transmissionTarget);
    if (d.heldoutBottomBaseline >= 0) {
        j.set("heldout_bottom_rmse_baseline", num(d.heldoutBottomBaseline));
        j.set("heldout_bottom_rmse_augmented", num(d.heldoutBottomAugmented));
    }
    Json runs = Json::array();
    for (const DemRun& r : d.runs) {
        Json o = Json::object({{"name", r.name}});
        if (hertz) {
            o.set("hertz_modulus_Pa", r.hertzModulus);
            o.set("normal_stiffness_scale", r.normalStiffnessScale);
            if (std::isfinite(r.exponent)) o.set("dem_unload_stiffness_exponent", r.exponent);
            o.set("dem_unload_curvature_calibration_branches", num(r.macro));
        } else if (coh) {
            o.set("kc_over_k", r.kcOverK);
            o.set("wall_kc_over_k", r.kcOverK);
            o.set("dem_tension_over_start_stress_calibration_branches", num(r.macro));
        } else if (branches) {
            if (plastic) o.set("k_over_k1", r.kOverK1);
            else o.set("wall_friction", r.wallFriction);
            if (d.calibration == "bottom_over_piston_secant") o.set("dem_bottom_over_piston_loading", num(r.transmission));
            o.set("dem_unload_stiffness_ratio_calibration_branches", num(r.macro));
        } else if (rate) {
            o.set("contact_viscous_time_s", r.viscTime);
            o.set("dem_hold_drop_calibration_holds", finite(r.macro));
            o.set("dem_speed_change_step", finite(r.rateStep));
        } else {
            o.set("relax_C", r.relaxC);
            o.set("relax_t0_s", r.relaxT0);
            o.set("relax_in_ramps", r.relaxInRamps);
            o.set("dem_macroscopic_C_calibration_holds", num(r.macro));
        }
        o.set("calibration_rmse_Pa", num(r.calibrationRmse));
        o.set("heldout_rmse_Pa", num(r.heldoutRmse));
        if (r.heldoutBottomRmse >= 0) o.set("heldout_bottom_rmse_Pa", r.heldoutBottomRmse);
        o.set("command", r.command);
        runs.push(o);
    }
    j.set("runs", runs);
    return j;
}

namespace {
/// printf into a string.
__attribute__((format(printf, 1, 2))) std::string formatted(const char* format, ...) {
    va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(static_cast<std::size_t>(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(out.data(), out.size(), format, again);
    va_end(again);
    out.pop_back();
    return out;
}
} // namespace

// The paragraph: what was re-run (shared opening), how the ingredient was set (the mechanism's
// middle), and the held-out errors of the two runs (shared ending).
std::string demMarkdown(const DemResult& d) {
    std::ostringstream os;
    os << "\n## DEM confirmation\n\n";
    if (d.status != "done") {
        os << "Status: " << d.status << (d.reason.empty() ? "" : " — " + d.reason) << ".\n";
        return os.str();
    }
    const DemRun& a = d.runs[static_cast<std::size_t>(d.chosen)];
    const double change = d.heldoutBaseline > 0 ? 100 * (1 - d.heldoutAugmented / d.heldoutBaseline) : 0.0;
    const bool branches = d.mechanism != "contact_relaxation" && d.mechanism != "rate_dependence";  // else holds
    const std::string scaled = formatted(" (stresses scaled by %.4g into the material's range", d.stressScale);
    const auto mould = [&] {
        return formatted(" in a mould D = %.3g m across and H = %.3g m high (H/D %.3g; the recording's %.3g), every bed poured "
                         "with frictionless walls, once with frictionless walls and with wall friction mu_w = %.4g",
                         d.mouldDiameter, d.mouldHeight, d.mouldHeight / d.mouldDiameter, d.recordingAspect, a.wallFriction);
    };
    const char* units = "Compared in units of each branch's start stress and loading stiffness, on ";
    os << "The OedometerRelaxation driver was re-run on this protocol";
    std::string without, with, extra;  // the two runs in the ending, and what follows their errors
    if (d.mechanism == "plasticity") {
        os << scaled << "), once with an elastic contact law (Luding k/k1 = 1) and once with plastic contacts "
           << formatted("(k/k1 = %.4g, calibrated on %d unload/reload branch(es) to the recording's unloading stiffness ratio "
                        "%.3g; the DEM gives %.3g). %sthe %d branch(es) the calibration did not see",
                        a.kOverK1, d.calibrationHolds, d.labMacro, a.macro, units, d.heldoutHolds);
        without = "elastic contacts", with = "plastic ones";
    } else if (d.mechanism == "cohesion") {
        os << scaled << "; Luding's law with the material's plasticity), once without adhesion and once with adhesive contacts "
           << formatted("and sticky walls (kc/k = %.3g for the particle pairs and the walls, of %zu values the one with the smallest "
                        "error on %d unload branch(es); largest tension over the start stress: recording %.3g, "
                        "DEM %.3g with adhesion, %.3g without). %sthe %d reload branch(es) the choice did not see",
                        a.kcOverK, d.runs.size() - 1, d.calibrationHolds, d.labMacro, a.macro, d.runs.front().macro, units,
                        d.heldoutHolds);
        without = "no adhesion", with = "adhesion";
    } else if (d.mechanism == "stiffness_nonlinearity") {
        os << scaled << "; the non-cohesive frictional material), once with linear elastic contacts and with Hertzian ones, "
           << formatted("whose stiffness falls with the force: E* = %.4g Pa (of %zu values), calibrated on %d unload branch(es) "
                        "to the recording's unloading curvature (tangent at the top over the secant to %.0f %% of the start "
                        "stress: recording %.3g, Hertzian DEM %.3g, linear DEM %.3g). %sthe %d reload branch(es) the "
                        "calibration did not see",
                        a.hertzModulus, d.runs.size() - (d.control >= 0 ? 2 : 1), d.calibrationHolds, 100 * d.ratioYMin, d.labMacro, a.macro,
                        d.runs.front().macro, units, d.heldoutHolds);
        without = "linear contacts", with = "Hertzian ones";
    } else if (d.mechanism == "wall_friction" && d.calibration == "bottom_over_piston_secant") {
        const std::string atMould = d.transmissionTarget > 0 && std::abs(d.transmissionTarget - d.labTransmission) > 1e-9 * d.labTransmission
                                        ? formatted(", %.3g at the mould's H/D", d.transmissionTarget)
                                        : "";
        os << scaled << ")" << mould()
           << formatted(", calibrated so that the bottom plate carries the share of the piston stress the recording's bottom "
                        "sensor shows on first loading (recording %.3g%s; DEM %.3g with friction, %.3g without; %zu runs with "
                        "friction, secant on its logarithm). On the %d reload branch(es), compared in units of each branch's "
                        "start stress and loading stiffness,",
                        d.labTransmission, atMould.c_str(), a.transmission, d.runs.front().transmission, d.runs.size() - 1,
                        d.heldoutHolds);
        without = "frictionless walls", with = "wall friction";
        if (d.heldoutBottomBaseline >= 0 && d.heldoutBottomAugmented >= 0)
            extra = formatted("; the bottom stress on the same branches by %.4g Pa and %.4g Pa", d.heldoutBottomBaseline,
                              d.heldoutBottomAugmented);
    } else if (d.mechanism == "wall_friction") {
        os << scaled << ")" << mould()
           << formatted(" (of %zu values around max(2 muK, %.2g) = %.3g, the one with the smallest error on %d unload "
                        "branch(es)). %sthe %d branch(es) the choice did not see",
                        d.runs.size() - 1, kMinWallFrictionGuess, d.runs.size() > 1 ? d.runs[1].wallFriction : 0.0,
                        d.calibrationHolds, units, d.heldoutHolds);
        without = "frictionless walls", with = "wall friction";
    } else if (d.mechanism == "rate_dependence") {
        os << formatted(", once with the standard contact law and once with a contact viscosity on the lab clock (viscous time "
                        "%.4g lab s, of %zu values the one with the smaller error on %d hold(s); the stress lost over the last third "
                        "of those holds: recording %.3g, DEM %.3g with the viscosity, %.3g without)",
                        a.viscTime, d.runs.size() - 1, d.calibrationHolds, d.labMacro, a.macro, d.runs.front().macro);
        if (d.rateChanges > 0)
            os << formatted(". Where the loading speed changes without a stop (%d change(s)), the stress steps by %.3g of the stress "
                            "there in the recording, %.3g with the viscosity and %.3g without (model-free: straight lines either "
                            "side; not used in the choice)",
                            d.rateChanges, d.labRateStep, a.rateStep, d.runs.front().rateStep);
        os << formatted(". On the %d hold(s) the calibration did not see,", d.heldoutHolds);
        without = "viscosity", with = "it";
    } else {
        os << formatted(", once with the standard contact law and once with contact relaxation switched on (contact C = "
                        "%.4g, t0 = %.4g s, calibrated on %d hold(s); the contacts relaxing %s",
                        a.relaxC, a.relaxT0, d.calibrationHolds, a.relaxInRamps ? "in the ramps as well as in the holds" : "in the holds only");
        if (d.rampAgedT0Ratio > kRampAgedT0Ratio)
            os << formatted(": with relaxation in the ramps too, the DEM holds relaxed on a time scale %.3g times t0, the contacts "
                            "aged by the ramp", d.rampAgedT0Ratio);
        os << formatted("). On the %d hold(s) the calibration did not see,", d.heldoutHolds);
        without = "relaxation", with = "it";
    }
    os << (branches ? " the DEM misses" : " the DEM hold curves miss") << " the recording by "
       << formatted("%.4g Pa (RMS) %s %s and %.4g Pa with %s (%.1f %% %s)", d.heldoutBaseline, branches ? "with" : "without",
                    without.c_str(), d.heldoutAugmented, with.c_str(), std::abs(change), change >= 0 ? "lower" : "higher")
       << extra << ".";
    if (d.mechanism == "wall_friction" && d.calibration != "bottom_over_piston_secant")
        os << formatted(" Unloading ratio over the top %.0f %% of the unloads: recording %.3g, chosen run %.3g, frictionless %.3g.",
                        100 * (1 - d.ratioYMin), d.labMacro, a.macro, d.runs.front().macro);
    if (!d.controlNote.empty()) os << " The contact law was not judged: " << d.controlNote << ".";
    if (d.control >= 0) {
        const DemRun& c = d.runs[static_cast<std::size_t>(d.control)];
        const bool byExponent = d.judgedByExponent;
        os << formatted(" A control run with linear contacts as soft as the chosen Hertzian ones at the top stress (normal "
                        "stiffness x %.3g) unloads with curvature %.3g (held-out %.4g Pa)",
                        c.normalStiffnessScale, c.macro, c.heldoutRmse);
        if (byExponent)
            os << formatted("; the unloading stiffness grows with the stress it unloads from as stress^%.2f in the recording, "
                            "^%.2f with the Hertzian contacts and ^%.2f with the linear control",
                            d.labExponent, d.runs[static_cast<std::size_t>(d.chosen)].exponent, c.exponent);
        os << ": ";
        if (d.contactLawDistinguished)
            os << (byExponent ? "the control is clearly further from the recording, so the record needs the Hertzian force law."
                              : "clearly further from the recording's, so the curvature needs the Hertzian force law.");
        else if (byExponent)
            os << "the control is about as close to the recording, so the record does not tell Hertz's force law from a linear "
                  "one that soft (the bulk nonlinearity is confirmed, the contact law is not).";
        else
            os << "about as close to the recording's, so the record shows contacts that are soft under the load; it does not "
                  "tell Hertz's force law from a linear one that soft (the bulk nonlinearity is confirmed, the contact law is "
                  "not; unloads from two stress levels at least a factor "
               << fmt(kExponentStressRatio) << " apart would judge it by how the unloading stiffness grows with the stress).";
    }
    os << " Runs, commands and logs are in `dem/`.\n";
    return os.str();
}

} // namespace pdpm::explain
