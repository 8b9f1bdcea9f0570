// Per-hold results and statistics of the OedometerRelaxation driver: stress and strain at the start
// and end of the hold, the fit of Eq. (4.3), and how quasi-static the hold was (E_k/E_p samples,
// clock pauses). Serialised into restart files and the protocol file.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "Core/Error.h"
#include "IO/Json.h"
#include "Recording.h"

namespace pdpm {

struct OedometerHold {
    int step = 0;
    bool creep = false;
    double labStart = 0, labDuration = 0;
    double stressStart = 0, stressEnd = 0, strainStart = 0, strainEnd = 0;
    double maxEkEp = 0, settleDem = 0;  ///< settleDem: DEM seconds waited before the clock started
    long samples = 0, samplesAbove = 0;  ///< samples taken while the lab clock ran, and those with E_k/E_p > 1e-4
    long pauses = 0, forcedResumes = 0;  ///< clock pauses (rearrangement events), and pauses ended by hold_settle_max
    double pauseDem = 0;                 ///< DEM seconds the clock stood still after it had started
    recording::RelaxationFit fit;
    std::vector<double> t, s;  ///< lab time, axial stress samples of the hold

    double fractionAbove() const { return samples > 0 ? double(samplesAbove) / double(samples) : 0.0; }

    /// The scalars, in the order of the restart file's "hold" record.
    std::vector<double> numbers() const {
        return {double(step), creep ? 1.0 : 0.0, labStart, labDuration, stressStart, stressEnd, strainStart, strainEnd,
                maxEkEp, fit.C, fit.t0, fit.rms, fit.ok ? 1.0 : 0.0, double(samples), double(samplesAbove), settleDem,
                double(pauses), double(forcedResumes), pauseDem};
    }
    /// Inverse of numbers(); restart files written before the clock pauses hold 16 numbers.
    static OedometerHold fromNumbers(const std::vector<double>& a) {
        if (a.size() != 16 && a.size() != 19) inputError("restart file: bad hold record");
        OedometerHold h;
        h.step = static_cast<int>(a[0]);
        h.creep = a[1] != 0;
        h.labStart = a[2], h.labDuration = a[3], h.stressStart = a[4], h.stressEnd = a[5];
        h.strainStart = a[6], h.strainEnd = a[7], h.maxEkEp = a[8];
        h.fit.C = a[9], h.fit.t0 = a[10], h.fit.rms = a[11], h.fit.ok = a[12] != 0;
        h.samples = static_cast<long>(a[13]), h.samplesAbove = static_cast<long>(a[14]), h.settleDem = a[15];
        if (a.size() == 19) h.pauses = static_cast<long>(a[16]), h.forcedResumes = static_cast<long>(a[17]), h.pauseDem = a[18];
        return h;
    }
    /// Entry of the protocol file's extra.holds list.
    Json json() const {
        // the fit's numbers are null when there is no fit (a creep step, a fit that gave up) or it is not finite
        const auto fitted = [this](double x) { return fit.ok && std::isfinite(x) ? Json(x) : Json(); };
        return Json::object({{"step", step},
                             {"type", creep ? "hold_stress" : "hold_position"},
                             {"lab_start_s", labStart},
                             {"stress_start_Pa", stressStart},
                             {"stress_end_Pa", stressEnd},
                             {"strain_start", strainStart},
                             {"strain_end", strainEnd},
                             {"settle_dem_s", settleDem},
                             {"max_Ek_over_Ep", maxEkEp},
                             {"fraction_Ek_over_Ep_above_1e-4", fractionAbove()},
                             {"clock_pauses", pauses},
                             {"clock_pauses_ended_by_hold_settle_max", forcedResumes},
                             {"pause_dem_s", pauseDem},
                             {"fit_C", fitted(fit.C)},
                             {"fit_t0_s", fitted(fit.t0)},
                             {"fit_rms", fitted(fit.rms)}});
    }
    /// One line for the end-of-run summary.
    void print() const {
        std::printf("  step %d %s: stress %.6g -> %.6g Pa (drop %.4g %%), max Ek/Ep %.3g (%.3g %% of samples above 1e-4; "
                    "%ld clock pauses, %.3g DEM s), fit C = %.4g, t0 = %.4g s (rms %.2g)\n",
                    step, creep ? "creep" : "hold", stressStart, stressEnd, 100 * (1 - stressEnd / stressStart), maxEkEp,
                    100 * fractionAbove(), pauses, pauseDem, fit.C, fit.t0, fit.rms);
    }
};

} // namespace pdpm
