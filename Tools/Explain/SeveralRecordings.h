// pdpm-explain with several recordings of one material (two devices, two rates, ...).
//
// Each recording is explained on its own first (explain(): baseline, nuisances, mechanisms, windows).
// Then every mechanism accepted in one recording is tested on each other recording, which its fit
// did not see: the other recording is fitted twice with only its device parameters free (its own
// baseline model: E, eps0, its nuisances) — once alone and once with the mechanism's terms switched
// on at the material parameters of the recording that found it (C and t0, lambda, sigma_c, muK, tau_v,
// n: not refitted). The likelihood of that held-out recording with and without the transferred term
// is the test (Transfer::evidence, against the explainer's acceptance threshold): "confirmed" when it
// improves some held-out recording where its term acts and worsens none; "inconclusive" when it acts
// but decides nothing; "recording_dependent" when it was accepted in several recordings but the
// parameters of one make another worse (the thesis' cocoa relaxes with C 0.079 in the lambdameter and
// 0.044 in the FT4); "not_transferable" when found in one recording and contradicted by another.
// The joint fit (JointFit.h) then votes: confirmed, accepted in several recordings, but inconsistent
// -> recording_dependent; recording_dependent with some transfer that helped, and consistent -> confirmed.
// Documentation/tools-explain.md ("Several recordings") describes the verdict rules.
#pragma once
#include <string>
#include <vector>

#include "Explain.h"
#include "JointFit.h"

namespace pdpm::explain {

/// One mechanism set carried from the recording `from` to the held-out recording `to`.
struct Transfer {
    std::size_t from = 0, to = 0;
    std::vector<int> mechanisms;
    double rmseBaseline = 0, rmseAugmented = 0;  ///< Pa, on recording `to`
    double termRms = 0;                          ///< RMS of (augmented - baseline) prediction on `to`, Pa
    bool acts = false;                           ///< the term changes the prediction by more than the noise allows to see
    double noiseSigma = 0;                       ///< noise sd of recording `to` (its own estimate), Pa
    /// n ln(RSS_without / RSS_with) of the whitened residuals (same free parameters in both fits):
    /// twice the log-likelihood ratio; >= the acceptance threshold confirms, <= -threshold contradicts
    double evidence = 0;
    std::vector<double> yBaseline, yAugmented;
    double gain() const { return rmseBaseline > 0 ? 1 - rmseAugmented / rmseBaseline : 0; }
    /// The same for the error above the noise level, sqrt(max(0, rmse^2 - sigma^2)) (-1: baseline at noise level).
    double excessGain() const;
};

struct SeveralResult {
    std::vector<ExplainResult> per;       ///< one per recording, in input order
    std::vector<int> mechanisms;          ///< union of the accepted mechanisms, in order of first acceptance
    std::vector<char> confirmed;          ///< per entry of `mechanisms`
    std::vector<char> testedElsewhere;    ///< per entry: its term acts on some held-out recording
    std::vector<int> foundIn;             ///< per entry: number of recordings that accepted it
    /// per entry: "confirmed", "inconclusive", "not_testable_elsewhere", "recording_dependent" or
    /// "not_transferable" (see the file comment)
    std::vector<std::string> status;
    /// per entry: the status from the transfers alone, before the joint fit's vote (`status` differs
    /// where the joint consistency test overruled it: confirmed, accepted in several recordings, but
    /// inconsistent -> recording_dependent; recording_dependent, some transfer helped, but consistent ->
    /// confirmed)
    std::vector<std::string> transferStatus;
    std::vector<Transfer> transfers;      ///< single mechanisms, then each recording's full accepted set
    /// one set of material parameters for every recording that informs a mechanism (JointFit.h): per
    /// mechanism found, when it was accepted in, or its transfer acts on, at least two recordings
    std::vector<JointFit> joint;
    std::string verdict, summary;
};

/// Explains every recording, then transfers the accepted mechanisms between them.
SeveralResult explainSeveral(const std::vector<Recording>& recs, const std::vector<Protocol>& protos,
                             const ExplainOptions& opt);

/// DIR/report.json, report.md, heldout_K_A_to_B.csv (transfer K, from A to B; + PNG with gnuplot); each recording's own
/// report in DIR/recording_<k>/.
void writeSeveralReport(const std::string& dir, const SeveralResult& r, const std::vector<Recording>& recs,
                        const std::vector<Protocol>& protos, const ExplainOptions& opt);

} // namespace pdpm::explain
