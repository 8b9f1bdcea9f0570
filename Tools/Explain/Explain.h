// pdpm-explain: locate where a recording and the baseline model disagree, name the missing
// physics from a library of mechanisms, add it, refit, and accept it only under a strict criterion.
// Documentation/tools-explain.md describes the method, the report and the measured performance.
#pragma once
#include <string>
#include <vector>

#include "ExplainData.h"
#include "ExplainModel.h"
#include "HoldFits.h"
#include "IO/Json.h"

namespace pdpm::explain {

struct ExplainOptions {
    unsigned long seed = 1;
    bool figures = true;             ///< write PNG figures with gnuplot (when it is installed)
    std::vector<int> baselineComps;  ///< components always on (default: none beyond the baseline)
    std::vector<int> candidates;     ///< mechanisms to screen (default: all)
    std::vector<int> nuisances;      ///< nuisances to try first (default: compliance, drift)
    double bicThreshold = 10;        ///< ΔBIC (with n_eff) needed to accept a mechanism
    double ambiguityMargin = 6;      ///< ΔBIC difference below which two mechanisms are "ambiguous"
    int maxMechanisms = 3;
    int folds = 4;                   ///< blocked cross-validation folds
    bool forceBest = false;          ///< add the best candidate even if it fails (benchmark control)
    bool whitenedLikelihood = true;  ///< GLS likelihood (AR(1)+white innovations); false: plain residuals with n_eff
    double knownNoiseSigma = 0;      ///< >0: instrument noise sd (Pa) from MODEL.json, used instead of the
                                     ///< estimate (sparse records, where differences see the misfit)
    /// >= 0: the instrument compliance ratio kappa (instrument strain = kappa * stress / E) is known
    /// from a calibration (MODEL.json "instrument_compliance_ratio"): held at that value, never fitted
    /// (0: the instrument is rigid). < 0: unknown, tried as a nuisance.
    double knownCompliance = -1;
};

/// Reads MODEL.json: {"baseline": [components always on], "candidates": [mechanism names],
/// "nuisances": [...], "noise_sigma_Pa": x, "bic_threshold": x, "instrument_compliance_ratio": x}
/// (all optional). Unknown keys, names and out-of-range values: InputError (exit 2).
void readModelFile(const std::string& path, ExplainOptions& opt);

struct Candidate {
    int comp = -1;
    int round = 0;
    double dBIC = 0;           ///< against the model of that round
    double rss = 0;
    double orthFraction = 0;   ///< |template ⊥ baseline Jacobian| / |template|
    double minDetectable = 0;  ///< smallest detectable value of the primary parameter (linearised)
    bool testable = true;
    bool accepted = false;
    bool rejectedHeldOut = false;  ///< better BIC, but the held-out error did not drop
    double heldoutBase = -1, heldoutAug = -1;
    /// wall_friction with a usable bottom sensor: the sensor channel's part of dBIC (chi2 - ln n_eff of
    /// the channel; 0 otherwise)
    double sensorDBIC = 0;
    std::string note;
    std::vector<double> p, se;
    /// nuisances of the current model this candidate's best fit goes without (a nuisance selected on
    /// the baseline may have absorbed part of the mechanism's signature; see explain(), step 4)
    std::vector<int> dropsNuisances;
};

struct Window {
    std::size_t begin = 0, end = 0;
    double tStart = 0, tEnd = 0, epsStart = 0, epsEnd = 0, sStart = 0, sEnd = 0;
    std::string phase;
    double share = 0;       ///< share of the excess residual energy
    double meanZ = 0;       ///< mean normalised residual (sign of the mismatch)
    double excessZ = 0;     ///< the phase's excess energy over its noise sd (significance)
    bool mismatch = false;  ///< in a protocol phase carrying a comparable part of the excess (selectMismatch)
};

struct MechanismResult {
    int comp = -1;
    std::vector<int> params;
    std::vector<double> value, lo, hi;
    double inclusionProbability = 0;
    /// protocol phases where the added term itself acts (final model minus the same model with the
    /// term switched off), as opposed to `windows`, where the baseline disagrees with the recording
    std::vector<Window> actsIn;
    /// left-out nuisances whose inclusion widened the 95 % intervals (see explain(), step 6)
    std::vector<std::string> widenedBy;
    /// contact_relaxation only: Eq. 4.3 fitted to each hold separately (the thesis' per-hold C, t0)
    HoldFitSummary perHold;
    /// wall_friction with a usable bottom sensor and the device's H and D: Janssen's mu_w K from the
    /// sensor's loading transmission T, -ln T / (4 H/D), with the 95 % interval of T (T +- 1.96 se)
    /// carried through (-1: none). The piston-stress term's muK is the one in `value`.
    double sensorMuK = -1, sensorMuKLo = -1, sensorMuKHi = -1;
    /// cohesion only: the largest tension the final model (without the sensor offset and drift)
    /// reaches in the record, Pa. Equal to the `tension` parameter when the record pulls the bed to
    /// its strength; smaller when the test stopped before (then `tension` is only bounded below).
    double reachedTension = -1;
};

/// What the recording's bottom stress sensor says about wall friction (Documentation/tools-explain.md,
/// "Bottom stress sensor"): the loading's bottom/piston transmission (ExplainData.h) and its verdict,
/// wall_friction_present when 1 - slope exceeds both 3 standard errors and kMinWallLoss,
/// no_wall_loss when even 1 - slope + 3 se stays below kMinWallLoss, else inconclusive.
struct BottomSensor {
    bool present = false;  ///< the recording has a usable bottom_stress_Pa channel
    Transmission transmission;
    double janssenMuK = -1;  ///< -ln(slope) / (4 H/D) when the protocol gives H and D and slope < 1
    std::string says;        ///< wall_friction_present | no_wall_loss | inconclusive
    /// the sensor channel's evidence against "no stress lost to the walls": ((1 - kMinWallLoss - T)_+ / se)^2,
    /// the likelihood-ratio statistic of the fitted transmission against the no-loss band; it enters
    /// wall_friction's dBIC (with one parameter, ln n_eff of the channel) in explain()
    double chi2 = 0;
};
BottomSensor readBottomSensor(const Recording& rec, const Protocol& proto);

/// The refinement test of contact_relaxation: does C depend on the stress at the start of each hold,
/// C_h = C (s_h/s_ref)^(-beta) (relaxation_stress_dependence in ExplainModel.h)?
struct RelaxStressTest {
    bool tested = false;
    std::string why;              ///< why it was not tested, or the outcome in words
    int holds = 0;                ///< holds with a positive start stress
    double stressSpan = 0;        ///< largest / smallest hold start stress
    double dBIC = 0, heldoutBase = 0, heldoutAug = 0;
    double beta = 0, betaSe = 0;  ///< the fitted exponent (in the refined fit, accepted or not)
    double stressRef = 0;         ///< s_ref (Pa): C is reported at this stress when accepted
    double holdsBeta = 0, holdsBetaSe = 0;  ///< the exponent over the holds fitted one by one (HoldFits)
    bool accepted = false;
};

struct ExplainResult {
    std::string verdict;
    std::string summary;
    std::vector<MechanismResult> mechanisms;
    std::vector<int> nuisances;         ///< nuisances of the final model
    std::vector<int> nuisancesDropped;  ///< selected on the baseline, dropped with an added mechanism
    std::vector<Candidate> candidates;
    /// times a selection round refitted the current model from a candidate's fit (the polish, step 5)
    int polishes = 0;
    /// rounds that stopped polishing at the limit while a candidate's fit still beat the current model
    /// (a third polish might have moved the current model further; it is not tried)
    int polishLimitRounds = 0;
    std::vector<Window> windows;
    RelaxStressTest relaxStress;
    /// what the windows' explained part is measured against (report.json windows_reference)
    std::string windowsReference = "the baseline residual alone (no mechanism added, or its refit failed)";
    std::string ambiguousWith;  ///< second mechanism when verdict == ambiguous
    std::string separatingExperiment;
    NoiseModel noise;
    double pNoiseBaseline = 1, pNoiseFinal = 1, explainedFraction = 0;
    double rmseBaseline = 0, rmseAugmented = 0, heldoutBaseline = 0, heldoutAugmented = 0;
    double minDetectableRms = 0;  ///< smallest RMS effect (Pa) the data could reveal
    std::vector<double> pBaseline, pFinal;
    std::vector<char> onBaseline, onFinal;
    int heldParam = -1;  ///< parameter held in every fit (the calibrated compliance), or -1
    std::vector<double> yBaseline, yFinal;  ///< model predictions
    std::vector<Phase> phaseOfSample;
    BottomSensor bottom;
};

ExplainResult explain(const Recording& rec, const Protocol& proto, const ExplainOptions& opt);

/// report.json, report.md, series.csv, candidates.csv, windows.csv and (if gnuplot exists) PNGs.
void writeReport(const std::string& dir, const ExplainResult& r, const Recording& rec, const Protocol& proto,
                 const ExplainOptions& opt);

/// The command line of pdpm-explain (argv[1..]); returns the exit code.
int runExplainCommand(const std::vector<std::string>& args);

/// The parts (e.g. protocol phases) carrying the excess residual energy: every part with at least
/// `relative` times the largest part's excess and at least `minShare` of the total. Used by the
/// explainer (estimated excess) and by the benchmark truth (noise-free visible effect).
std::vector<char> selectMismatch(const std::vector<double>& excess, double relative = 0.3, double minShare = 0.05);

/// Free parameters of the components switched on in `on` (the baseline always); `fixed` (a parameter
/// index, or -1) is held, e.g. a calibrated instrument compliance.
std::vector<int> freeParamsFor(const Model& m, const std::vector<char>& on, int fixed = -1);

/// report.json pieces: a mechanism's parameters ({name: {value, ci95, unit}}) and one window.
Json parametersJson(const MechanismResult& m, const std::vector<ParDef>& defs);
Json windowJson(const Window& w);

/// `x` with `prec` significant digits (report text).
std::string num(double x, int prec = 4);
/// Root-mean-square difference of two equally long series.
double rmsOf(const std::vector<double>& a, const std::vector<double>& b);

/// A path quoted for a gnuplot script ('...' with '' for a quote).
std::string gnuplotQuote(const std::string& s);
/// Runs gnuplot on `script` (when gnuplot is installed; nothing otherwise). The script writes each
/// figure of `pngs` to PNG.tmp; on success every PNG.tmp is renamed to PNG, otherwise removed, so a
/// failed or killed plot never leaves a half-written figure.
void runGnuplot(const std::string& script, const std::vector<std::string>& pngs);

/// Experiment that separates two mechanisms.
std::string separatingExperiment(int a, int b);

} // namespace pdpm::explain
