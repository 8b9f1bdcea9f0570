// The lateral stress channel of an oedometer recording, summarised for the report (not modelled by
// the mechanisms, which act on the axial stress):
//   - K0 on virgin loading: the through-origin slope of the lateral on the axial stress over the
//     samples of the Load phases (the strain beyond its largest value so far: normally consolidated),
//     from 30 % of the recording's top stress up (the seating part left out). Jaky (1944):
//     K0 = 1 - sin(phi), so phi_Jaky = asin(1 - K0).
//   - On unloading, K0 grows with the overconsolidation ratio OCR = sigma_max / sigma. Mayne and
//     Kulhawy (1982): K0 = K0_NC OCR^m with m ~ sin(phi); m is the through-origin slope of
//     ln(K0 / K0_NC) on ln(OCR) over the unload samples with OCR >= 1.02 and sigma >= 5 % of sigma_max.
// Two friction angles from two independent parts of the record; their agreement is a check of the
// frictional (Coulomb) picture of the lateral stress, their disagreement a pointer to physics the
// baseline leaves out (e.g. rolling resistance or cohesion changing K0).
#pragma once
#include <string>
#include <vector>

#include "IO/Json.h"

namespace pdpm::explain {

struct LateralSummary {
    bool present = false;       ///< the recording has a lateral channel with usable samples
    int loadingSamples = 0;     ///< virgin-loading samples of the K0 fit
    int unloadSamples = 0;      ///< unload samples of the OCR exponent fit
    double k0 = -1, k0Se = -1;  ///< K0 on virgin loading and its standard error (lag-1 autocorrelation allowed for)
    double m = -1, mSe = -1;    ///< exponent of K0 = K0_NC OCR^m on unloading (-1: no unload samples)
    double ocrMax = 0;          ///< largest OCR among the unload samples
    double phiJakyDeg = -1;     ///< asin(1 - K0) in degrees (-1 unless 0 < K0 < 1)
    double phiUnloadDeg = -1;   ///< asin(m) in degrees (-1 unless 0 < m < 1)
};

/// The summary of the channel `lateral` (Pa; empty or with non-finite samples allowed) next to the axial
/// stress `s` (Pa), the phases being taken from the strain `e` over time `t`.
LateralSummary summariseLateral(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                const std::vector<double>& lateral);

/// report.json's "lateral_channel" object.
Json lateralJson(const LateralSummary& L);

/// One paragraph of report.md in plain words (empty when the channel is absent).
std::string lateralWords(const LateralSummary& L);

} // namespace pdpm::explain
