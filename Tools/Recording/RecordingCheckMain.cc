// pdpm-recording-check: validates recording files (Documentation/recording-format.md).
//   pdpm-recording-check FILE...      FILE.csv: time series; FILE.json: protocol
// Prints each problem as "FILE:LINE: message" (LINE 0: the file as a whole; at most 10 per file, then
// a count of the rest; bytes outside printable ASCII as \xNN) and exits 2 if any file is malformed;
// prints "FILE: ok ..." per valid file and exits 0 otherwise.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "Cli.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "Recording.h"

using namespace pdpm;

namespace {
constexpr std::size_t kMaxProblemsShown = 10;

std::string printable(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        }
    }
    return out;
}
} // namespace

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
            // a compiler-style list, capped (a binary or wrongly encoded file would give one line per row)
            // and with control and non-ASCII bytes escaped (they would garble the terminal)
            const std::size_t shown = std::min<std::size_t>(problems.size(), kMaxProblemsShown);
            for (std::size_t k = 0; k < shown; ++k)
                std::cerr << f << ":" << problems[k].line << ": " << printable(problems[k].message) << '\n';
            if (problems.size() > shown)
                std::cerr << f << ": ... and " << problems.size() - shown << " more problems (not shown)\n";
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
