// pdpm-recording-check: validates recording files (Documentation/recording-format.md).
//   pdpm-recording-check FILE...      FILE.csv: time series; FILE.json: protocol
// Prints every problem as "FILE:LINE: message" (LINE 0: the file as a whole) and exits 2 if any file
// is malformed; prints "FILE: ok ..." per valid file and exits 0 otherwise.
#include <iostream>
#include <string>
#include <vector>

#include "Cli.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "Recording.h"

using namespace pdpm;

int main(int argc, char** argv) {
    return tools::runTool("pdpm-recording-check", [&]() -> int {
        std::vector<std::string> files;
        tools::Cli cli("pdpm-recording-check",
                       "Validate recording time series (.csv) and protocol files (.json); exit 2 on any problem");
        cli.addList("input", &files, "files to check (.csv recordings, .json protocols)");
        std::vector<std::string> args(argv + 1, argv + argc);
        // Bare file names are accepted as well as --input A B.
        if (!args.empty() && args[0].rfind("--", 0) != 0) args.insert(args.begin(), "--input");
        if (!cli.parse(args, std::cout)) return 0;
        if (files.empty()) inputError("no files given (pdpm-recording-check FILE...)");
        bool bad = false;
        for (const std::string& f : files) {
            const bool json = f.size() > 5 && f.substr(f.size() - 5) == ".json";
            if (json) {
                try {
                    const auto p = recording::readProtocol(f);
                    std::cout << f << ": ok (protocol, device " << p.device << ", " << p.steps.size() << " steps)\n";
                } catch (const InputError& e) {
                    std::string m = e.what();
                    if (m.rfind(f + ":", 0) != 0) m = f + ":0: " + m;
                    std::cerr << m << '\n';
                    bad = true;
                }
                continue;
            }
            recording::Recording r;
            const auto problems = recording::checkRecording(readWholeFile(f), &r);
            for (const auto& p : problems) std::cerr << f << ":" << p.line << ": " << p.message << '\n';
            if (!problems.empty()) {
                bad = true;
                continue;
            }
            std::cout << f << ": ok (" << r.rows.size() << " rows; columns";
            for (const auto& c : r.columns) std::cout << ' ' << c;
            std::cout << ")\n";
        }
        return bad ? kExitBadInput : 0;
    });
}
