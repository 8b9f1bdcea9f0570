// Unit tests of pdpm-explain (Tools/Explain): noise model, fitter, input validation, and a small
// fixed subset of the blind benchmark (null and positive cases with fixed seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "Core/Error.h"
#include "Explain.h"
#include "ExplainBench.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"

using namespace pdpm;
using namespace pdpm::explain;

namespace {
std::string workDir(const std::string& name) {
    const std::string d = std::filesystem::current_path().string() + "/explain_" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}
ExplainResult runCase(const CaseSpec& s, GeneratedCase* out = nullptr) {
    GeneratedCase g = generateCase(s);
    ExplainOptions opt;
    opt.figures = false;
    ExplainResult r = pdpm::explain::explain(g.rec, g.proto, opt);
    if (out) *out = std::move(g);
    return r;
}
} // namespace

TEST(ExplainNoise, RecoversAr1SigmaAndRho) {
    for (double rho : {0.0, 0.5, 0.9}) {
        std::mt19937_64 g(7);
        std::normal_distribution<double> N(0, 1);
        std::vector<double> r(5000);
        double x = N(g) * 2.0;
        for (auto& v : r) {
            x = rho * x + std::sqrt(1 - rho * rho) * 2.0 * N(g);
            v = x;
        }
        const NoiseModel nm = estimateNoise(r);
        EXPECT_NEAR(nm.sigma, 2.0, 0.3) << "rho " << rho;
        const double trueNeff = 5000 * (1 - rho) / (1 + rho);
        EXPECT_GT(nm.nEff, 0.5 * trueNeff) << "rho " << rho;
        EXPECT_LT(nm.nEff, 1.5 * trueNeff + 1) << "rho " << rho;
        EXPECT_GT(blockChiSquarePValue(r, nm, 0), 1e-3) << "pure noise must pass the block test, rho " << rho;
        // a smooth offset in one tenth of the record must fail it
        std::vector<double> s = r;
        for (std::size_t i = 2000; i < 2500; ++i) s[i] += 3.0;
        EXPECT_LT(blockChiSquarePValue(s, estimateNoise(s), 0), 1e-3) << "rho " << rho;
    }
}

TEST(ExplainFit, RecoversRelaxationParametersFromCleanData) {
    GeneratedCase g = generateCase({"contact_relaxation", 5, 0.0, 11, 1500});
    const Model M(makeModelInput(g.rec, g.proto));
    const auto& tp = g.truth.at("parameters");
    const double C = tp.at("C").asNumber(), t0 = tp.at("t0").asNumber();
    std::vector<double> p = M.defaults();
    p[pE] = 2e6;
    p[pEps0] = 0.001;
    p[pRelaxC] = C;
    p[pRelaxT0] = t0;
    std::vector<char> on(kNumComp, 0);
    on[kBaseline] = on[kRelaxation] = 1;
    std::vector<double> y;
    M.evaluate(p, on, y);
    std::vector<double> start = p;
    start[pRelaxC] = 0.03;
    start[pRelaxT0] = 1.0;
    start[pE] = 1.5e6;
    FitOptions fo;
    fo.freeParams = {pE, pEps0, pRelaxC, pRelaxT0};
    const FitResult f = fitModel(M, y, on, start, fo);
    EXPECT_NEAR(f.p[pRelaxC], C, 0.02 * C);
    EXPECT_NEAR(f.p[pE], 2e6, 0.01 * 2e6);
}

TEST(ExplainInput, BadInputsAreInputErrors) {
    const std::string d = workDir("badinput");
    writeWholeFile(d + "/noGeom.json", R"({"device":{"name":"x"},"steps":[{"type":"ramp"}]})");
    EXPECT_THROW(readProtocol(d + "/noGeom.json"), InputError);
    writeWholeFile(d + "/badStep.json", R"({"device":{"name":"x","diameter_m":0.05,"height_m":0.05},"steps":[{"type":"jump"}]})");
    EXPECT_THROW(readProtocol(d + "/badStep.json"), InputError);
    writeWholeFile(d + "/ok.json", R"({"format":"pdpm-oedometer-protocol","version":1,"device":{"name":"x","diameter_m":0.05,"height_m":0.05},"steps":[{"type":"hold_position","duration_s":5000}]})");
    const Protocol p = readProtocol(d + "/ok.json");
    std::string csv = "time_s,axial_strain\n";
    for (int i = 0; i < 30; ++i) csv += std::to_string(i) + "," + std::to_string(0.001 * i) + "\n";
    writeWholeFile(d + "/noStress.csv", csv);
    EXPECT_THROW(readRecording(d + "/noStress.csv", p), InputError);
    std::string csv2 = "# comment\ntime_s,axial_strain,axial_stress_Pa\n";
    for (int i = 0; i < 30; ++i) csv2 += std::to_string(i) + "," + std::to_string(0.001 * i) + "," + std::to_string(100 * i) + "\n";
    writeWholeFile(d + "/ok.csv", csv2);
    const Recording r = readRecording(d + "/ok.csv", p);
    EXPECT_EQ(r.size(), 30u);
    EXPECT_THROW(checkConsistency(r, p), InputError);  // 5000 s protocol vs 29 s recording
    EXPECT_EQ(runExplainCommand({"--recording", d + "/ok.csv", "--protocol", d + "/ok.json", "--output", d + "/out"}), 2);
    EXPECT_EQ(runExplainCommand({"--recording", d + "/missing.csv", "--protocol", d + "/ok.json", "--output", d + "/out"}), 2);
    EXPECT_EQ(runExplainCommand({"--protocol", d + "/ok.json", "--output", d + "/out"}), 2);
    writeWholeFile(d + "/model.json", R"({"candidates":["no_such_mechanism"]})");
    ExplainOptions o;
    EXPECT_THROW(readModelFile(d + "/model.json", o), InputError);
}

TEST(ExplainBenchmarkSubset, NullCasesSayNoMissingPhysics) {
    for (unsigned long seed : {101ul, 102ul, 103ul}) {
        const double rho = seed == 101 ? 0.0 : seed == 102 ? 0.5 : 0.9;
        const ExplainResult r = runCase({"null", 0, rho, seed, 1500});
        EXPECT_EQ(r.verdict, "no_missing_physics") << "seed " << seed << ": " << r.summary;
        EXPECT_GT(r.minDetectableRms, 0);
    }
}

TEST(ExplainBenchmarkSubset, PositiveCasesNameTheMechanism) {
    for (const char* kind : {"contact_relaxation", "plasticity", "rate_dependence"}) {
        GeneratedCase g;
        const ExplainResult r = runCase({kind, 8, 0.5, 201, 1500}, &g);
        ASSERT_EQ(r.verdict, "missing_physics") << kind << ": " << r.summary;
        ASSERT_FALSE(r.mechanisms.empty());
        EXPECT_EQ(std::string(compName(r.mechanisms.front().comp)), kind);
        EXPECT_LT(r.heldoutAugmented, r.heldoutBaseline) << kind;
        // the primary parameter's 95 % interval is finite and excludes "off"
        const auto& m = r.mechanisms.front();
        EXPECT_TRUE(std::isfinite(m.lo[0]) && std::isfinite(m.hi[0]));
        bool hasWindow = false;
        for (const auto& w : r.windows) hasWindow = hasWindow || w.mismatch;
        EXPECT_TRUE(hasWindow) << kind;
    }
}

TEST(ExplainCommand, EndToEndIsDeterministicAndScored) {
    const std::string d = workDir("e2e");
    writeCase(generateCase({"contact_relaxation", 8, 0.5, 301, 1500}), d + "/case", d + "/truth.json");
    for (const char* out : {"/a", "/b"})
        ASSERT_EQ(runExplainCommand({"--recording", d + "/case/recording.csv", "--protocol", d + "/case/protocol.json",
                                     "--output", d + out, "--seed", "5", "--no_figures"}),
                  0);
    EXPECT_EQ(readWholeFile(d + "/a/report.json"), readWholeFile(d + "/b/report.json"));
    const Json rep = readJsonFile(d + "/a/report.json");
    for (const char* key : {"verdict", "mechanisms", "windows", "fit", "dem_confirmation", "candidates", "noise"})
        EXPECT_TRUE(rep.has(key)) << key;
    EXPECT_EQ(rep.at("dem_confirmation").at("status").asString(), "not_run");
    const CaseScore s = scoreCase(rep, readJsonFile(d + "/truth.json"));
    EXPECT_TRUE(s.positive);
    EXPECT_TRUE(s.detected);
    EXPECT_TRUE(s.correctMechanism);
    EXPECT_GE(s.paramRelError, 0.0);
}
