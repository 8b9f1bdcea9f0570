#include <iostream>
#include <sstream>

#include "Cli.h"
#include "Core/Error.h"
#include "DemConfirmation.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"
#include "Explain.h"

namespace pdpm::explain {

int runExplainCommand(const std::vector<std::string>& args) {
    return tools::runTool("pdpm-explain", [&] {
        tools::Cli cli("pdpm-explain",
                       "Compares an oedometric recording with the baseline model of the same protocol, locates the "
                       "mismatch, names the missing physics from a mechanism library, refits and reports "
                       "(DIR/report.json, report.md, figures).");
        std::vector<std::string> recordings;
        std::string protocol, output, model;
        int seed = 1;
        bool noFigures = false;
        DemOptions dem;
        cli.addList("recording", &recordings, "recording CSV (recording format: time_s, axial_stress_Pa, axial_strain or piston_position_m)");
        cli.add("protocol", &protocol, "", "protocol JSON of the recording");
        cli.add("output", &output, "", "output directory");
        cli.add("model", &model, "", "MODEL.json naming the baseline and the candidates (default: oedometric baseline, all mechanisms)");
        cli.add("seed", &seed, 1, "seed of the randomised restarts (results are deterministic for a seed)", 0, 2147483647);
        cli.add("no_figures", &noFigures, false, "do not run gnuplot");
        cli.add("dem", &dem.mode, "fast",
                "DEM confirmation of an accepted mechanism: off, fast (small periodic bed) or ft4 (50 mm mould; slow)");
        cli.add("dem_driver", &dem.driver, "", "OedometerRelaxation executable (default: next to pdpm-explain)");
        cli.add("dem_threads", &dem.threads, 1, "OpenMP threads of the DEM runs", 1, 256);
        if (!cli.parse(args, std::cout)) return 0;
        if (dem.mode != "off" && dem.mode != "fast" && dem.mode != "ft4") inputError("--dem: expected off, fast or ft4, got '" + dem.mode + "'");
        if (recordings.empty()) inputError("--recording is required");
        if (recordings.size() > 1)
            inputError("--recording: several recordings of one material are not supported yet; give one file");
        if (protocol.empty()) inputError("--protocol is required");
        if (output.empty()) inputError("--output is required");
        ExplainOptions opt;
        opt.seed = (unsigned long)seed;
        opt.figures = !noFigures;
        if (!model.empty()) readModelFile(model, opt);
        const Protocol proto = readProtocol(protocol);
        const Recording rec = readRecording(recordings[0], proto);
        checkConsistency(rec, proto);
        const ExplainResult r = explain(rec, proto, opt);
        writeReport(output, r, rec, proto, opt);
        // Step 6: the DEM re-run; its block replaces the placeholder in report.json.
        const DemResult d = confirmWithDem(r, rec, protocol, dem, output + "/dem");
        Json report = readJsonFile(output + "/report.json");
        report.set("dem_confirmation", demJson(d));
        writeJsonFile(output + "/report.json", report);
        writeWholeFile(output + "/report.md", readWholeFile(output + "/report.md") + demMarkdown(d));
        if (d.status == "done")
            std::cout << "DEM confirmation (" << d.mechanism << "): held-out RMSE " << d.heldoutBaseline << " Pa -> "
                      << d.heldoutAugmented << " Pa (" << d.runs.size() << " DEM runs, " << d.wallSeconds << " s)\n";
        else
            std::cout << "DEM confirmation: " << d.status << (d.reason.empty() ? "" : " (" + d.reason + ")") << "\n";
        std::cout << "verdict: " << r.verdict << "\n" << r.summary << "\nreport: " << output << "/report.md\n";
        return 0;
    });
}

} // namespace pdpm::explain
