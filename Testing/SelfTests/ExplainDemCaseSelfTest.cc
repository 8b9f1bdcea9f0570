// pdpm-explain's DEM-made benchmark cases (Tools/Explain/DemCases.h) on a small bed (4 d x 4 d x 5 d,
// about 80 particles; the validation script uses the driver's default bed):
//  1. a contact_relaxation case at peak SNR 8: two DEM runs (with and without relaxation, the same
//     seed), the truth names the mechanism with the contact C in [0.02, 0.08] and the record's
//     macroscopic C between 0.3 and 1.1 times it; the noise sd is the peak of |with - without| over
//     the SNR, recomputed here from the two runs' own recordings; the truth windows are protocol
//     phases and the one with the largest share is a hold; the case folder is valid explainer input
//     and its MODEL.json puts stiffness_nonlinearity, plasticity and loading_curve into the baseline;
//  2. its null twin (same seed and work folder): the two runs are reused, the record is the run
//     without relaxation, with the same noise sd; no mechanism, no window;
//  3. with the driver executable changed (a copy of it whose modification time moves, as after a
//     rebuild) the runs are made again.
// About a minute of CPU (two small DEM runs); label heavy (left out of the sanitizer suite).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "DemCases.h"
#include "DemConfirmation.h"
#include "ExplainData.h"
#include "IO/Json.h"
#include "Recording.h"

using namespace pdpm;
using namespace pdpm::explain;

namespace {

bool check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    return ok;
}

/// (lab time, stress) of a driver recording.
void readRun(const std::string& path, std::vector<double>& t, std::vector<double>& s) {
    const recording::Recording rec = recording::readRecording(path);
    const int ct = rec.column("time_s"), cs = rec.column("axial_stress_Pa");
    for (const auto& row : rec.rows) t.push_back(row[static_cast<std::size_t>(ct)]), s.push_back(row[static_cast<std::size_t>(cs)]);
}

double interp(const std::vector<double>& t, const std::vector<double>& y, double x) {
    if (x <= t.front()) return y.front();
    if (x >= t.back()) return y.back();
    std::size_t k = 1;
    while (t[k] < x) ++k;
    const double w = (x - t[k - 1]) / (t[k] - t[k - 1]);
    return (1 - w) * y[k - 1] + w * y[k];
}

} // namespace

int main() {
    bool ok = true;
    std::filesystem::remove_all("runs_pos");  // runs left by an earlier ctest run would be reused
    // a copy of the driver, whose modification time the last check moves
    std::filesystem::copy_file(defaultDemDriver(), "driver_copy", std::filesystem::copy_options::overwrite_existing);
    DemCaseSpec spec;
    spec.driver = std::filesystem::absolute("driver_copy").string();
    spec.kind = "contact_relaxation";
    spec.snr = 8;
    spec.seed = 3;
    spec.samples = 600;
    spec.driverArgs = "--width 4 --fill_height 5";
    Json model;
    const GeneratedCase g = generateDemCase(spec, "runs_pos", model);
    writeCase(g, "case_pos", "truth_pos.json");
    const Json& tr = g.truth;
    const double C = tr.at("primary_value").asNumber(), Cm = tr.at("primary_value_identifiable").asNumber();
    std::printf("     contact C %.4g, macroscopic C %.4g, sigma %.4g Pa, %zu truth windows\n", C, Cm, tr.at("sigma_Pa").asNumber(),
                tr.at("windows").asArray().size());
    ok &= check(tr.at("source").asString() == "dem" && tr.at("mechanisms").asArray().size() == 1 &&
                    tr.at("mechanisms").asArray()[0].asString() == "contact_relaxation",
                "the truth names contact_relaxation (source dem)");
    ok &= check(C >= 0.02 && C <= 0.08, "contact C drawn in [0.02, 0.08]");
    ok &= check(Cm > 0.3 * C && Cm < 1.1 * C, "the record's macroscopic C is below the contact C, within a factor 0.3");
    {
        // the SNR definition, recomputed from the two DEM recordings
        std::vector<double> tw, sw, tn, sn;
        readRun("runs_pos/with.recording.csv", tw, sw);
        readRun("runs_pos/without.recording.csv", tn, sn);
        double peak = 0;
        const double T = tw.back() - tw.front();
        for (int i = 0; i < spec.samples; ++i) {
            const double t = tw.front() + T * i / (spec.samples - 1);
            peak = std::max(peak, std::abs(interp(tw, sw, t) - interp(tn, sn, t)));
        }
        ok &= check(std::abs(tr.at("sigma_Pa").asNumber() * spec.snr / peak - 1) < 1e-9, "noise sd = peak |with - without| / SNR");
    }
    {
        const Protocol p = readProtocol("case_pos/protocol.json");
        const Recording rec = readRecording("case_pos/recording.csv", p);
        checkConsistency(rec, p);  // throws on inconsistent input
        ok &= check(rec.size() == 600, "the case folder is valid explainer input (600 samples)");
        const auto phases = detectPhases(rec.t, rec.strain);
        const auto& ws = tr.at("windows").asArray();
        bool onPhases = !ws.empty(), holdAmong = false;
        for (const Json& w : ws) {
            const double a = w.asArray()[0].asNumber(), b = w.asArray()[1].asNumber();
            bool found = false;
            for (const auto& ph : phases)
                if (std::abs(rec.t[ph.begin] - a) < 1e-9 && std::abs(rec.t[ph.end - 1] - b) < 1e-9) {
                    found = true;
                    holdAmong |= ph.phase == Phase::Hold;
                }
            onPhases &= found;
        }
        ok &= check(onPhases && holdAmong, "truth windows are protocol phases, holds among them");
    }
    const auto& base = model.at("baseline").asArray();
    ok &= check(base.size() == 3 && base[0].asString() == "stiffness_nonlinearity" && base[1].asString() == "plasticity" &&
                    base[2].asString() == "loading_curve",
                "MODEL.json: the bed's stiffness_nonlinearity, plasticity and free loading curve are baseline");

    DemCaseSpec nul = spec;
    nul.kind = "null";
    Json m2;
    const auto stamp = std::filesystem::last_write_time("runs_pos/without.command");
    const GeneratedCase gn = generateDemCase(nul, "runs_pos", m2);
    ok &= check(gn.truth.at("mechanisms").asArray().empty() && gn.truth.at("windows").asArray().empty(), "null twin: no mechanism, no window");
    ok &= check(std::filesystem::last_write_time("runs_pos/without.command") == stamp, "null twin: the DEM runs are reused");
    ok &= check(gn.truth.at("sigma_Pa").asNumber() == tr.at("sigma_Pa").asNumber(), "null twin: the same noise sd");
    {
        std::vector<double> tn, sn;
        readRun("runs_pos/without.recording.csv", tn, sn);
        double worst = 0;  // the twin's record is the run without relaxation (to the noise)
        for (std::size_t i = 0; i < gn.rec.size(); ++i)
            worst = std::max(worst, std::abs(gn.rec.stress[i] - interp(tn, sn, tn.front() + gn.rec.t[i])));
        std::printf("     null twin: largest |record - run without relaxation| %.4g Pa (%.3g sd)\n", worst, worst / tr.at("sigma_Pa").asNumber());
        ok &= check(worst < 8 * tr.at("sigma_Pa").asNumber(), "null twin: its record is the run without relaxation plus noise");
    }
    std::filesystem::last_write_time("driver_copy", std::filesystem::last_write_time("driver_copy") + std::chrono::seconds(10));
    Json m3;
    generateDemCase(nul, "runs_pos", m3);
    ok &= check(std::filesystem::last_write_time("runs_pos/without.command") != stamp, "a rebuilt driver: the DEM runs are made again");
    return ok ? 0 : 1;
}
