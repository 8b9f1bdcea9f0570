// pdpm-explain: thesis Eq. 4.3 fitted to every hold of a recording on its own, the way thesis
// chapter 4 analyses relaxation (Tables 4.4/4.5): sigma(t) = sigma_h (1 + (t - t_h)/t0)^(-C) with
// sigma_h, C and t0 free per hold. The explainer's contact_relaxation term has one (C, t0) for the
// whole record; these per-hold values show how C and t0 change with the stress (thesis Fig. 4.5b,
// 4.7b) and are what the thesis tables report. Raw recorded stress, no nuisance removed.
#pragma once
#include <string>
#include <vector>

#include "ExplainData.h"
#include "IO/Json.h"

namespace pdpm::explain {

struct HoldFit {
    double tStart = 0, tEnd = 0;  ///< first and last sample of the hold (s)
    double stressStart = 0;       ///< fitted sigma_h (Pa)
    double C = 0, cLo = 0, cHi = 0;
    double t0 = 0, t0Lo = 0, t0Hi = 0;
    double rmse = 0;              ///< RMS residual of the hold fit (Pa)
    std::size_t samples = 0;
};

struct HoldFitSummary {
    std::vector<HoldFit> holds;
    /// ln C = a - beta ln sigma_h over the holds (thesis: C falls with stress); NaN with < 3 holds
    double beta = 0, betaSe = 0;
    double meanC = 0;
};

/// Fits every hold phase with at least `minSamples` samples. `rho`: lag-1 autocorrelation of the
/// noise's AR(1) part; the 95 % intervals (Jacobian, residual variance of the hold) are widened by
/// sqrt((1 + rho)/(1 - rho)). With a given instrument noise level the explainer passes rho = 0.
/// `creep` (optional, one flag per sample, creepSamples of ExplainData.h): a hold whose middle sample
/// lies in a creep step is skipped (the stress is held there, it has no decay to fit).
HoldFitSummary fitHolds(const Recording& rec, double rho, std::size_t minSamples = 20, const std::vector<char>& creep = {});

/// {"holds": [{t_start_s, t_end_s, stress_start_Pa, C, C_ci95, t0_s, t0_ci95, rmse_Pa, samples}],
///  "mean_C", "C_stress_exponent", "C_stress_exponent_se"}
Json holdFitsJson(const HoldFitSummary& s);

} // namespace pdpm::explain
