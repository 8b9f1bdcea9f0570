#include "DemConfirmation.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "Recording.h"

namespace pdpm::explain {

namespace {

namespace fs = std::filesystem;

std::string defaultDriver() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "OedometerRelaxation";
    return (self.parent_path() / "OedometerRelaxation").string();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// One hold of the lab recording: time since its start and stress.
struct LabHold {
    std::vector<double> t, s;
    double s0 = 0;
};

/// Hold curves of a DEM run, normalised: g(t) = sigma(t)/sigma(0), t from the clock start.
struct DemHold {
    std::vector<double> t, g;
    double fitC = -1;
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
    const Json proto = readJsonFile(base + ".protocol.json");
    const recording::Recording rec = recording::readRecording(base + ".recording.csv");
    const int ct = rec.column("time_s"), cs = rec.column("axial_stress_Pa"), cstep = rec.column("step");
    if (ct < 0 || cs < 0 || cstep < 0) inputError(base + ".recording.csv: missing time_s/axial_stress_Pa/step");
    std::vector<DemHold> out;
    const Json* extra = proto.find("extra");
    const Json* holds = extra ? extra->find("holds") : nullptr;
    if (!holds) return out;
    for (const Json& h : holds->asArray("extra.holds")) {
        if (h.at("type").asString() != "hold_position") continue;
        const double step = h.at("step").asNumber(), t0 = h.at("lab_start_s").asNumber(), s0 = h.at("stress_start_Pa").asNumber();
        DemHold d;
        d.fitC = h.find("fit_C") && h.at("fit_C").isNumber() ? h.at("fit_C").asNumber() : -1;
        d.t.push_back(0);
        d.g.push_back(1);
        for (const auto& row : rec.rows)
            if (row[static_cast<std::size_t>(cstep)] == step && row[static_cast<std::size_t>(ct)] > t0) {
                d.t.push_back(row[static_cast<std::size_t>(ct)] - t0);
                d.g.push_back(s0 > 0 ? row[static_cast<std::size_t>(cs)] / s0 : 1);
            }
        out.push_back(std::move(d));
    }
    return out;
}

/// RMSE (Pa) of the DEM prediction over the lab holds with index in `which`.
double holdRmse(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, const std::vector<std::size_t>& which) {
    double ss = 0;
    std::size_t n = 0;
    for (std::size_t k : which) {
        if (k >= dem.size()) return -1;
        for (std::size_t i = 0; i < lab[k].t.size(); ++i) {
            const double e = lab[k].s[i] - lab[k].s0 * interpolate(dem[k], lab[k].t[i]);
            ss += e * e;
            ++n;
        }
    }
    return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : -1;
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
    const MechanismResult* relax = nullptr;
    for (const auto& m : r.mechanisms)
        if (m.comp == kRelaxation) relax = &m;
    if (!relax) {
        d.status = "not_supported";
        d.mechanism = compName(r.mechanisms.front().comp);
        d.reason = "the DEM re-run is implemented for contact_relaxation only; " + d.mechanism +
                   " maps to a driver ingredient (Documentation/tools-explain.md) that is not wired yet";
        return d;
    }
    d.mechanism = "contact_relaxation";
    double C = -1, t0 = -1;
    for (std::size_t q = 0; q < relax->params.size(); ++q) {
        if (relax->params[q] == pRelaxC) C = relax->value[q];
        if (relax->params[q] == pRelaxT0) t0 = relax->value[q];
    }
    if (!(C > 0) || !(t0 > 0)) {
        d.status = "failed";
        d.reason = "the accepted contact_relaxation term has no positive C and t0";
        return d;
    }

    // lab holds, alternately calibration and held-out
    std::vector<LabHold> lab;
    for (const PhaseSegment& seg : detectPhases(rec.t, rec.strain)) {
        if (seg.phase != Phase::Hold || seg.end - seg.begin < 5) continue;
        LabHold h;
        for (std::size_t i = seg.begin; i < seg.end; ++i) {
            h.t.push_back(rec.t[i] - rec.t[seg.begin]);
            h.s.push_back(rec.stress[i]);
        }
        h.s0 = (h.s[0] + h.s[1] + h.s[2]) / 3;
        lab.push_back(std::move(h));
    }
    std::vector<std::size_t> cal, held;
    for (std::size_t k = 0; k < lab.size(); ++k) (k % 2 == 0 ? cal : held).push_back(k);
    if (held.empty()) {
        d.status = "not_run";
        d.reason = "the recording has fewer than two holds: no held-out hold to score the DEM re-run on";
        return d;
    }
    d.calibrationHolds = static_cast<int>(cal.size());
    d.heldoutHolds = static_cast<int>(held.size());

    const std::string driver = opt.driver.empty() ? defaultDriver() : opt.driver;
    if (::access(driver.c_str(), X_OK) != 0) {
        d.status = "not_run";
        d.reason = "driver executable not found: " + driver + " (give --dem_driver)";
        return d;
    }
    fs::create_directories(workDir);
    const auto tStart = std::chrono::steady_clock::now();
    auto runDem = [&](const std::string& name, double relaxC) -> std::vector<DemHold> {
        DemRun run;
        run.name = name;
        run.relaxC = relaxC;
        run.relaxT0 = t0;
        std::ostringstream cmd;
        cmd << quote(driver) << " --protocol_file " << quote(protocolPath) << " --relax_C " << fmt(relaxC) << " --relax_t0 "
            << fmt(t0) << " --output " << quote(workDir) << " --name " << name << " --threads " << opt.threads
            << " --quiet --vtk 0 --ene 0";
        // the FT4 mould with the driver's ft4 preset (without its protocol: the recording's is used)
        if (opt.mode == "ft4")
            cmd << " --geometry cylinder --device ft4 --diameter 0.05 --fill_height_m 0.05 --hold_tau 0.005 --ramp_rate 1";
        run.command = cmd.str();
        const auto t1 = std::chrono::steady_clock::now();
        const int rc = std::system((run.command + " > " + quote(workDir + "/" + name + ".log") + " 2>&1").c_str());
        run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        d.runs.push_back(run);
        if (rc != 0) return {};
        return readDemHolds(workDir + "/" + name);
    };
    const auto fail = [&](const std::string& why) {
        d.status = "failed";
        d.reason = why;
        d.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tStart).count();
        return d;
    };
    const std::vector<DemHold> base = runDem("dem_baseline", 0);
    if (base.size() < lab.size()) return fail("baseline DEM run failed or has fewer holds than the recording (log: dem_baseline.log)");
    const std::vector<DemHold> augA = runDem("dem_relax_a", C);
    if (augA.size() < lab.size()) return fail("augmented DEM run failed (log: dem_relax_a.log)");
    double macroA = 0;
    int nA = 0;
    for (std::size_t k : cal)
        if (augA[k].fitC > 0) macroA += augA[k].fitC, ++nA;
    macroA = nA > 0 ? macroA / nA : C;
    const double C2 = C * C / macroA;
    const std::vector<DemHold> augB = runDem("dem_relax_b", C2);
    if (augB.size() < lab.size()) return fail("augmented DEM run failed (log: dem_relax_b.log)");
    double macroB = 0;
    int nB = 0;
    for (std::size_t k : cal)
        if (augB[k].fitC > 0) macroB += augB[k].fitC, ++nB;

    const std::vector<const std::vector<DemHold>*> all = {&base, &augA, &augB};
    for (std::size_t q = 0; q < all.size(); ++q) {
        d.runs[q].calibrationRmse = holdRmse(lab, *all[q], cal);
        d.runs[q].heldoutRmse = holdRmse(lab, *all[q], held);
    }
    d.runs[1].macroC = macroA;
    d.runs[2].macroC = nB > 0 ? macroB / nB : -1;
    d.chosen = d.runs[2].calibrationRmse < d.runs[1].calibrationRmse ? 2 : 1;
    d.heldoutBaseline = d.runs[0].heldoutRmse;
    d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
    d.status = "done";
    d.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tStart).count();
    return d;
}

Json demJson(const DemResult& d) {
    Json j = Json::object();
    j.set("status", d.status);
    if (!d.reason.empty()) j.set("reason", d.reason);
    if (!d.mechanism.empty()) j.set("mechanism", d.mechanism);
    const auto num = [](double x) { return x >= 0 && std::isfinite(x) ? Json(x) : Json(); };
    j.set("heldout_rmse_baseline", num(d.heldoutBaseline));
    j.set("heldout_rmse_augmented", num(d.heldoutAugmented));
    if (d.status == "done") {
        j.set("heldout_reduction", d.heldoutBaseline > 0 ? Json(1 - d.heldoutAugmented / d.heldoutBaseline) : Json());
        j.set("calibration_holds", d.calibrationHolds);
        j.set("heldout_holds", d.heldoutHolds);
        j.set("chosen_run", d.runs[static_cast<std::size_t>(d.chosen)].name);
    }
    Json runs = Json::array();
    for (const DemRun& r : d.runs)
        runs.push(Json::object({{"name", r.name},
                                {"relax_C", r.relaxC},
                                {"relax_t0_s", r.relaxT0},
                                {"dem_macroscopic_C_calibration_holds", num(r.macroC)},
                                {"calibration_rmse_Pa", num(r.calibrationRmse)},
                                {"heldout_rmse_Pa", num(r.heldoutRmse)},
                                {"command", r.command}}));
    j.set("runs", runs);
    return j;
}

std::string demMarkdown(const DemResult& d) {
    std::ostringstream os;
    os << "\n## DEM confirmation\n\n";
    if (d.status != "done") {
        os << "Status: " << d.status << (d.reason.empty() ? "" : " — " + d.reason) << ".\n";
        return os.str();
    }
    const DemRun& a = d.runs[static_cast<std::size_t>(d.chosen)];
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "The OedometerRelaxation driver was re-run on this protocol, once with the standard contact law and "
                  "once with contact relaxation switched on (contact C = %.4g, t0 = %.4g s, calibrated on %d hold(s)). "
                  "On the %d hold(s) the calibration did not see, the DEM hold curves miss the recording by %.4g Pa (RMS) "
                  "without relaxation and %.4g Pa with it (%.1f %% lower). Runs, commands and logs are in `dem/`.\n",
                  a.relaxC, a.relaxT0, d.calibrationHolds, d.heldoutHolds, d.heldoutBaseline, d.heldoutAugmented,
                  d.heldoutBaseline > 0 ? 100 * (1 - d.heldoutAugmented / d.heldoutBaseline) : 0.0);
    os << buf;
    return os.str();
}

} // namespace pdpm::explain
