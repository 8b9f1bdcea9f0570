// Self-test: DeviatoricD2 (self-prepared at v_i = 0.70, N = 500, frictionless), D2 pure shear to
// eps_dev = 0.3. Checks: volume is conserved, eps_dev reaches 0.3, the stress anisotropy builds up in
// the direction of the imposed strain and then saturates, the major stress eigenvector turns to z
// (compression). Then a short triaxial run: the lateral stresses stay at their start value within
// 15 % while z is compressed. Then the same triaxial run split in two at a time between outputs
// (--time_max, then --restart): its macro rows equal the uninterrupted run's bit for bit. Until
// 2026-12-04 the stress control's first step after a restart used contacts re-evaluated with the
// current instead of the step's predicted velocities, and the second step stale records, so the rows
// after the restart differed from about the 11th digit on. The same without ene output, split at an
// output time (there the macro row needs records the kernel did not make; replacing the step's own
// records made the next step's stress, and so the run, depend on the output flags). A restart whose
// driver keys (contact sum, stage) are malformed (edited, checksum resealed) is refused with exit code 2.
// "Builds up": the signed anisotropy (sigma_zz - sigma_xx)/p (z is compressed, x extended) rises by at
// least 0.1 from the isotropic start (the last row before the shear) to its mean over eps_dev in
// [0.15, 0.3], and the late s_dev exceeds 0.15. Until 2026-12-04 the check was "the mean s_dev over
// eps_dev in [0.15, 0.22] and [0.22, 0.3] exceed 1.5 times its mean over eps_dev <= 0.01": a
// 500-particle packing starts with a random s_dev of about 0.1, half the saturation value, so that
// ratio passed or failed with the packing's realisation (0.111 -> 0.20, passing, before the contact
// loops added the affine flow to remapped axes; 0.148 -> 0.176, failing, after, with the same
// physics of the shear). Measured 2026-12-04: signed anisotropy 0.065 at the start, 0.21 late; late
// s_dev 0.20; the two halves of [0.15, 0.3] 0.176 and 0.213.
#include <fstream>
#include <sstream>

#include "../../Drivers/Deviatoric/DeviatoricD2.h"
#include "IO/NumberFormat.h"
#include "IO/RestartSeal.h"
#include "ElementTestCommon.h"

namespace {
std::string readWholeText(const std::string& path) {
    std::ifstream f(path);
    std::ostringstream os;
    os << f.rdbuf();
    return os.str();
}
} // namespace

int main() {
    using namespace etest;
    int rc = runDriver<DeviatoricD2>({"--quiet", "--threads", "1", "--vtk", "0", "--output", "d2", "--particles", "500", "--mu", "0",
                                      "--rate", "10", "--eps_dev_max", "0.3", "--outputs", "60"});
    check(rc == 0, "DeviatoricD2 exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable t = pdpm::readCsv("d2/DeviatoricD2.macro.csv");
    const int tau = t.column("tau");
    auto test = [&](const std::vector<double>& r) { return r[tau] >= 0; };
    const Series vf = select(t, "eps_dev", "volume_fraction", test);
    double dv = 0;
    for (double y : vf.y) dv = std::max(dv, std::fabs(y - vf.y.front()));
    check(dv < 1e-9, "volume conserved during D2 (max change " + std::to_string(dv) + ")");
    check(std::fabs(vf.x.back() - 0.3) < 1e-4, "eps_dev reaches 0.3 (" + std::to_string(vf.x.back()) + ")");
    const Series s = select(t, "eps_dev", "s_dev", test);
    const double a = meanOver(s, 0.15, 0.22), b = meanOver(s, 0.22, 0.3);
    // signed anisotropy along the imposed strain, from the isotropic start (last row before the shear)
    const int cz = t.column("sigma_zz"), cx = t.column("sigma_xx"), cp = t.column("p");
    double start = 0;
    for (const auto& r : t.rows)
        if (r[tau] < 0) start = (r[cz] - r[cx]) / r[cp];
    std::vector<double> signedLate;
    const int ce = t.column("eps_dev");
    for (const auto& r : t.rows)
        if (r[tau] >= 0 && r[ce] >= 0.15) signedLate.push_back((r[cz] - r[cx]) / r[cp]);
    double late = 0;
    for (double x : signedLate) late += x;
    late = signedLate.empty() ? 0 : late / static_cast<double>(signedLate.size());
    check(late > start + 0.1 && 0.5 * (a + b) > 0.15,
          "anisotropy builds up along the imposed strain ((sigma_zz - sigma_xx)/p " + std::to_string(start) + " -> " +
              std::to_string(late) + ", late s_dev " + std::to_string(0.5 * (a + b)) + ")");
    check(std::fabs(a - b) < 0.25 * b, "s_dev saturates (" + std::to_string(a) + " vs " + std::to_string(b) + ")");
    const Series th = select(t, "eps_dev", "sig_theta1", test);
    check(meanOver(th, 0.1, 0.3) < 20, "major stress axis near z (" + std::to_string(meanOver(th, 0.1, 0.3)) + " deg)");

    // the triaxial run of every check below, written to `dir`, with extra flags
    const auto triaxial = [](const std::string& dir, std::vector<std::string> extra) {
        std::vector<std::string> args = {"--quiet", "--threads", "1", "--vtk", "0", "--output", dir, "--particles", "500",
                                         "--mode", "triaxial", "--rate", "5", "--eps_dev_max", "0.05", "--outputs", "40"};
        args.insert(args.end(), extra.begin(), extra.end());
        return runDriver<DeviatoricD2>(args);
    };
    rc = triaxial("tri", {});
    check(rc == 0, "triaxial exit code 0");
    if (rc != 0) return 1;
    const pdpm::CsvTable u = pdpm::readCsv("tri/DeviatoricD2.macro.csv");
    const int ut = u.column("tau");
    const Series sxx = select(u, "tau", "sigma_xx", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const Series syy = select(u, "tau", "sigma_yy", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const Series szz = select(u, "tau", "sigma_zz", [&](const std::vector<double>& r) { return r[ut] >= 0; });
    const double goal = 0.5 * (sxx.y.front() + syy.y.front());
    const double lateEnd = 0.5 * (meanOver(sxx, 0.5, 1.0) + meanOver(syy, 0.5, 1.0));
    // measured 2026-12-06: 1.0023 of the goal, row-to-row sd 6e-5 over the second half (the
    // controller's lag behind a wall that keeps moving); 1 % is four times that offset
    check(std::fabs(lateEnd / goal - 1) < 0.01, "triaxial lateral stress held (" + std::to_string(lateEnd / goal) + " of goal)");
    check(meanOver(szz, 0.5, 1.0) > 1.2 * lateEnd, "triaxial axial stress exceeds lateral stress");

    auto lines = [](const std::string& path) {
        std::ifstream f(path);
        std::vector<std::string> out;
        for (std::string l; std::getline(f, l);) out.push_back(l);
        return out;
    };
    const std::vector<std::string> tri = lines("tri/DeviatoricD2.macro.csv");
    const auto timeText = [](const std::string& row) { return row.substr(0, row.find(',')); };
    const std::string tEnd = timeText(tri.back());
    // A triaxial run (extra flags `flags`) split in two by --time_max tSplit and --restart, against
    // the straight run whose macro rows are `straight`. A split between two outputs adds the row
    // the first half wrote when it stopped; it is the first row that differs, and is left out.
    const auto splitMatches = [&](const std::string& dir, const std::vector<std::string>& flags, const std::string& tSplit,
                                  const std::vector<std::string>& straight, const std::string& what) {
        std::vector<std::string> firstHalf = {"--time_max", tSplit};
        firstHalf.insert(firstHalf.end(), flags.begin(), flags.end());
        check(triaxial(dir, firstHalf) == 0, what + ": first half exit code 0");
        check(readWholeText(dir + "/DeviatoricD2.restart").find("\ncontact_stress_sum ") != std::string::npos,
              what + ": the restart file holds the stress control's contact sum");
        check(runDriver<DeviatoricD2>({"--quiet", "1", "--threads", "1", "--output", dir, "--restart", dir + "/DeviatoricD2.restart",
                                       "--time_max", tEnd}) == 0,
              what + ": restarted second half exit code 0");
        std::vector<std::string> split = lines(dir + "/DeviatoricD2.macro.csv");
        std::size_t extra = 0;
        for (std::size_t k = 0; k < split.size(); ++k)
            if (k >= straight.size() || split[k] != straight[k]) {
                extra = k;
                break;
            }
        if (extra > 0 && split.size() == straight.size() + 1) split.erase(split.begin() + static_cast<long>(extra));
        std::size_t same = 0;
        for (std::size_t k = 0; k < std::min(split.size(), straight.size()); ++k) same += split[k] == straight[k];
        check(split == straight, what + ", split by a restart at t = " + tSplit + " s, equals the straight run (" + std::to_string(same) +
                                     " of " + std::to_string(straight.size()) + " macro rows identical)");
    };
    double t0 = 0;  // start of the triaxial stage; split 43.7 % into it, between two outputs
    for (const auto& r : u.rows)
        if (r[ut] < 0) t0 = r[u.column("time")];
    splitMatches("tri2", {}, std::to_string(t0 + 0.437 * (u.rows.back()[u.column("time")] - t0)), tri, "triaxial run");
    // driver keys edited into malformed values (file resealed, so the checksum passes): refused
    {
        const std::string text = readWholeText("tri2/DeviatoricD2.restart");
        // resumed for five steps: the file's own time_max is reached, and would refuse every edit alike
        std::string resumeTo;
        {
            std::istringstream line(text.substr(text.find("\ntime ") + 1));
            std::string word, stepWord, dtWord;
            double t = 0, dt = 0;
            long step = 0;
            line >> word >> t >> stepWord >> step >> dtWord >> dt;
            check(word == "time" && stepWord == "step" && dtWord == "dt" && dt > 0, "the final restart file has a time line");
            resumeTo = pdpm::fmt(t + 5 * dt);
        }
        check(runDriver<DeviatoricD2>({"--quiet", "1", "--threads", "1", "--output", "tri2edit", "--restart", "tri2/DeviatoricD2.restart",
                                       "--time_max", resumeTo}) == 0,
              "the unedited final restart file resumes for five steps");
        const std::pair<const char*, const char*> edits[] = {{"contact_stress_sum", "1 2 oops"}, {"contact_stress_sum", "1 2 3 4"},
                                                             {"contact_stress_sum", "nan 0 0"},  {"stage", "99"},
                                                             {"stage_begun", "2"},               {"stage_start", "nan"},
                                                             {"stage_start", "-1"},              {"stage_start", "1e300"}};
        for (const auto& [key, bad] : edits) {
            const std::string edited = pdpm::withRestartValue(text, key, bad);
            check(!edited.empty(), std::string("the final restart file holds ") + key);
            if (edited.empty()) continue;
            std::ofstream("tri2/edited.restart", std::ios::binary | std::ios::trunc) << edited;
            check(runDriver<DeviatoricD2>({"--quiet", "1", "--threads", "1", "--output", "tri2edit", "--restart", "tri2/edited.restart",
                                           "--time_max", resumeTo}) == 2,
                  std::string("a restart with ") + key + " '" + bad + "' is refused (exit code 2)");
        }
        // the box line's periodic flags (PX PY PZ after the six corner coordinates) with z made a
        // wall-less open axis: no element test runs in it (it ran before)
        const std::size_t at = text.find("\nbox ");
        check(at != std::string::npos, "the final restart file has a box line");
        if (at != std::string::npos) {
            std::string edited = text;
            std::size_t p = at + 5;
            for (int field = 0; field < 8; ++field) p = edited.find(' ', p) + 1;  // to PZ
            check(edited.compare(p, 2, "1 ") == 0, "the box line's PZ is 1");
            edited.replace(p, 1, "0");
            std::ofstream("tri2/edited.restart", std::ios::binary | std::ios::trunc) << pdpm::resealRestartText(edited);
            check(runDriver<DeviatoricD2>({"--quiet", "1", "--threads", "1", "--output", "tri2edit", "--restart", "tri2/edited.restart",
                                           "--time_max", resumeTo}) == 2,
                  "a restart whose box is not periodic along z is refused (exit code 2)");
        }
    }
    // without ene, vtk and fstat output the macro rows need records the kernel does not make; the
    // restart at an output time of the straight run (the row at tau >= 0.5)
    check(triaxial("tri3", {"--ene", "0"}) == 0, "triaxial run without ene output exit code 0");
    const std::vector<std::string> triNoEne = lines("tri3/DeviatoricD2.macro.csv");
    std::string tOut;
    for (std::size_t k = 1; k < u.rows.size() && tOut.empty(); ++k)
        if (u.rows[k][ut] >= 0.5) tOut = timeText(tri[k + 1]);  // tri[0] is the header
    splitMatches("tri4", {"--ene", "0"}, tOut, triNoEne, "triaxial run without ene output");
    return failures ? 1 : 0;
}
