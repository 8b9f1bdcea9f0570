// pdpm-explain blind benchmark: a generator of concealed-effect recordings (surrogate model +
// coloured noise, drift, quantisation, nuisances) whose truth goes to a separate file, and a
// scorer that reads only report.json and truth.json.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "ExplainData.h"
#include "IO/Json.h"

namespace pdpm::explain {

/// kind: "null", a mechanism name ("contact_relaxation", ...), "two:A+B" (two mechanisms), or an
/// out-of-library effect "ool:bump" / "ool:sine".
struct CaseSpec {
    std::string kind = "null";
    double snr = 3;        ///< peak |effect| / noise sd (pointwise SNR)
    double rho = 0.5;      ///< AR(1) coefficient of the noise
    unsigned long seed = 1;
    int samples = 3000;
    /// 0: every parameter from `seed`. Otherwise the material (stiffness E and the mechanism
    /// parameters) comes from this seed and the rest (device, protocol, nuisances, noise) from
    /// `seed`: two cases with the same material seed are two recordings of one material.
    unsigned long materialSeed = 0;
};

struct GeneratedCase {
    Recording rec;
    Protocol proto;
    Json truth;
};

GeneratedCase generateCase(const CaseSpec& spec);
/// Writes CASE_DIR/recording.csv and CASE_DIR/protocol.json, and TRUTH_PATH (separately).
void writeCase(const GeneratedCase& g, const std::string& caseDir, const std::string& truthPath);
void writeRecordingCsv(const Recording& r, const std::string& path, const std::vector<std::string>& comments);
void writeProtocolJson(const Protocol& p, const std::string& path);

struct CaseScore {
    bool positive = false;     ///< something is truly missing (in the library)
    bool outOfLibrary = false;
    bool detected = false;     ///< verdict missing_physics or ambiguous (positives) / not no_missing_physics (nulls)
    bool correctMechanism = false;
    bool ambiguous = false;
    double iou = 0;
    double paramRelError = -1; ///< |estimate - truth| / |truth - off| of the primary parameter (-1: n/a)
    double paramRelErrorIdentifiable = -1;  ///< the same against the value the record can identify (differs for plasticity)
    int paramCovered = -1;     ///< 1 if the reported 95 % interval of the primary parameter holds the truth (-1: n/a)
    double heldoutGain = 0;    ///< 1 - heldout_aug / heldout_base
    double heldoutExcessGain = 0;  ///< the same for the held-out error above the noise level (-1: n/a)
    std::string verdict, truthKind;
    double snr = 0, rho = 0;
};

CaseScore scoreCase(const Json& report, const Json& truth);

/// "a/b (x.x %)"
std::string countShare(int a, int b);
/// Markdown table with one row per mechanism and one column per SNR; cells "hits/cases".
std::string snrGrid(const std::map<std::string, std::map<double, std::pair<int, int>>>& table,
                    const std::vector<double>& snrs);

/// Benchmark of the several-recordings stage (in process; the truth is the kind each pair was
/// generated with): `pairs` same-material pairs per mechanism and SNR (one material seed, two
/// devices/protocols/noise realisations), `pairs` null pairs and `pairs` contradicting pairs
/// (mechanism in one recording, a different material without it in the other). Returns a
/// markdown section.
std::string pairBenchmark(int pairs, const std::vector<std::string>& mechanisms, const std::vector<double>& snrs,
                          int samples, unsigned long seed);

} // namespace pdpm::explain
