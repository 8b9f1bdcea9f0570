// pdpm-explain-bench: the blind benchmark. Generates cases (recording + protocol in cases/, truth
// sealed in truth/), runs the explainer on each (reports/), then scores every report against its
// truth and writes summary.md, power.csv and scores.csv (one row per case).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "Cli.h"
#include "Core/Error.h"
#include "Core/Parameters.h"
#include "DemCases.h"
#include "Explain.h"
#include "ExplainBench.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"
#include "IO/NumberFormat.h"

using namespace pdpm;
using namespace pdpm::explain;

namespace {
struct Job {
    std::string name;
    CaseSpec spec;
    bool forced = false;
};
} // namespace

int main(int argc, char** argv) {
    return tools::runTool("pdpm-explain-bench", [&] {
        tools::Cli cli("pdpm-explain-bench", "blind benchmark of pdpm-explain: generate, explain, score");
        std::string out, snrText, mechText;
        int reps = 5, nulls = 40, samples = 2000, seed = 1, forced = 10, extras = 5, pairs = 0;
        std::string pairSnrText, demSnrText, demDriverArgs, demFamiliesText;
        int demCases = 0;
        bool calibrated = false;
        double bicThreshold = 10;
        cli.add("output", &out, "", "output directory");
        cli.add("reps", &reps, 5, "positive cases per mechanism and SNR", 0, 100000);
        cli.add("nulls", &nulls, 40, "null cases", 0, 100000);
        cli.add("forced", &forced, 10, "null cases with a forced addition (control)", 0, 100000);
        cli.add("extras", &extras, 5, "two-mechanism and out-of-library cases of each kind", 0, 100000);
        cli.add("samples", &samples, 2000, "samples per recording", 100, 1000000);
        cli.add("seed", &seed, 1, "base seed", 0, 1000000);
        cli.add("snr", &snrText, "1,2,3,5", "peak SNR values of the positive cases");
        cli.add("pairs", &pairs, 0, "several-recordings benchmark: pairs per mechanism and SNR (0: skip)", 0, 100000);
        cli.add("pair_snr", &pairSnrText, "3,5", "peak SNR values of the same-material pairs");
        cli.add("mechanisms", &mechText,
                "contact_relaxation,plasticity,cohesion,wall_friction,rate_dependence,stiffness_nonlinearity",
                "mechanisms of the positive cases");
        cli.add("dem_cases", &demCases, 0, "DEM-made cases: positive cases per family of --dem_families and SNR of --dem_snr, each with its null twin (0: skip; each runs the OedometerRelaxation driver, about a minute per run)", 0, 100000);
        cli.add("dem_families", &demFamiliesText, "contact_relaxation", "families of the DEM-made cases: contact_relaxation, wall_friction, creep (contact relaxation in creep steps), cohesion (lift-off test), rate_dependence (contact viscosity) (comma separated)");
        cli.add("dem_snr", &demSnrText, "3,5", "peak SNR values of the DEM-made positive cases");
        cli.add("dem_driver_args", &demDriverArgs, "", "extra OedometerRelaxation arguments of the DEM-made cases (e.g. '--width 4 --fill_height 5')");
        cli.add("calibrated_compliance", &calibrated, false,
                "give the explainer each case's instrument compliance, as a lab's calibration run would "
                "(cases/NAME/model.json); default: blind, the compliance is fitted as a nuisance");
        cli.add("bic_threshold", &bicThreshold, 10.0, "-",
                "the explainer's acceptance threshold dBIC (MODEL.json bic_threshold), to measure its trade-off "
                "between detection and false alarms", 2.0, 1e6);
        if (!cli.parse(argc, argv, std::cout)) return 0;
        if (out.empty()) inputError("--output is required");
        const auto snrs = tools::parseNumberList("snr", snrText);
        const auto pairSnrs = tools::parseNumberList("pair_snr", pairSnrText);  // checked before the long run
        const auto demSnrs = tools::parseNumberList("dem_snr", demSnrText);
        for (const auto& [flag, list] : {std::pair{"snr", &snrs}, {"pair_snr", &pairSnrs}, {"dem_snr", &demSnrs}})
            for (double v : *list)
                if (!(v > 0 && v <= 1e6)) inputError(std::string("--") + flag + ": " + formatDoubleShort(v) + " is not a SNR in (0, 1e6]");
        // comma- or space-separated words
        const auto words = [](std::string text) {
            for (char& c : text)
                if (c == ',') c = ' ';
            std::istringstream is(text);
            std::vector<std::string> w;
            for (std::string x; is >> x;) w.push_back(x);
            return w;
        };
        const std::vector<std::string> demFamilies = words(demFamiliesText);  // checked here, before the long run
        for (const std::string& w : demFamilies) checkDemCaseFamily(w, "--dem_families");
        const std::vector<std::string> mechs = words(mechText);
        if (pairs > 0 && (mechs.empty() || pairSnrs.empty())) inputError("--pairs needs --mechanisms and --pair_snr");
        const double rhos[3] = {0.0, 0.5, 0.9};
        std::vector<Job> jobs;
        unsigned long s = (unsigned long)seed * 100000;
        auto add = [&](const std::string& kind, double snr, int k, bool f = false) {
            Job j;
            j.spec = {kind, snr, rhos[k % 3], ++s, samples};
            std::ostringstream nm;
            std::string kk = kind;
            for (char& c : kk)
                if (c == ':' || c == '+') c = '_';
            nm << (f ? "forced_" : "") << kk << "_snr" << snr << "_" << k;
            j.name = nm.str();
            j.forced = f;
            jobs.push_back(j);
        };
        for (int k = 0; k < nulls; ++k) add("null", 0, k);
        for (int k = 0; k < forced; ++k) add("null", 0, k, true);
        for (const auto& m : mechs)
            for (double snr : snrs)
                for (int k = 0; k < reps; ++k) add(m, snr, k);
        for (int k = 0; k < extras; ++k) {
            add("two:contact_relaxation+plasticity", 5, k);
            add("ool:bump", 5, k);
            add("ool:sine", 5, k);
        }
        if (jobs.empty() && pairs == 0 && demCases == 0)
            inputError("no cases to run (--reps, --nulls, --forced, --extras, --pairs and --dem_cases are all 0, or --mechanisms is empty)");
        ensureDirectory(out + "/cases");
        ensureDirectory(out + "/truth");
        ensureDirectory(out + "/reports");
        std::vector<CaseScore> scores(jobs.size());
        std::vector<std::string> errors(jobs.size());
#pragma omp parallel for schedule(dynamic, 1)
        for (long i = 0; i < long(jobs.size()); ++i) {
            const Job& j = jobs[std::size_t(i)];
            try {
                const std::string cdir = out + "/cases/" + j.name, tpath = out + "/truth/" + j.name + ".json";
                const GeneratedCase g = generateCase(j.spec);
                writeCase(g, cdir, tpath);
                if (calibrated) {  // the instrument's calibration is an input of the case, like its protocol
                    Json mj = Json::object();
                    mj.set("instrument_compliance_ratio", g.truth.at("baseline_and_nuisances").at("compliance_ratio").asNumber());
                    writeJsonFile(cdir + "/model.json", mj);
                } else {
                    std::remove((cdir + "/model.json").c_str());  // left by an earlier calibrated run into this folder
                }
                // the explainer sees only the case directory
                const Protocol proto = readProtocol(cdir + "/protocol.json");
                const Recording rec = readRecording(cdir + "/recording.csv", proto);
                ExplainOptions opt;
                if (calibrated) readModelFile(cdir + "/model.json", opt);
                opt.figures = false;
                opt.forceBest = j.forced;
                opt.bicThreshold = bicThreshold;
                const ExplainResult r = pdpm::explain::explain(rec, proto, opt);
                writeReport(out + "/reports/" + j.name, r, rec, proto, opt);
                // the scorer reads the report and the sealed truth
                scores[std::size_t(i)] = scoreCase(readJsonFile(out + "/reports/" + j.name + "/report.json"), readJsonFile(tpath));
            } catch (const std::exception& e) {
                errors[std::size_t(i)] = e.what();
            }
        }
        for (std::size_t i = 0; i < jobs.size(); ++i)
            if (!errors[i].empty()) inputError("case " + jobs[i].name + ": " + errors[i]);

        // ---- summary ----
        int nNull = 0, fa = 0, nForced = 0;
        double forcedGainMax = -1e9, forcedGainSum = 0;
        std::map<double, std::pair<int, int>> power;  // snr -> detected, total
        std::map<std::string, std::map<double, std::pair<int, int>>> powerM;
        int det = 0, correct = 0, iouOk = 0, parN = 0, parOk = 0, parIdOk = 0, gainN = 0, gainOk = 0, exGainOk = 0, covN = 0, covOk = 0;
        double iouSum = 0;
        int ool = 0, oolOk = 0, two = 0, twoDet = 0, twoBoth = 0;
        std::map<std::string, std::map<std::string, int>> confusion;
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const CaseScore& c = scores[i];
            if (jobs[i].forced) {
                ++nForced;
                forcedGainMax = std::max(forcedGainMax, c.heldoutGain);
                forcedGainSum += c.heldoutGain;
                continue;
            }
            if (c.outOfLibrary) {
                ++ool;
                oolOk += c.verdict == "unexplained";
                continue;
            }
            if (!c.positive) {
                ++nNull;
                fa += c.detected;
                continue;
            }
            if (c.truthKind.rfind("two:", 0) == 0) {
                ++two;
                twoDet += c.detected;
                twoBoth += c.correctMechanism;
                continue;
            }
            auto& pw = power[c.snr];
            pw.second++;
            pw.first += c.detected;
            auto& pm = powerM[c.truthKind][c.snr];
            pm.second++;
            pm.first += c.detected;
            if (c.detected) {
                ++det;
                correct += c.correctMechanism;
                iouOk += c.iou >= 0.7;
                if (c.snr >= 5 && c.paramRelError >= 0) {
                    ++parN;
                    parOk += c.paramRelError <= 0.25;
                    parIdOk += c.paramRelErrorIdentifiable <= 0.25;
                }
                if (c.paramCovered >= 0) {
                    ++covN;
                    covOk += c.paramCovered;
                }
                ++gainN;
                gainOk += c.heldoutGain >= 0.3;
                exGainOk += c.heldoutExcessGain >= 0.3;
                iouSum += c.iou;
            }
            std::string got = c.verdict == "missing_physics" || c.verdict == "ambiguous" ? "" : c.verdict;
            if (got.empty()) {
                const Json rep = readJsonFile(out + "/reports/" + jobs[i].name + "/report.json");
                const auto& ms = rep.at("mechanisms").asArray();
                got = ms.empty() ? c.verdict : ms.front().at("name").asString();
                if (c.ambiguous) got += " (ambiguous)";
            }
            confusion[c.truthKind][got]++;
        }
        std::ostringstream md;
        md << "Benchmark: " << jobs.size() << " cases, " << samples << " samples each, noise AR(1) with rho in {0, 0.5, 0.9} "
           << "(cycled), quantisation sigma/2, instrument compliance and sensor drift present in every case"
           << (calibrated ? "; the explainer is given each case's instrument compliance (a calibrated instrument)" : "")
           << (bicThreshold != 10 ? "; acceptance threshold dBIC >= " + fmt(bicThreshold) + " (default 10)" : std::string())
           << ".\n\n";
        md << "| figure | target | measured |\n|---|---|---|\n";
        md << "| false 'missing physics' (any verdict but no_missing_physics) on null cases | <= 5 % | " << countShare(fa, nNull) << " |\n";
        for (auto& [snr, pr] : power)
            md << "| detection at peak SNR " << snr << " | " << (snr >= 5 ? ">= 98 %" : snr >= 3 ? ">= 90 %" : "-") << " | "
               << countShare(pr.first, pr.second) << " |\n";
        md << "| correct mechanism among detections | >= 90 % | " << countShare(correct, det) << " |\n";
        md << "| window IoU >= 0.7 among detections | >= 90 % | " << countShare(iouOk, det) << " |\n";
        md << "| window IoU, mean over detections | - | " << std::fixed << std::setprecision(2) << (det ? iouSum / det : 0.0)
           << std::defaultfloat << " |\n";
        md << "| primary parameter within 25 % (detections, SNR >= 5) | >= 90 % | " << countShare(parOk, parN) << " |\n";
        if (!calibrated)  // with a calibrated compliance the identifiable value is the true one
            md << "| primary parameter within 25 % of what one record can identify (plasticity: lambda seen through the unknown "
              "instrument compliance, lambda (1 + kappa) / (1 + lambda kappa); detections, SNR >= 5) | - | "
           << countShare(parIdOk, parN) << " |\n";
        md << "| primary parameter's 95 % interval holds the truth (detections, all SNR) | - | " << countShare(covOk, covN) << " |\n";
        md << "| held-out error reduced >= 30 % (detections) | >= 30 % reduction when truly missing | " << countShare(gainOk, gainN) << " |\n";
        md << "| held-out error above the noise level reduced >= 30 % (detections) | - | " << countShare(exGainOk, gainN) << " |\n";
        md << "| forced addition on null cases: held-out gain (mean / max) | <= 2 % | ";
        if (nForced > 0)
            md << std::setprecision(3) << 100 * forcedGainSum / nForced << " % / " << 100 * forcedGainMax << " % (" << nForced << " cases) |\n";
        else
            md << "- (0 cases) |\n";
        md << "| two mechanisms (relaxation + plasticity, SNR 5): detected / both named | - | " << countShare(twoDet, two) << " / "
           << countShare(twoBoth, two) << " |\n";
        md << "| out-of-library effects answered 'unexplained' | - | " << countShare(oolOk, ool) << " |\n\n";
        md << "Power curve (detections / cases) per mechanism and peak SNR:\n\n" << snrGrid(powerM, snrs);
        md << "\nConfusion (truth -> first reported mechanism or verdict):\n\n| truth | answers |\n|---|---|\n";
        for (auto& [t, row] : confusion) {
            md << "| " << t << " |";
            for (auto& [g, k] : row) md << " " << g << ": " << k << ";";
            md << " |\n";
        }
        if (pairs > 0)
            md << "\n" << (calibrated ? "(The pairs below are blind: --calibrated_compliance applies to the single cases only.)\n" : "")
               << pairBenchmark(pairs, mechs, pairSnrs, samples,
                                        (unsigned long)seed);
        if (demCases > 0) md << "\n" << demCaseBenchmark(demCases, demSnrs, samples, (unsigned long)seed, out, demDriverArgs, demFamilies);
        writeWholeFile(out + "/summary.md", md.str());
        std::ostringstream pc;
        pc << "snr,detected,cases\n";
        for (auto& [snr, pr] : power) pc << snr << ',' << pr.first << ',' << pr.second << '\n';
        writeWholeFile(out + "/power.csv", pc.str());
        // every case's score, for looking into what the summary counts (e.g. which detections
        // miss the window IoU of 0.7); the parameter columns and heldout_excess_gain are -1 where
        // they do not apply; iou is 0 for a case without a detected window
        std::ostringstream sc;
        sc << std::setprecision(6) << "name,kind,snr,rho,forced,verdict,detected,correct_mechanism,ambiguous,iou,"
           << "param_rel_error,param_rel_error_identifiable,param_covered,heldout_gain,heldout_excess_gain\n";
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const CaseScore& c = scores[i];
            sc << jobs[i].name << ',' << jobs[i].spec.kind << ',' << jobs[i].spec.snr << ',' << jobs[i].spec.rho << ','
               << int(jobs[i].forced) << ',' << c.verdict << ',' << int(c.detected) << ',' << int(c.correctMechanism) << ','
               << int(c.ambiguous) << ',' << c.iou << ',' << c.paramRelError << ',' << c.paramRelErrorIdentifiable << ','
               << c.paramCovered << ',' << c.heldoutGain << ',' << c.heldoutExcessGain << '\n';
        }
        writeWholeFile(out + "/scores.csv", sc.str());
        std::cout << md.str();
        return 0;
    });
}
