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

namespace fs = std::filesystem;

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

double holdPredict(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, std::size_t k, std::size_t i) {
    return lab[k].s0 * interpolate(dem[k], lab[k].t[i]);
}

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

double slope(const std::vector<double>& x, const std::vector<double>& y, std::size_t i0, std::size_t i1) {
    const double n = static_cast<double>(i1 - i0);
    double mx = 0, my = 0;
    for (std::size_t i = i0; i < i1; ++i) mx += x[i], my += y[i];
    mx /= n, my /= n;
    double sxy = 0, sxx = 0;
    for (std::size_t i = i0; i < i1; ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxx > 0 ? sxy / sxx : 0;
}

std::vector<Branch> cycleBranches(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                  const std::vector<double>& bottom) {
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

bool samePhases(const std::vector<Branch>& lab, const std::vector<Branch>& dem) {
    if (lab.size() != dem.size()) return false;
    for (std::size_t k = 0; k < lab.size(); ++k)
        if (lab[k].phase != dem[k].phase) return false;
    return true;
}

double branchAt(const std::vector<std::pair<double, double>>& uy, double u) {
    if (uy.empty()) return 0;
    if (u <= uy.front().first) return uy.front().second;
    if (u >= uy.back().first) return uy.back().second;
    const auto it = std::upper_bound(uy.begin(), uy.end(), std::make_pair(u, -std::numeric_limits<double>::infinity()));
    const auto& [u1, y1] = *it;
    const auto& [u0, y0] = *(it - 1);
    return u1 > u0 ? y0 + (y1 - y0) * (u - u0) / (u1 - u0) : y1;
}

std::vector<double> branchPredict(const std::vector<Branch>& lab, const std::vector<Branch>& dem, std::size_t k, BranchJudge judge) {
    const bool bottom = judge == BranchJudge::BottomStress;
    if (bottom && (dem[k].b.size() != dem[k].u.size() || lab[k].b.size() != lab[k].u.size())) return {};
    std::vector<std::pair<double, double>> uy;
    for (std::size_t i = 0; i < dem[k].u.size(); ++i) uy.emplace_back(dem[k].u[i], bottom ? dem[k].b[i] / dem[k].sRef : dem[k].y[i]);
    std::sort(uy.begin(), uy.end());
    std::vector<double> out;
    if (judge == BranchJudge::StressFromStart) {
        if (lab[k].u.empty() || dem[k].u.empty()) return {};
        const double uLab0 = lab[k].u.front(), uDem0 = dem[k].u.front(), yDem0 = branchAt(uy, uDem0);
        for (double u : lab[k].u) out.push_back(lab[k].s.front() + lab[k].sRef * (branchAt(uy, uDem0 + (u - uLab0)) - yDem0));
        return out;
    }
    for (double u : lab[k].u) out.push_back(lab[k].sRef * branchAt(uy, u));
    return out;
}

double branchRmse(const std::vector<Branch>& lab, const std::vector<Branch>& dem, const std::vector<std::size_t>& which,
                  BranchJudge judge) {
    const bool bottom = judge == BranchJudge::BottomStress;
    double ss = 0;
    std::size_t n = 0;
    for (std::size_t k : which) {
        if (k >= dem.size()) return -1;
        const std::vector<double> pred = branchPredict(lab, dem, k, judge);
        if (pred.size() != lab[k].u.size()) return -1;
        for (std::size_t i = 0; i < pred.size(); ++i) {
            const double err = (bottom ? lab[k].b[i] : lab[k].s[i]) - pred[i];
            ss += err * err;
            ++n;
        }
    }
    return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : -1;
}

double unloadRatio(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yMin) {
    double suy = 0, suu = 0;
    for (std::size_t k : which) {
        if (k >= b.size() || b[k].phase != Phase::Unload) continue;
        for (std::size_t i = 0; i < b[k].u.size(); ++i)
            if (b[k].y[i] >= yMin) suy += b[k].u[i] * (1 - b[k].y[i]), suu += b[k].u[i] * b[k].u[i];
    }
    return suu > 0 ? suy / suu : -1;
}

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

std::vector<LabHold> labHolds(const Recording& rec, bool stopFromRamp) {
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

} // namespace pdpm::explain::dem
