#include "ExplainBench.h"

#include "Recording.h"

#include <filesystem>
#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

#include "Ar1Noise.h"
#include "Core/Error.h"
#include "Explain.h"
#include "ExplainModel.h"
#include "SeveralRecordings.h"
#include "IO/AtomicFile.h"

namespace pdpm::explain {

namespace {

struct Seg {
    double e0, e1, dur;
};

std::vector<std::pair<double, double>> effectWindows(const std::vector<double>& t, const std::vector<double>& d) {
    double mx = 0;
    for (double x : d) mx = std::max(mx, std::abs(x));
    std::vector<std::pair<double, double>> w;
    if (mx <= 0) return w;
    for (std::size_t i = 0; i < d.size();) {
        if (std::abs(d[i]) < 0.2 * mx) { ++i; continue; }
        std::size_t j = i;
        while (j < d.size() && std::abs(d[j]) >= 0.2 * mx) ++j;
        if (j - i >= 3) w.push_back({t[i], t[j - 1]});
        i = j;
    }
    return w;
}

} // namespace

GeneratedCase generateCase(const CaseSpec& spec) {
    std::mt19937_64 rng(spec.seed * 0x9E3779B97F4A7C15ULL + 12345);
    std::uniform_real_distribution<double> U(0, 1);
    auto uni = [&](double a, double b) { return a + (b - a) * U(rng); };
    std::mt19937_64 rngMat(spec.materialSeed * 0xBF58476D1CE4E5B9ULL + 4242);
    auto matU = [&] { return spec.materialSeed ? U(rngMat) : U(rng); };
    auto matUni = [&](double a, double b) { return a + (b - a) * matU(); };
    GeneratedCase g;
    Protocol& P = g.proto;
    const bool ft4 = U(rng) < 0.5;
    P.device = ft4 ? "FT4 (generated)" : "lambdameter (generated)";
    P.diameter = ft4 ? 0.05 : 0.149;
    P.height = ft4 ? 0.05 : 0.06;
    P.material = "generated";
    P.source = "protocol.json";

    std::vector<std::string> mechs;
    std::string ool;
    const bool isOol = spec.kind.rfind("ool:", 0) == 0;
    if (spec.kind.rfind("two:", 0) == 0) {
        const std::string rest = spec.kind.substr(4);
        const auto plus = rest.find('+');
        if (plus == std::string::npos || rest.find('+', plus + 1) != std::string::npos)
            inputError("generator: kind '" + spec.kind + "' must name two mechanisms, two:A+B");
        mechs = {rest.substr(0, plus), rest.substr(plus + 1)};
        if (mechs[0] == mechs[1]) inputError("generator: kind '" + spec.kind + "' names " + mechs[0] + " twice");
    } else if (isOol) {
        ool = spec.kind.substr(4);
    } else if (spec.kind != "null") {
        mechs = {spec.kind};
    }
    for (const auto& m : mechs)
        if (compFromName(m) < 0 || !isMechanism(compFromName(m)) || compFromName(m) == kRolling)
            inputError("generator: unknown or untestable mechanism '" + m + "'");
    if (isOol && ool != "bump" && ool != "sine") inputError("generator: unknown out-of-library effect '" + ool + "' (bump or sine)");
    const bool hasCoh = std::find(mechs.begin(), mechs.end(), "cohesion") != mechs.end();

    // true baseline
    const double E = std::pow(10.0, matUni(5, 7));
    const double epsTop = uni(0.03, 0.15);
    const double e0 = uni(0.0, 0.15) * epsTop;
    const double rate = uni(0.02e-3, 0.1e-3) / P.height;
    const int K = 3 + int(U(rng) * 3);
    const double hold = uni(60, 300);
    double tension = 0;
    // (with a material seed the material constants must not depend on the protocol: reference strain 0.08)
    if (hasCoh) tension = matUni(0.03, 0.1) * E * (spec.materialSeed ? 0.08 : epsTop - e0);
    std::vector<Seg> segs;
    double e = 0;
    for (int k = 1; k <= K; ++k) {
        const double ek = e0 + (epsTop - e0) * k / K;
        segs.push_back({e, ek, (ek - e) / rate});
        P.steps.push_back({StepType::Ramp, rate * P.height, -1, (ek - e) / rate});
        segs.push_back({ek, ek, hold});
        P.steps.push_back({StepType::Hold, -1, -1, hold});
        e = ek;
    }
    // Lift-off test (unload below the contact strain and hold there): always for cohesion cases,
    // where it is the segment the tension branch needs, and in 30 % of the other cases, so that the
    // protocol does not give the truth away. Drawn from a separate stream so that the parameters
    // of the other cases do not change.
    std::mt19937_64 rngLift(spec.seed * 0xD1B54A32D192ED03ULL + 777);
    const bool liftOff = hasCoh || U(rngLift) < 0.3;
    const double liftDepth = hasCoh ? 1.5 * tension / E : 1.5 * (0.03 + 0.07 * U(rngLift)) * (epsTop - e0);
    const double partial = hasCoh ? 0.0 : uni(0.05, 0.3);  // drawn as before the lift-off option
    const double eu = liftOff ? e0 - liftDepth : e0 + partial * (epsTop - e0);
    segs.push_back({e, eu, (e - eu) / rate});
    P.steps.push_back({StepType::Unload, rate * P.height, -1, (e - eu) / rate});
    if (liftOff) {  // lift-off test: hold in tension at the bottom of the unloading
        segs.push_back({eu, eu, 0.5 * hold});
        P.steps.push_back({StepType::Hold, -1, -1, 0.5 * hold});
    }
    segs.push_back({eu, e, (e - eu) / rate});
    P.steps.push_back({StepType::Ramp, rate * P.height, -1, (e - eu) / rate});
    segs.push_back({e, e, 0.5 * hold});
    P.steps.push_back({StepType::Hold, -1, -1, 0.5 * hold});
    double T = 0;
    for (const auto& s : segs) T += s.dur;

    Recording& R = g.rec;
    const int n = spec.samples;
    R.t.resize(std::size_t(n));
    R.strain.resize(std::size_t(n));
    R.source = "recording.csv";
    R.strainSource = "axial_strain";
    for (int i = 0; i < n; ++i) {
        const double t = T * i / (n - 1);
        double acc = 0, ev = segs.back().e1;
        for (const auto& s : segs) {
            if (t <= acc + s.dur) {
                ev = s.e0 + (s.e1 - s.e0) * (s.dur > 0 ? (t - acc) / s.dur : 1);
                break;
            }
            acc += s.dur;
        }
        R.t[std::size_t(i)] = t;
        R.strain[std::size_t(i)] = std::round(ev / 1e-7) * 1e-7;
    }
    R.stress.resize(R.t.size());
    for (std::size_t i = 0; i < R.t.size(); ++i) R.stress[i] = E * std::max(R.strain[i] - e0, 0.0) + 1;
    const Model M(makeModelInput(R, P));
    std::vector<double> p = M.defaults();
    p[pE] = E;
    p[pEps0] = e0;
    const double smaxGuess = E * (epsTop - e0);
    p[pKappa] = uni(0, 0.1);
    p[pOffset] = uni(-0.01, 0.01) * smaxGuess;
    p[pDrift] = uni(-0.01, 0.01) * smaxGuess / T;
    std::vector<char> on(kNumComp, 0);
    on[kBaseline] = on[kCompliance] = on[kDrift] = 1;
    Json tp = Json::object();
    std::string primaryName;
    double primaryValue = 0, primaryOff = 0;
    std::vector<double> yWithout;
    M.evaluate(p, on, yWithout);
    std::vector<double> minEffect;
    double minMaxEffect = 1e300;
    for (const auto& mname : mechs) {
        const int c = compFromName(mname);
        std::vector<double> q = p;
        switch (c) {
        case kRelaxation:
            q[pRelaxC] = matUni(0.02, 0.08);
            q[pRelaxT0] = std::pow(10.0, matUni(-1, 0.7));
            break;
        case kPlasticity: q[pLambda] = matUni(2, 10); break;
        case kCohesion: q[pTension] = tension; break;
        case kWallFriction: q[pMuK] = matUni(0.05, 0.3); break;
        case kRate:  // a viscous time; with a material seed a constant of the material (2-20 s), not of the ramp
            q[pTauV] = spec.materialSeed ? matUni(2, 20) : matUni(0.01, 0.05) * smaxGuess / (E * rate);
            break;
        case kNonlinearity: q[pExpN] = matU() < 0.5 ? matUni(1.3, 2.0) : matUni(0.6, 0.8); break;
        default: break;
        }
        std::vector<char> onm = on;
        onm[c] = 1;
        std::vector<double> ym;
        M.evaluate(q, onm, ym);
        double mx = 0;
        for (std::size_t i = 0; i < ym.size(); ++i) mx = std::max(mx, std::abs(ym[i] - yWithout[i]));
        minMaxEffect = std::min(minMaxEffect, mx);
        for (int k : M.paramsOf(c)) {
            p[k] = q[k];
            tp.set(M.defs()[k].name, q[k]);
        }
        if (primaryName.empty()) {
            const int pp = c == kRelaxation ? pRelaxC : c == kPlasticity ? pLambda : c == kCohesion ? pTension
                         : c == kWallFriction ? pMuK : c == kRate ? pTauV : pExpN;
            primaryName = M.defs()[pp].name;
            primaryValue = q[pp];
            primaryOff = M.defs()[pp].off;
        }
        on[c] = 1;
    }
    std::vector<double> yWith;
    M.evaluate(p, on, yWith);
    double smax = 0;
    for (double x : yWith) smax = std::max(smax, std::abs(x));
    double sigma;
    std::vector<double> effect(yWith.size());
    for (std::size_t i = 0; i < yWith.size(); ++i) effect[i] = yWith[i] - yWithout[i];
    if (!mechs.empty()) {
        sigma = minMaxEffect / spec.snr;
    } else {
        sigma = uni(0.002, 0.02) * smax;
        if (!ool.empty()) {
            const double A = spec.snr * sigma;
            const double tc = uni(0.2, 0.7) * T, w = T / 30;
            for (std::size_t i = 0; i < yWith.size(); ++i) {
                const double t = R.t[i];
                effect[i] = ool == "bump" ? A * std::exp(-(t - tc) * (t - tc) / (w * w)) : A * std::sin(2 * M_PI * t / (T / 5));
                yWith[i] += effect[i];
            }
        }
    }
    // AR(1) noise with marginal sd sigma, quantised at sigma/2
    std::normal_distribution<double> N(0, 1);
    Ar1Noise x = Ar1Noise::stationary(spec.rho, sigma, rng, N);
    const double q = sigma / 2;
    double e2 = 0, emx = 0;
    for (std::size_t i = 0; i < yWith.size(); ++i) {
        if (i > 0) x.next(rng, N);
        R.stress[i] = std::round((yWith[i] + x.x) / q) * q;
        e2 += effect[i] * effect[i];
        emx = std::max(emx, std::abs(effect[i]));
    }
    const double nEff = double(n) * (1 - spec.rho) / (1 + spec.rho);
    Json tr = Json::object();
    tr.set("kind", spec.kind);
    Json ms = Json::array();
    for (const auto& m : mechs) ms.push(Json(m));
    tr.set("mechanisms", ms);
    tr.set("out_of_library", !ool.empty());
    tr.set("parameters", tp);
    {
        Json nu = Json::object();
        for (int k : {pE, pEps0, pKappa, pOffset, pDrift}) nu.set(M.defs()[k].name, p[k]);
        tr.set("baseline_and_nuisances", nu);
    }
    if (!primaryName.empty()) {
        tr.set("primary_parameter", primaryName);
        tr.set("primary_value", primaryValue);
        tr.set("primary_off", primaryOff);
        if (primaryName == M.defs()[pLambda].name) {
            // a series instrument compliance kappa (strain kappa * stress / E) softens the loading
            // branch to E / (1 + kappa) and the unloading branch to lambda E / (1 + lambda kappa): from
            // one record with unknown kappa only the ratio of the two is identifiable
            const double k = p[pKappa];
            tr.set("primary_value_identifiable", primaryValue * (1 + k) / (1 + primaryValue * k));
            tr.set("primary_identifiable_definition",
                   "unload/load stiffness ratio seen through the instrument compliance: lambda (1 + kappa) / (1 + lambda kappa)");
        }
    }
    tr.set("snr_peak", spec.snr);
    tr.set("snr_integrated", emx > 0 ? std::sqrt(e2 * nEff / double(n)) / sigma : 0.0);
    tr.set("rho", spec.rho);
    tr.set("sigma_Pa", sigma);
    tr.set("seed", double(spec.seed));
    if (spec.materialSeed) tr.set("material_seed", double(spec.materialSeed));
    tr.set("samples", n);
    tr.set("duration_s", T);
    Json wraw = Json::array();
    for (auto [a, b] : effectWindows(R.t, effect)) wraw.push(Json::array({Json(a), Json(b)}));
    tr.set("windows_raw_effect", wraw);
    // where the mismatch is visible: the noise-free recording minus the best baseline (+ nuisances)
    // fit to it, i.e. what the baseline cannot imitate by re-tuning its own parameters
    Json wj = Json::array();
    if (!mechs.empty() || !ool.empty()) {
        std::vector<char> onB(kNumComp, 0);
        onB[kBaseline] = onB[kCompliance] = onB[kDrift] = 1;
        FitOptions fo;
        fo.freeParams = freeParamsFor(M, onB);
        std::vector<double> start = p;
        for (int c = kRelaxation; c <= kLastMechanism; ++c)
            for (int k : M.paramsOf(c))
                if (!std::isnan(M.defs()[k].off)) start[k] = M.defs()[k].off;
        {  // the same estimator as the explainer: GLS with the (here: true) noise model
            NoiseModel tn;
            tn.rho = spec.rho;
            tn.arVar = sigma * sigma;
            tn.whiteVar = (sigma / 2) * (sigma / 2) / 12;  // quantisation
            fo.whitener = tn.whitener();
        }
        const FitResult fb = fitModel(M, yWith, onB, start, fo);
        std::vector<double> vis(yWith.size());
        for (std::size_t i = 0; i < vis.size(); ++i) vis[i] = yWith[i] - fb.model[i];
        Json ws = Json::array();
        for (auto [a, b] : effectWindows(R.t, vis)) ws.push(Json::array({Json(a), Json(b)}));
        tr.set("windows_visible_samplewise", ws);
        // the true affected window, at the granularity a powder engineer reads a test (and the tool
        // reports): the protocol phases carrying a comparable part of the visible mismatch energy
        const auto phases = detectPhases(R.t, R.strain);
        std::vector<double> en(phases.size(), 0.0);
        for (std::size_t k = 0; k < phases.size(); ++k)
            for (std::size_t i = phases[k].begin; i < phases[k].end; ++i) en[k] += vis[i] * vis[i];
        const auto mark = selectMismatch(en);
        {  // diagnostics for the scorer's reader: the noise-free baseline fit and each phase's energy
            Json fbj = Json::object();
            for (int k : fo.freeParams) fbj.set(M.defs()[k].name, fb.p[k]);
            tr.set("visible_baseline_fit", fbj);
            Json pe = Json::array();
            for (std::size_t k = 0; k < phases.size(); ++k)
                pe.push(Json::array({Json(R.t[phases[k].begin]), Json(R.t[phases[k].end - 1]), Json(en[k])}));
            tr.set("visible_phase_energy_Pa2", pe);
        }
        for (std::size_t k = 0; k < phases.size(); ++k)
            if (mark[k]) wj.push(Json::array({Json(R.t[phases[k].begin]), Json(R.t[phases[k].end - 1])}));
    }
    tr.set("windows", wj);
    tr.set("windows_definition", "protocol phases carrying at least 30 % of the largest phase's visible mismatch energy and 5 % of the total (visible: noise-free recording minus the best baseline + nuisance fit)");
    g.truth = tr;
    return g;
}

void writeRecordingCsv(const Recording& r, const std::string& path, const std::vector<std::string>& comments) {
    std::ostringstream os;
    for (const auto& c : comments) os << "# " << c << "\n";
    const bool step = r.step.size() == r.t.size() && !r.t.empty();
    os << "time_s," << (step ? "step," : "") << "axial_strain,axial_stress_Pa" << (r.lateral.empty() ? "" : ",lateral_stress_Pa")
       << (r.bottom.empty() ? "" : ",bottom_stress_Pa") << "\n";
    os << std::setprecision(12);
    for (std::size_t i = 0; i < r.t.size(); ++i) {
        os << r.t[i] << ',';
        if (step) os << r.step[i] << ',';
        os << r.strain[i] << ',' << r.stress[i];
        if (!r.lateral.empty()) os << ',' << r.lateral[i];
        if (!r.bottom.empty()) os << ',' << r.bottom[i];
        os << '\n';
    }
    writeWholeFile(path, os.str());
}

void writeProtocolJson(const Protocol& p, const std::string& path) {
    recording::writeProtocol(path, toRecordingProtocol(p));
}

void writeCase(const GeneratedCase& g, const std::string& caseDir, const std::string& truthPath) {
    // The truth first (after the case folder, which may hold it): if it cannot be written, no case
    // appears without it. If the case then fails, what this call wrote goes again, so that a failed
    // call leaves no half case behind (files of an earlier call are not touched before they are replaced).
    ensureDirectory(caseDir);
    writeJsonFile(truthPath, g.truth);
    bool recordingWritten = false;
    try {
        writeRecordingCsv(g.rec, caseDir + "/recording.csv", {"generated blind-benchmark case (pdpm-explain-data generate)"});
        recordingWritten = true;
        writeProtocolJson(g.proto, caseDir + "/protocol.json");
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(truthPath, ec);
        if (recordingWritten) std::filesystem::remove(caseDir + "/recording.csv", ec);
        throw;
    }
}

CaseScore scoreCase(const Json& report, const Json& truth) {
    CaseScore s;
    s.verdict = report.at("verdict").asString();
    s.truthKind = truth.at("kind").asString();
    s.snr = truth.at("snr_peak").asNumber();
    s.rho = truth.at("rho").asNumber();
    const auto& tm = truth.at("mechanisms").asArray();
    s.outOfLibrary = truth.at("out_of_library").asBool();
    s.positive = !tm.empty();
    s.ambiguous = s.verdict == "ambiguous";
    if (s.positive) s.detected = s.verdict == "missing_physics" || s.verdict == "ambiguous";
    else s.detected = s.verdict != "no_missing_physics";
    std::vector<std::string> found;
    for (const auto& m : report.at("mechanisms").asArray()) found.push_back(m.at("name").asString());
    if (s.ambiguous && report.has("ambiguous_with")) found.push_back(report.at("ambiguous_with").asString());
    if (s.positive && s.detected && !found.empty()) {
        // correct: every reported mechanism is true, and the first true one is found
        bool allTrue = true;
        for (const auto& f : found) {
            bool t = false;
            for (const auto& m : tm) t = t || m.asString() == f;
            if (!t && !(s.ambiguous && f == found.back())) allTrue = false;
        }
        bool firstFound = false;
        for (const auto& f : found) firstFound = firstFound || f == tm.front().asString();
        s.correctMechanism = allTrue && firstFound;
    }
    // window IoU on a fine time grid
    const double T = truth.at("duration_s").asNumber();
    const auto& tw = truth.at("windows").asArray();
    std::vector<std::pair<double, double>> pw;
    for (const auto& w : report.at("windows").asArray())
        if (w.at("mismatch").asBool()) pw.push_back({w.at("t_start_s").asNumber(), w.at("t_end_s").asNumber()});
    int inter = 0, uni = 0;
    const int G = 20000;
    for (int k = 0; k < G; ++k) {
        const double t = T * (k + 0.5) / G;
        bool a = false, b = false;
        for (const auto& w : tw) a = a || (t >= w.asArray()[0].asNumber() && t <= w.asArray()[1].asNumber());
        for (auto [x, y] : pw) b = b || (t >= x && t <= y);
        inter += a && b;
        uni += a || b;
    }
    s.iou = uni > 0 ? double(inter) / uni : 0;
    if (s.positive && truth.has("primary_parameter")) {
        const std::string pn = truth.at("primary_parameter").asString();
        const double tv = truth.at("primary_value").asNumber(), off = truth.at("primary_off").asNumber();
        for (const auto& m : report.at("mechanisms").asArray()) {
            const Json* pj = m.at("parameters").find(pn);
            if (pj && m.at("name").asString() == tm.front().asString()) {
                s.paramRelError = std::abs(pj->at("value").asNumber() - tv) / std::abs(tv - off);
                const double ti = truth.has("primary_value_identifiable") ? truth.at("primary_value_identifiable").asNumber() : tv;
                s.paramRelErrorIdentifiable = std::abs(pj->at("value").asNumber() - ti) / std::abs(ti - off);
                const auto& ci = pj->at("ci95").asArray();
                if (ci.size() == 2 && ci[0].isNumber() && ci[1].isNumber())
                    s.paramCovered = ci[0].asNumber() <= tv && tv <= ci[1].asNumber();
            }
        }
    }
    const Json& f = report.at("fit");
    const double hb = f.at("heldout_rmse_baseline").asNumber(), ha = f.at("heldout_rmse_augmented").asNumber();
    s.heldoutGain = hb > 0 ? 1 - ha / hb : 0;
    if (f.has("heldout_excess_rmse_baseline")) {
        const double eb = f.at("heldout_excess_rmse_baseline").asNumber(), ea = f.at("heldout_excess_rmse_augmented").asNumber();
        s.heldoutExcessGain = eb > 0 ? 1 - ea / eb : 0;
    } else {
        s.heldoutExcessGain = -1;
    }
    return s;
}

std::string countShare(int a, int b) {
    std::ostringstream os;
    os << a << "/" << b << " (" << std::fixed << std::setprecision(1) << (b ? 100.0 * a / b : 0.0) << " %)";
    return os.str();
}

std::string snrGrid(const std::map<std::string, std::map<double, std::pair<int, int>>>& table,
                    const std::vector<double>& snrs) {
    std::ostringstream md;
    md << "| mechanism |";
    for (double snr : snrs) md << " SNR " << snr << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < snrs.size(); ++k) md << "---|";
    md << "\n";
    for (const auto& [m, row] : table) {
        md << "| " << m << " |";
        for (double snr : snrs) {
            const auto it = row.find(snr);
            md << " " << (it == row.end() ? 0 : it->second.first) << "/" << (it == row.end() ? 0 : it->second.second) << " |";
        }
        md << "\n";
    }
    return md.str();
}

std::string pairBenchmark(int pairs, const std::vector<std::string>& mechanisms, const std::vector<double>& snrs,
                          int samples, unsigned long seed) {
    struct PairJob {
        std::string kind;  ///< mechanism, "null" or "contra:<mechanism>"
        double snr = 0;
        CaseSpec a, b;
    };
    if (mechanisms.empty() || snrs.empty()) inputError("pair benchmark: no mechanisms or no SNR values");
    const double rhos[3] = {0.0, 0.5, 0.9};
    std::vector<PairJob> jobs;
    unsigned long s = seed * 100000 + 50000;
    for (const auto& m : mechanisms)
        for (double snr : snrs)
            for (int k = 0; k < pairs; ++k) {
                const unsigned long mat = ++s;
                jobs.push_back({m, snr, {m, snr, rhos[k % 3], ++s, samples, mat}, {m, snr, rhos[(k + 1) % 3], ++s, samples, mat}});
            }
    for (int k = 0; k < pairs; ++k) {
        jobs.push_back({"null", 0, {"null", 0, rhos[k % 3], ++s, samples}, {"null", 0, rhos[(k + 1) % 3], ++s, samples}});
        const std::string& m = mechanisms[std::size_t(k) % mechanisms.size()];
        jobs.push_back({"contra:" + m, 5, {m, 5, rhos[k % 3], ++s, samples}, {"null", 0, rhos[(k + 1) % 3], ++s, samples}});
    }
    std::vector<SeveralResult> res(jobs.size());
    std::vector<std::string> errors(jobs.size());
    std::vector<std::pair<int, double>> primary(jobs.size(), {-1, 0.0});  // true primary parameter (index, value) of recording a
#pragma omp parallel for schedule(dynamic, 1)
    for (long i = 0; i < long(jobs.size()); ++i) {
        try {
            const GeneratedCase ga = generateCase(jobs[std::size_t(i)].a), gb = generateCase(jobs[std::size_t(i)].b);
            if (ga.truth.has("primary_parameter")) {
                const Model M(makeModelInput(ga.rec, ga.proto));
                for (std::size_t q = 0; q < M.defs().size(); ++q)
                    if (M.defs()[q].name == ga.truth.at("primary_parameter").asString())
                        primary[std::size_t(i)] = {int(q), ga.truth.at("primary_value").asNumber()};
            }
            ExplainOptions opt;
            opt.figures = false;
            res[std::size_t(i)] = explainSeveral({ga.rec, gb.rec}, {ga.proto, gb.proto}, opt);
        } catch (const std::exception& e) {
            errors[std::size_t(i)] = e.what();
        }
    }
    for (std::size_t i = 0; i < jobs.size(); ++i)
        if (!errors[i].empty()) inputError("pair " + std::to_string(i) + " (" + jobs[i].kind + "): " + errors[i]);
    auto statusOf = [](const SeveralResult& r, const std::string& m) -> std::string {
        for (std::size_t u = 0; u < r.mechanisms.size(); ++u)
            if (compName(r.mechanisms[u]) == m) return r.status[u];
        return "";
    };
    auto jointOf = [](const SeveralResult& r, const std::string& m) -> const JointFit* {
        for (const JointFit& J : r.joint)
            if (compName(J.comp) == m) return &J;
        return nullptr;
    };
    int nNull = 0, nullFalse = 0, nContra = 0, contraFlag = 0, contraJoint = 0, contraInconsistent = 0;
    // same-material pairs with a joint fit of the true mechanism: fits, consistent, interval holds the
    // truth, interval narrower than the narrower of the recordings' own (where both accepted it)
    // [0] fits, [1] consistent, [2] interval holds the truth, [3] interval determined, [4] both
    // recordings accepted it, [5] joint interval narrower among those
    std::map<std::string, std::array<int, 6>> jointBy;
    std::map<double, std::array<int, 5>> bySnr;  // pairs, named, confirmed, gain >= 30 %, excess gain >= 30 %
    std::map<std::string, std::map<double, std::pair<int, int>>> confirmedBy;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const PairJob& j = jobs[i];
        const SeveralResult& r = res[i];
        if (j.kind == "null") {
            ++nNull;
            nullFalse += r.verdict != "no_missing_physics";
        } else if (j.kind.rfind("contra:", 0) == 0) {
            ++nContra;
            contraFlag += statusOf(r, j.kind.substr(7)) != "confirmed";
            if (const JointFit* J = jointOf(r, j.kind.substr(7))) {
                ++contraJoint;
                contraInconsistent += !J->consistent;
            }
        } else {
            auto& c = bySnr[j.snr];
            const std::string st = statusOf(r, j.kind);
            c[0]++;
            c[1] += (r.verdict == "missing_physics" || r.verdict == "ambiguous") && !st.empty() && st != "not_transferable";
            c[2] += st == "confirmed";
            double gmin = 1, emin = 1;  // over every direction tested (both, for a pair where both found it)
            for (const auto& t : r.transfers)
                if (t.mechanisms.size() == 1 && compName(t.mechanisms[0]) == j.kind) {
                    gmin = std::min(gmin, t.gain());
                    emin = std::min(emin, t.excessGain());
                }
            c[3] += st == "confirmed" && gmin >= 0.3;
            c[4] += st == "confirmed" && emin >= 0.3;
            if (const JointFit* J = jointOf(r, j.kind)) {
                auto& jb = jointBy[j.kind];
                jb[0]++;
                jb[1] += J->consistent;
                const bool determined = J->intervalMethod != "not_determined";
                jb[3] += determined;
                for (std::size_t q = 0; q < J->joint.params.size(); ++q)
                    if (determined && J->joint.params[q] == primary[i].first)
                        jb[2] += J->joint.lo[q] <= primary[i].second && primary[i].second <= J->joint.hi[q];
                double ownWidth = std::numeric_limits<double>::infinity();
                int owners = 0;
                for (const ExplainResult& own : r.per)
                    for (const MechanismResult& m : own.mechanisms)
                        if (m.comp == J->comp && !m.params.empty()) {
                            ++owners;
                            ownWidth = std::min(ownWidth, m.hi[0] - m.lo[0]);
                        }
                if (owners == 2) {
                    jb[4]++;
                    jb[5] += J->joint.hi[0] - J->joint.lo[0] < ownWidth;
                }
            }
            auto& cb = confirmedBy[j.kind][j.snr];
            cb.second++;
            cb.first += st == "confirmed";
        }
    }
    std::ostringstream md;
    md << "Several recordings: " << jobs.size() << " pairs, " << samples << " samples per recording; a same-material "
       << "pair shares the material seed (stiffness and mechanism parameters); device, protocol, nuisances and noise "
       << "are drawn independently for each recording.\n\n| figure | measured |\n|---|---|\n";
    md << "| null pairs: any verdict but no_missing_physics | " << countShare(nullFalse, nNull) << " |\n";
    for (auto& [snr, c] : bySnr) {
        md << "| same-material pairs, peak SNR " << snr << ": mechanism named in the joint verdict | " << countShare(c[1], c[0]) << " |\n";
        md << "| same-material pairs, peak SNR " << snr << ": confirmed on the held-out recording | " << countShare(c[2], c[0]) << " |\n";
        md << "| same-material pairs, peak SNR " << snr << ": confirmed, held-out recording error -30 % or better in every direction tested | "
           << countShare(c[3], c[0]) << " |\n";
        md << "| same-material pairs, peak SNR " << snr << ": confirmed, held-out recording error above the noise -30 % "
           << "or better in every direction tested | " << countShare(c[4], c[0]) << " |\n";
    }
    md << "| contradicting pairs (mechanism in one recording, absent in the other's material): not confirmed | "
       << countShare(contraFlag, nContra) << " |\n\n";
    md << "Confirmed on the held-out recording, per mechanism and peak SNR:\n\n" << snrGrid(confirmedBy, snrs);
    md << "\nJoint material parameters (one set for both recordings, JointFit.h), same-material pairs with a joint "
       << "fit of the true mechanism, all SNR; the interval is the primary parameter's, against the generator's "
       << "true value (plasticity: the true lambda, which one instrument's unknown compliance hides):\n\n"
       << "| mechanism | joint fits | consistent (p >= " << kJointConsistencyLevel << ") | interval determined | "
       << "95 % interval holds the truth (determined ones) | narrower than either recording's own (pairs where both "
       << "accepted it) |\n|---|---|---|---|---|---|\n";
    for (const auto& [m, c] : jointBy)
        md << "| " << m << " | " << c[0] << " | " << countShare(c[1], c[0]) << " | " << countShare(c[3], c[0]) << " | "
           << countShare(c[2], c[3]) << " | " << countShare(c[5], c[4]) << " |\n";
    md << "\nContradicting pairs with a joint fit: " << countShare(contraInconsistent, contraJoint)
       << " say the two recordings need different values.\n";
    return md.str();
}

} // namespace pdpm::explain
