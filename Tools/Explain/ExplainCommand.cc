#include <algorithm>
#include <iostream>
#include <sstream>

#include "Cli.h"
#include "Core/Error.h"
#include "DemConfirmation.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"
#include "Explain.h"
#include "SeveralRecordings.h"

namespace pdpm::explain {

int runExplainCommand(const std::vector<std::string>& args) {
    return tools::runTool("pdpm-explain", [&] {
        tools::Cli cli("pdpm-explain",
                       "Compares an oedometric recording with the baseline model of the same protocol, locates the "
                       "mismatch, names the missing physics from a mechanism library, refits and reports "
                       "(DIR/report.json, report.md, figures).");
        std::vector<std::string> recordings, protocols;
        std::string output, model;
        int seed = 1;
        bool noFigures = false;
        DemOptions dem;
        cli.addList("recording", &recordings,
                    "recording CSV (recording format: time_s, axial_stress_Pa, axial_strain or piston_position_m); "
                    "several recordings of one material: repeat the flag or list several files after it");
        cli.addList("protocol", &protocols,
                    "protocol JSON of the recording (one per recording, in the same order; one for all if they share it)");
        cli.add("output", &output, "", "output directory");
        cli.add("model", &model, "", "MODEL.json naming the baseline and the candidates (default: oedometric baseline, all mechanisms)");
        cli.add("seed", &seed, 1, "seed of the randomised restarts (results are deterministic for a seed)", 0, 2147483647);
        cli.add("no_figures", &noFigures, false, "do not run gnuplot");
        cli.add("dem", &dem.mode, "fast",
                "DEM confirmation of an accepted mechanism: off, fast (small periodic bed; wall_friction: a mould about 30 mm across) or ft4 (50 mm mould; slow)");
        cli.add("dem_driver", &dem.driver, "", "OedometerRelaxation executable (default: next to pdpm-explain)");
        cli.add("dem_threads", &dem.threads, 1, "OpenMP threads of the DEM runs", 1, 256);
        cli.add("dem_mechanism", &dem.mechanism, "",
                "accepted mechanism to confirm with the DEM (default: the first accepted one with a DEM counterpart, stiffness_nonlinearity last)");
        if (!cli.parse(args, std::cout)) return 0;
        if (dem.mode != "off" && dem.mode != "fast" && dem.mode != "ft4") inputError("--dem: expected off, fast or ft4, got '" + dem.mode + "'");
        if (!dem.mechanism.empty() && !(compFromName(dem.mechanism) >= 0 && isMechanism(compFromName(dem.mechanism))))
            inputError("--dem_mechanism: unknown mechanism '" + dem.mechanism + "'");
        if (recordings.empty()) inputError("--recording is required");
        if (protocols.empty()) inputError("--protocol is required");
        if (protocols.size() != 1 && protocols.size() != recordings.size())
            inputError("--protocol: give one protocol for all recordings or one per recording (" +
                       std::to_string(recordings.size()) + " recordings, " + std::to_string(protocols.size()) + " protocols)");
        if (output.empty()) inputError("--output is required");
        ExplainOptions opt;
        opt.seed = (unsigned long)seed;
        opt.figures = !noFigures;
        dem.figures = !noFigures;
        if (!model.empty()) readModelFile(model, opt);
        std::vector<Protocol> protos;
        std::vector<Recording> recs;
        for (std::size_t k = 0; k < recordings.size(); ++k) {
            const std::string& pp = protocols[protocols.size() == 1 ? 0 : k];
            protos.push_back(readProtocol(pp));
            recs.push_back(readRecording(recordings[k], protos.back()));
            checkConsistency(recs.back(), protos.back());
        }
        ExplainResult single;
        SeveralResult several;
        if (recs.size() == 1) {
            single = explain(recs[0], protos[0], opt);
            writeReport(output, single, recs[0], protos[0], opt);
        } else {
            several = explainSeveral(recs, protos, opt);
            writeSeveralReport(output, several, recs, protos, opt);
        }
        // Step 6: the DEM re-run, on the first recording whose own explanation accepted a mechanism the
        // DEM step supports (contact_relaxation, plasticity, wall_friction, cohesion; stiffness_nonlinearity
        // only where no recording has one of those; with --dem_mechanism the named one; else recording 1);
        // its block replaces the placeholder.
        std::size_t demRec = 0;
        // (wall_friction without the device's size and cohesion without an unload into tension rank with
        // stiffness_nonlinearity, as in confirmWithDem)
        const auto pulls = [&](std::size_t k) {
            return std::any_of(protos[k].steps.begin(), protos[k].steps.end(), [](const ProtocolStep& s) { return s.tension > 0; });
        };
        const auto rank = [&](int comp, std::size_t k) {
            if (!dem.mechanism.empty()) return compName(comp) == dem.mechanism ? 2 : 0;
            if (!demSupported(comp)) return 0;
            if (comp == kNonlinearity || (comp == kWallFriction && !(protos[k].diameter > 0 && protos[k].height > 0)) ||
                (comp == kCohesion && !pulls(k)))
                return 1;
            return 2;
        };
        int bestRank = 0;
        if (recs.size() > 1)
            for (std::size_t k = 0; k < recs.size(); ++k)
                for (const auto& m : several.per[k].mechanisms)
                    if (rank(m.comp, k) > bestRank) bestRank = rank(m.comp, k), demRec = k;
        const ExplainResult& r = recs.size() == 1 ? single : several.per[demRec];
        const DemResult d = confirmWithDem(r, recs[demRec], protocols[protocols.size() == 1 ? 0 : demRec], dem, output + "/dem");
        for (const std::string& dir : recs.size() == 1 ? std::vector<std::string>{output}
                                                        : std::vector<std::string>{output, output + "/recording_" + std::to_string(demRec + 1)}) {
            Json report = readJsonFile(dir + "/report.json");
            report.set("dem_confirmation", demJson(d));
            writeJsonFile(dir + "/report.json", report);
            writeWholeFile(dir + "/report.md", readWholeFile(dir + "/report.md") + demMarkdown(d));
        }
        if (d.status == "done")
            std::cout << "DEM confirmation (" << d.mechanism << (recs.size() > 1 ? ", recording " + std::to_string(demRec + 1) : "")
                      << "): held-out RMSE " << d.heldoutBaseline << " Pa -> "
                      << d.heldoutAugmented << " Pa (" << d.runs.size() << " DEM runs, " << d.wallSeconds << " s)\n";
        else
            std::cout << "DEM confirmation: " << d.status << (d.reason.empty() ? "" : " (" + d.reason + ")") << "\n";
        if (recs.size() > 1) {
            for (std::size_t k = 0; k < recs.size(); ++k)
                std::cout << "recording " << k + 1 << ": " << several.per[k].verdict << "\n";
            std::cout << "verdict: " << several.verdict << "\n" << several.summary << "\nreport: " << output << "/report.md\n";
            return 0;
        }
        std::cout << "verdict: " << r.verdict << "\n" << r.summary << "\nreport: " << output << "/report.md\n";
        return 0;
    });
}

} // namespace pdpm::explain
