// pdpm-recording-check: exit 0 on a valid recording and protocol; exit 2 with "FILE:LINE: message"
// on malformed ones (missing time column, non-monotonic time, NaN, wrong unit, bad protocol).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "IO/AtomicFile.h"

namespace {
bool check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    return ok;
}
int runCheck(const std::string& exe, const std::string& args, std::string& err) {
    const int rc = std::system((exe + " " + args + " > out.txt 2> err.txt").c_str());
    err = pdpm::readWholeFile("err.txt");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
} // namespace

int main(int, char** argv) {
    std::string exe = argv[0];
    exe = exe.substr(0, exe.find_last_of('/') + 1) + "pdpm-recording-check";
    bool ok = true;
    std::string err;
    write("good.csv", "# test\ntime_s,axial_stress_Pa,axial_strain\n0,0,0\n1,10,0.01\n");
    write("good.json", R"({"format": "pdpm-oedometer-protocol", "version": 1, "device": {"name": "ft4"},
      "steps": [{"type": "ramp", "velocity_m_s": 5e-5, "target_stress_Pa": 5000}, {"type": "hold_position", "duration_s": 300}]})");
    ok &= check(runCheck(exe, "good.csv good.json", err) == 0 && err.empty(), "valid files: exit 0");
    write("notime.csv", "t,axial_stress_Pa\n0,1\n");
    ok &= check(runCheck(exe, "notime.csv", err) == 2 && err.find("notime.csv:1:") != std::string::npos, "missing time_s: exit 2, line 1");
    write("order.csv", "time_s,axial_stress_Pa\n0,1\n1,2\n0.5,3\n");
    ok &= check(runCheck(exe, "order.csv", err) == 2 && err.find("order.csv:4:") != std::string::npos, "non-monotonic time: exit 2, line 4");
    write("nan.csv", "time_s,axial_stress_Pa\n0,1\n1,nan\n");
    ok &= check(runCheck(exe, "nan.csv", err) == 2 && err.find("nan.csv:3:") != std::string::npos, "NaN: exit 2, line 3");
    write("unit.csv", "time_s,axial_stress_kPa\n0,1\n");
    ok &= check(runCheck(exe, "unit.csv", err) == 2 && err.find("wrong unit") != std::string::npos, "wrong unit: exit 2");
    write("bad.json", R"({"format": "pdpm-oedometer-protocol", "version": 1, "device": {"name": "ft4"}, "steps": [{"type": "hold_position"}]})");
    ok &= check(runCheck(exe, "bad.json", err) == 2 && err.find("duration_s") != std::string::npos, "bad protocol: exit 2");
    write("syntax.json", "{\n  \"a\": 1,\n}\n");
    ok &= check(runCheck(exe, "syntax.json", err) == 2 && err.find("syntax.json:3:") != std::string::npos, "JSON syntax error: exit 2 with line");
    ok &= check(runCheck(exe, "missing_file.csv", err) == 2, "missing file: exit 2");
    std::printf("%s", err.c_str());
    return ok ? 0 : 1;
}
