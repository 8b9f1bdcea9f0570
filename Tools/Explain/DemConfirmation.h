// DEM confirmation of an accepted mechanism (pdpm-explain step 6): the OedometerRelaxation driver
// is re-run on the recording's protocol without and with the matching contact ingredient, the
// ingredient's parameter is calibrated on part of the record, and both runs are scored on the part
// the calibration did not see. Documentation/tools-explain.md ("DEM confirmation") has the method.
//
// Implemented for contact_relaxation (contact law ingredient Relaxing<...>, driver flags --relax_C,
// --relax_t0): the lab holds are split alternately into calibration holds (1st, 3rd, ...) and
// held-out holds (2nd, 4th, ...). Each DEM hold curve is normalised by its stress when the hold's
// clock starts, g_k(t) = sigma_k(t)/sigma_k(0), and predicts the lab hold k as sigma_lab,k(0) g_k(t),
// sigma_lab,k(0) being the mean of the lab hold's first three samples. Runs: baseline (C = 0);
// augmented with the contact C equal to the explainer's macroscopic C; a second augmented run with
// C rescaled by (macroscopic C / DEM macroscopic C on the calibration holds). The augmented run with
// the smaller calibration error is scored on the held-out holds.
#pragma once
#include <string>
#include <vector>

#include "Explain.h"
#include "IO/Json.h"

namespace pdpm::explain {

struct DemOptions {
    std::string mode = "fast";  ///< off | fast (periodic bed, default driver size) | ft4 (D = H = 50 mm mould)
    std::string driver;         ///< OedometerRelaxation executable (empty: next to this program)
    int threads = 1;
};

struct DemRun {
    std::string name;
    double relaxC = 0, relaxT0 = 0;
    double calibrationRmse = -1, heldoutRmse = -1;  ///< Pa
    double macroC = -1;                             ///< mean fitted C of the DEM calibration holds
    double wallSeconds = 0;
    std::string command;
};

struct DemResult {
    std::string status = "not_run";  ///< done | not_run | not_needed | not_supported | failed
    std::string reason, mechanism;
    std::vector<DemRun> runs;
    int chosen = -1;  ///< index of the scored augmented run
    int calibrationHolds = 0, heldoutHolds = 0;
    double heldoutBaseline = -1, heldoutAugmented = -1;
    double wallSeconds = 0;
};

/// Runs the confirmation for the first accepted mechanism of `r` (workDir receives the runs).
DemResult confirmWithDem(const ExplainResult& r, const Recording& rec, const std::string& protocolPath,
                         const DemOptions& opt, const std::string& workDir);

/// The report.json block "dem_confirmation".
Json demJson(const DemResult& d);
/// Plain-words paragraph for report.md.
std::string demMarkdown(const DemResult& d);

} // namespace pdpm::explain
