// pdpm-explain-data: inputs for pdpm-explain in the recording format.
//   generate     --kind K --snr S --rho R --seed N --samples M [--material_seed K] --output CASE_DIR --truth TRUTH.json
//   dem-case     --kind null|contact_relaxation|wall_friction|creep|cohesion|rate_dependence [--family F] [--bottom_sensor 1] --snr S --rho R
//                --seed N --output CASE_DIR --truth TRUTH.json
//                a case made by the OedometerRelaxation DEM (Tools/Explain/DemCases.h); CASE_DIR/model.json
//                holds the baseline the explainer must be given
//   thesis       --material cocoa|limestone [--device lambdameter|ft4] --output DIR [--seed N]
//                reconstructs the protocol-1 test of thesis chapter 4 from Tables 4.4/4.5 (lambdameter;
//                FT4 for cocoa)
//   import-kfs   --input OEk.dat --output DIR     (Karlsruhe fine sand oedometer, KFSDB)
//   import-cheng --input obsdata.dat --output DIR (GrainLearning glass-bead oedometer)
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "Ar1Noise.h"
#include "Cli.h"
#include "Core/Error.h"
#include "DemCases.h"
#include "ExplainBench.h"
#include "IO/AtomicFile.h"
#include "IO/Csv.h"

using namespace pdpm;
using namespace pdpm::explain;

namespace {

std::vector<std::vector<double>> readWhitespaceTable(const std::string& path, int skipLines, std::size_t cols) {
    std::ifstream in(path);
    if (!in) inputError(path + ": cannot be read");
    std::string line;
    std::vector<std::vector<double>> rows;
    int ln = 0;
    while (std::getline(in, line)) {
        ++ln;
        if (ln <= skipLines) continue;
        if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
        std::istringstream is(line);
        std::vector<double> r;
        double v;
        while (is >> v) r.push_back(v);
        if (r.size() < cols) inputError(path + ":" + std::to_string(ln) + ": expected " + std::to_string(cols) + " numbers");
        rows.push_back(r);
    }
    if (rows.size() < 20) inputError(path + ": too few data rows");
    return rows;
}

/// The first line of a third-party table must name its columns as the source does: a file of
/// another source (same column count, other quantities) would otherwise be converted silently.
void requireHeader(const std::string& path, const std::vector<std::string>& words, const std::string& what) {
    std::ifstream in(path);
    if (!in) inputError(path + ": cannot be read");
    std::string line;
    std::getline(in, line);
    std::istringstream is(line);
    std::vector<std::string> have;
    for (std::string w; is >> w;) have.push_back(w);
    for (const std::string& w : words)
        if (std::find(have.begin(), have.end(), w) == have.end())
            inputError(path + ":1: not " + what + " (its first line should name the columns " + [&] {
                std::string l;
                for (const auto& x : words) l += (l.empty() ? "" : ", ") + x;
                return l;
            }() + ")");
}

int thesis(const std::string& material, const std::string& device, const std::string& dataDir, const std::string& out,
           unsigned long seed) {
    // Table 4.5 (lambdameter, protocol 1; cocoa and limestone) or Table 4.4 (cocoa, lambdameter L and
    // FT4 F): sigma_max (kPa), t0 (s), C per hold R1..R5.
    const bool cocoa = material == "cocoa", ft4 = device == "ft4";
    if (ft4 && !cocoa) inputError("--device ft4: the thesis gives FT4 relaxation data for cocoa only (Table 4.4)");
    // the tables have a text column (step), so strip it before the strict numeric CSV parser
    const std::string path =
        dataDir + (ft4 ? "/thesis/table_4_4_relaxation_devices.csv" : "/thesis/table_4_5_relaxation_materials.csv");
    std::istringstream raw(readWholeFile(path));
    std::string text, line;
    while (std::getline(raw, line)) {
        if (line.empty() || line[0] == '#') continue;
        const auto comma = line.find(',');
        text += (comma == std::string::npos ? line : line.substr(comma + 1)) + "\n";
    }
    const CsvTable tb = parseCsv(text, path);
    const std::string col = ft4 ? "F" : (cocoa ? "C" : "E");
    const auto smax = tb.columnValues("sigma_max_" + col + "_kPa");
    const auto t0 = tb.columnValues("t0_" + col + "_s");
    const auto C = tb.columnValues("C_" + col);
    // Assumed loading curve (not in the tables): sigma = s25 * (eps/eps25)^2 with eps25 = 0.25
    // (cocoa) / 0.30 (limestone, softer), i.e. the stiffening typical of powders under compression;
    // the same material curve in both devices (only the geometry and the hold data differ).
    const double H = ft4 ? 0.05 : 0.06, D = ft4 ? 0.05 : 0.149, v = 0.05e-3, rate = v / H, hold = 300, fs = 5.0;
    const double eps25 = cocoa ? 0.25 : 0.30, s25 = 25.0e3, m = 2.0;
    auto load = [&](double e) { return s25 * std::pow(std::max(e, 0.0) / eps25, m); };
    auto tangent = [&](double e) { return s25 * m * std::pow(std::max(e, 1e-9) / eps25, m - 1) / eps25; };
    std::vector<double> epsK;
    for (double s : smax) epsK.push_back(eps25 * std::pow(s * 1e3 / s25, 1 / m));
    Recording r;
    Protocol p;
    p.device = ft4 ? "FT4 rheometer (reconstructed from thesis Table 4.4)" : "lambdameter (reconstructed from thesis Table 4.5)";
    p.diameter = D;
    p.height = H;
    p.material = cocoa ? "cocoa powder (12 % fat)" : "Eskal 500 limestone";
    std::mt19937_64 rng(ft4 ? seed + 1000003 : seed);  // the two devices never share a noise sequence
    std::normal_distribution<double> N(0, 1);
    const double sigma = 15.0, rho = 0.5, q = 1.0;  // load-cell noise (Pa), AR(1), quantisation (Pa)
    Ar1Noise noise = Ar1Noise::fromZero(rho, sigma);
    double t = 0, e = 0, deficit = 0;
    const double dt = 1 / fs;
    auto emit = [&](double stress) {
        noise.next(rng, N);
        r.t.push_back(t);
        r.strain.push_back(e);
        r.stress.push_back(std::round((stress + noise.x + 2.0e-3 * t) / q) * q);  // 2 mPa/s drift
        t += dt;
    };
    for (std::size_t k = 0; k < smax.size(); ++k) {
        // Reloading after a hold, as in the thesis' protocol 1: the piston moves on at constant speed
        // "until the next intermediate stress" (the table's sigma_max), so every hold starts at
        // sigma_max. The stress lost in the hold (the deficit) is made up on the way, along a stiff
        // reload that rejoins the loading curve: deficit D exp(-(e - e_start)/e_rec), e_rec = D / tangent
        // (assumed; the tables give the holds only). With a deficit left, the ramp ends at a strain a
        // little beyond the loading curve's strain of sigma_max.
        const double eStart = e, dEnd = deficit, erec = dEnd > 0 ? dEnd / tangent(eStart) : 1;
        const double target = smax[k] * 1e3;
        auto stressAt = [&](double ee) { return load(ee) - (dEnd > 0 ? dEnd * std::exp(-(ee - eStart) / erec) : 0.0); };
        // strain where the ramp reaches the target: bisection between the start and far beyond
        double lo = eStart, hi = std::max(epsK[k], eStart) + 1.0;
        for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
            const double mid = 0.5 * (lo + hi);
            (stressAt(mid) < target ? lo : hi) = mid;
        }
        const double eEnd = hi;
        p.steps.push_back({StepType::Ramp, v, target, (eEnd - eStart) / rate});
        while (e < eEnd) {
            emit(stressAt(e));
            e = std::min(eEnd, e + rate * dt);
        }
        e = eEnd;
        p.steps.push_back({StepType::Hold, -1, -1, hold});
        const double th = t;
        while (t - th < hold) {
            const double rel = target * std::pow(1 + (t - th) / t0[k], -C[k]);
            emit(rel);
            deficit = load(e) - rel;  // below the loading curve: this hold's loss and what the ramp had not made up
        }
    }
    // the step durations must add up to the record
    double sum = 0;
    for (auto& s : p.steps) sum += s.duration;
    p.steps.back().duration += (r.t.back() - r.t.front()) - sum;
    ensureDirectory(out);
    writeRecordingCsv(r, out + "/recording.csv",
                      {"Reconstruction of thesis chapter 4, protocol 1, " + std::string(ft4 ? "FT4" : "lambdameter") + ", " + p.material,
                       std::string("holds: Eq. 4.3 with sigma_max, t0, C of Table ") + (ft4 ? "4.4 (FT4)" : "4.5") +
                           " per hold; loading curve assumed sigma ~ eps^2",
                       "sampling 5 Hz, AR(1) noise sd 15 Pa rho 0.5, quantisation 1 Pa, drift 2 mPa/s"});
    writeProtocolJson(p, out + "/protocol.json");
    double cm = 0;
    for (double c : C) cm += c;
    Json truth = Json::object();
    truth.set("material", material);
    truth.set("device", ft4 ? "ft4" : "lambdameter");
    truth.set("C_mean", cm / double(C.size()));
    Json cs = Json::array();
    for (double c : C) cs.push(Json(c));
    truth.set("C_per_hold", cs);
    Json ss = Json::array();
    for (double x : smax) ss.push(Json(x * 1e3));
    truth.set("sigma_max_per_hold_Pa", ss);
    writeJsonFile(out + "/thesis-values.json", truth);
    std::cout << "wrote " << out << "/recording.csv (" << r.t.size() << " samples)\n";
    return 0;
}

/// Piston speed of an imported record without a time base (time = row index): the median strain
/// step per row times the height. The recording format needs a speed > 0 for ramp/unload steps.
double typicalVelocity(const Recording& r, double height) {
    std::vector<double> v;
    for (std::size_t i = 1; i < r.t.size(); ++i) {
        const double d = std::abs(r.strain[i] - r.strain[i - 1]) / std::max(r.t[i] - r.t[i - 1], 1e-12);
        if (d > 0) v.push_back(d);
    }
    if (v.empty()) return 1e-6;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2] * height;
}

int importKfs(const std::string& in, const std::string& out) {
    requireHeader(in, {"sigma1", "eps1"}, "a KFSDB oedometer file");
    const auto rows = readWhitespaceTable(in, 3, 3);
    Recording r;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        r.t.push_back(double(i));
        r.strain.push_back(rows[i][1] / 100);
        r.stress.push_back(rows[i][0] * 1e3);
    }
    Protocol p;
    p.device = "oedometer (KFSDB, Wichtmann & Triantafyllidis 2016)";
    p.diameter = 0.07;  // assumed (not in the data); only wall_friction uses it
    p.height = 0.02;
    p.material = "Karlsruhe fine sand";
    const double vk = typicalVelocity(r, p.height);  // assumed: the file has no time
    p.steps = {{StepType::Ramp, vk, 407e3, -1}, {StepType::Unload, vk, -1, -1}, {StepType::Ramp, vk, 407e3, -1}};
    ensureDirectory(out);
    writeRecordingCsv(r, out + "/recording.csv",
                      {"imported from " + in + " (sigma1 kPa -> Pa, eps1 % -> strain)",
                       "time_s is the row index: the file has no time; geometry assumed D = 70 mm, H = 20 mm"});
    writeProtocolJson(p, out + "/protocol.json");
    return 0;
}

int importCheng(const std::string& in, const std::string& out) {
    requireHeader(in, {"e_a", "p", "q"}, "a GrainLearning obsdata.dat file");
    const auto rows = readWhitespaceTable(in, 1, 4);
    Recording r;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double pm = rows[i][1], q = rows[i][2];
        r.t.push_back(double(i));
        r.strain.push_back(rows[i][0]);
        r.stress.push_back((pm + 2 * q / 3) * 1e6);
        r.lateral.push_back((pm - q / 3) * 1e6);
    }
    Protocol p;
    p.device = "oedometer with lateral stress (GrainLearning obsdata.dat)";
    p.diameter = 0.05;  // assumed
    p.height = 0.02;
    p.material = "glass beads";
    const double vc = typicalVelocity(r, p.height);  // assumed: the file has no time
    p.steps = {{StepType::Ramp, vc, -1, -1}, {StepType::Unload, vc, -1, -1}, {StepType::Ramp, vc, -1, -1},
               {StepType::Unload, vc, -1, -1}};
    ensureDirectory(out);
    writeRecordingCsv(r, out + "/recording.csv",
                      {"imported from " + in + ": sigma_a = p + 2q/3, sigma_r = p - q/3, unit assumed MPa",
                       "time_s is the row index: the file has no time"});
    writeProtocolJson(p, out + "/protocol.json");
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    return tools::runTool("pdpm-explain-data", [&] {
        if (argc < 2) inputError("usage: pdpm-explain-data generate|dem-case|thesis|import-kfs|import-cheng [--help]");
        const std::string cmd = argv[1];
        if (cmd == "--help" || cmd == "-h") {
            std::cout << "pdpm-explain-data SUB-COMMAND [options]: inputs for pdpm-explain (Documentation/tools-explain.md)\n"
                         "  generate      a surrogate recording with a concealed mechanism (truth stored separately)\n"
                         "  dem-case      a recording made by the OedometerRelaxation driver with a mechanism switched on\n"
                         "  thesis        the thesis' cocoa / limestone hold curves (Tables 4.4/4.5) as recordings\n"
                         "  import-kfs    a Karlsruhe fine sand oedometer file as a recording\n"
                         "  import-cheng  the glass-bead oedometer with lateral stress as a recording\n"
                         "pdpm-explain-data SUB-COMMAND --help lists the sub-command's options.\n";
            return 0;
        }
        std::vector<std::string> args(argv + 2, argv + argc);
        tools::Cli cli("pdpm-explain-data " + cmd, "inputs for pdpm-explain (see Documentation/tools-explain.md)");
        std::string output, input, truth, kind, material, device, dataDir;
        double snr = 3, rho = 0.5;
        int seed = 1, samples = 3000, materialSeed = 0, threads = 1;
        std::string driver, driverArgs, work, family;
        bool bottomSensor = false;
        cli.add("output", &output, "", "output directory");
        if (cmd == "generate") {
            cli.add("kind", &kind, "null", "null | MECHANISM | two:A+B | ool:bump | ool:sine");
            cli.add("snr", &snr, 3, "-", "peak effect / noise sd", 0, 1e6, true, false);
            cli.add("rho", &rho, 0.5, "-", "AR(1) coefficient of the noise", 0, 0.99);
            cli.add("seed", &seed, 1, "seed", 0, 2147483647);
            cli.add("samples", &samples, 3000, "samples", 50, 1000000);
            cli.add("truth", &truth, "", "where to write the sealed truth (JSON)");
            cli.add("material_seed", &materialSeed, 0,
                    "seed of the material (stiffness, mechanism parameters); 0: from --seed. Cases with the same "
                    "material seed are recordings of one material (device, protocol and noise from --seed)",
                    0, 2147483647);
        } else if (cmd == "dem-case") {
            cli.add("kind", &kind, "null", "null | contact_relaxation | wall_friction | creep | cohesion | rate_dependence", {"null", "contact_relaxation", "wall_friction", "creep", "cohesion", "rate_dependence"});
            cli.add("family", &family, "", "the pair's family (a null case is its twin without the mechanism): contact_relaxation | wall_friction | creep (contact relaxation seen in creep steps) | cohesion (lift-off test) | rate_dependence (contact viscosity) (default: the kind; contact_relaxation for null)");
            cli.add("bottom_sensor", &bottomSensor, false, "wall_friction family: the record also carries a noisy bottom_stress_Pa");
            cli.add("snr", &snr, 3, "-", "peak effect (DEM with minus DEM without the mechanism) / noise sd", 0, 1e6, true, false);
            cli.add("rho", &rho, 0.5, "-", "AR(1) coefficient of the noise", 0, 0.99);
            cli.add("seed", &seed, 1, "seed (protocol, parameters, the DEM's bed, noise)", 0, 2147483647);
            cli.add("samples", &samples, 2000, "samples", 50, 1000000);
            cli.add("truth", &truth, "", "where to write the sealed truth (JSON)");
            cli.add("work", &work, "", "folder of the DEM runs (default: TRUTH.dem)");
            cli.add("driver", &driver, "", "OedometerRelaxation executable (default: next to this program)");
            cli.add("driver_args", &driverArgs, "", "extra driver arguments (e.g. '--width 4 --fill_height 5' for a smaller bed)");
            cli.add("threads", &threads, 1, "OpenMP threads of the DEM runs", 1, 256);
        } else if (cmd == "thesis") {
            cli.add("material", &material, "cocoa", "material", {"cocoa", "limestone"});
            cli.add("device", &device, "lambdameter", "device (ft4: cocoa only, Table 4.4)", {"lambdameter", "ft4"});
            cli.add("seed", &seed, 1, "seed of the noise", 0, 2147483647);
            cli.add("data", &dataDir, PDPM_SHARED_DATA, "shared data folder (holds thesis/table_4_4_relaxation_devices.csv and table_4_5_relaxation_materials.csv)");
        } else if (cmd == "import-kfs" || cmd == "import-cheng") {
            cli.add("input", &input, "", "data file");
        } else {
            inputError("unknown sub-command '" + cmd + "' (generate, dem-case, thesis, import-kfs, import-cheng)");
        }
        if (!cli.parse(args, std::cout)) return 0;
        if (output.empty()) inputError("--output is required");
        if (cmd == "generate") {
            if (truth.empty()) inputError("--truth is required");
            CaseSpec s{kind, snr, rho, (unsigned long)seed, samples, (unsigned long)materialSeed};
            writeCase(generateCase(s), output, truth);
            return 0;
        }
        if (cmd == "dem-case") {
            if (truth.empty()) inputError("--truth is required");
            DemCaseSpec s{kind, snr, rho, (unsigned long)seed, samples, driver, driverArgs, threads, family, bottomSensor};
            Json model;
            const GeneratedCase g = generateDemCase(s, work.empty() ? truth + ".dem" : work, model);
            writeCase(g, output, truth);
            writeJsonFile(output + "/model.json", model);
            return 0;
        }
        if (cmd == "thesis") return thesis(material, device, dataDir, output, (unsigned long)seed);
        if (input.empty()) inputError("--input is required");
        return cmd == "import-kfs" ? importKfs(input, output) : importCheng(input, output);
    });
}
