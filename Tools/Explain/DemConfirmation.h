// DEM confirmation of an accepted mechanism (pdpm-explain step 6): the OedometerRelaxation driver
// is re-run on the recording's protocol without and with the matching contact ingredient, the
// ingredient's parameter is calibrated on part of the record, and both runs are scored on the part
// the calibration did not see. Documentation/tools-explain.md ("DEM confirmation") has the method.
// The shared machinery is DemRuns.h; the hold confirmations are in DemHoldConfirmations.cc, the
// branch confirmations in DemBranchConfirmations.cc.
//
// Implemented for contact_relaxation (contact law ingredient Relaxing<...>, driver flags --relax_C,
// --relax_t0): the lab holds are split alternately into calibration holds (1st, 3rd, ...) and
// held-out holds (2nd, 4th, ...). Each DEM hold curve is normalised by its stress when the hold's
// clock starts, g_k(t) = sigma_k(t)/sigma_k(0), and predicts the lab hold k as sigma_lab,k(0) g_k(t),
// sigma_lab,k(0) being the mean of the lab hold's first three samples. Runs: baseline (C = 0);
// augmented with the contact C equal to the explainer's macroscopic C; a second augmented run with
// C rescaled by (macroscopic C / DEM macroscopic C on the calibration holds). The augmented run with
// the smaller calibration error is scored on the held-out holds.
//
// And for plasticity (Luding's law, driver flag --k_over_k1; adhesion and relaxation off in every
// run): the lab's unload and reload branches, alternately calibration and held-out, are compared in
// units of each branch's start: u = (e_ref - e) E_load / s_ref, y = s / s_ref (e_ref, s_ref where the
// unload began, E_load the loading tangent over the top 20 % of stress before it); the DEM branch
// y(u) predicts the lab branch as s_ref,lab y_DEM(u_lab). Runs: baseline k/k1 = 1 (elastic);
// k/k1 = the explainer's unloading stiffness ratio; k/k1 from the secant through both runs' measured
// ratios aimed at the recording's; when neither augmented run is within 10 % (of the ratio's excess
// over 1), a fourth run from the secant through the two. The augmented run with the smallest
// calibration error is scored. The protocol's stresses are scaled into the material's range
// (at most kDemMaxStress).
//
// And for wall_friction (driver flag --wall_friction mu_w of the mould, piston and bottom, in the
// cylinder geometry with the recording's aspect ratio H/D; plasticity, adhesion and relaxation off in
// every run, every bed poured with frictionless walls, so that all runs compress the same bed): the
// same branches, normalisation and held-out reloads. Where the recording has a bottom stress sensor,
// mu_w is calibrated on it: the slope of bottom against piston stress on first loading
// (loadingTransmission, Janssen's exp(-4 mu_w K H/D)) falls steadily with mu_w, so runs at mu_w = 0,
// at the recording's own Janssen estimate 2 (-ln T)/(4 H/D), and from the secant on ln T aimed at the
// recording's T (a third secant step when neither is within 10 % of the recording's log loss); the run
// closest to it is scored. A recording whose sensor shows no loss (T not below the frictionless
// mould's) makes the status "contradicted". Without a bottom sensor: runs at mu_w = 0, g, g/2 and 2g
// with g = 2 muK (muK the explainer's Janssen product, K ~ 0.5; at least kMinWallFrictionGuess), the
// augmented run with the smallest unload error scored. The piston-only unloading ratio (y >= 0.6) is
// reported but not aimed at: in a mould of a thousand particles it is not monotone in mu_w
// (Documentation/tools-explain.md).
//
// And for stiffness_nonlinearity (driver flag --hertz_modulus: Hertz's normal force in place of
// Luding's, every other part of the law kept; the non-cohesive frictional material; plasticity,
// adhesion and relaxation off in every run): the branches, normalisation and held-out reloads of
// plasticity, calibrated on the unloading's curvature (unloadCurvature: the tangent at the top over
// the secant to 20 % of the start stress, or to just above the lowest stress the recording's unloads
// reach; 1 for a straight unload). Runs: linear contacts; Hertz
// with E* = hertzModulusMatching / 10 (at hertzModulusMatching itself, where the Hertz force equals
// the linear one at the mean contact force of the top stress, the bed's unloading measured like
// the linear bed's); the secant on the curvature against ln E* aimed at the recording's; a third
// secant step when neither is within 10 % of the recording's excess over the linear bed. The run with
// the smallest calibration error is scored, on each held-out reload followed from its own first sample
// (BranchJudge::StressFromStart, since 2026-12-07: the confirmation's bed is not the record's, and on
// the u scale the strain another bed's unload recovers offsets the whole reload; the u-scale errors
// are reported beside). A recording whose unloading is not more curved than the
// linear bed's (by kCurvatureMargin) makes the status "contradicted", unless the recording's noise
// could hide that much (its curvature plus kCurvatureSpreads spreads, unloadCurvatureSpread: replicas
// with the explainer's noise model, is above the margin): then "inconclusive", since 2026-12-07 (on
// DEM-made Hertz records with noise of 2.5 % of the top stress the curvature read 1.01-1.08 against
// 1.33 without noise, and Hertz was "contradicted"). A last, control run has linear
// contacts whose normal stiffness is the chosen Hertzian run's secant stiffness at the mean contact
// force of the top stress (--normal_stiffness_scale): the unloading curvature comes from contacts that
// are soft under the load, Hertzian or not (measured on 940-particle beds: linear at the secant
// stiffness of E* = 5e7 Pa, 1.37 and 1.44, against Hertz 1.43 and 1.45). The judge is therefore the
// pressure exponent of the unloading stiffness (unloadStiffnessExponent) where the recording unloads
// from two stress levels at least kExponentStressRatio apart: Hertzian contacts stiffen with the force,
// linear ones only through new contacts (measured: records 0.55-0.62, Hertzian runs 0.57-0.60, control
// 0.33-0.38); the law counts as distinguished where the control misses the recording's exponent by
// kExponentMargin more than the chosen run does (and as favouring linear contacts that soft where the
// chosen run misses it by that much more). With one unload level, since 2026-12-07, the held-out reload
// followed from its start judges: a factor kReloadLawRatio between the two runs' errors either way
// (the curvature with kCurvatureMargin before, which practically never told; it still judges where a
// reload error is missing). A failed control leaves the result and skips the judgement.
//
// And for cohesion (since 2026-12-05; driver flags --kc_over_k and --wall_kc_over_k with one value, Luding's law
// with the material's plasticity, relaxation off in every run): only where the protocol pulls on the bed
// (an unload with a negative target stress, the lift-off test; else not_run), since adhesion shows in
// the DEM only in tension. The branches, normalisation and held-out reloads of plasticity; runs at
// kc/k = 0 and at 0.25, 0.5 and 1, the one with the smallest error on the unloads (which end in
// tension) scored on the reloads (which start in it). The largest tension over the start stress is
// reported for the recording and every run.
//
// And for rate_dependence (since 2026-12-07; driver flag --contact_viscous_time, the Maxwell branch on
// the lab clock, relaxation off in every run): calibrated, like contact_relaxation, on the lab holds
// (alternately calibration and held out, the same normalisation g_k(t) = sigma_k(t)/sigma_k(0)), where
// the viscous stress of the ramp before fades. Runs: baseline (no viscosity); the contact viscous time
// tau_a = the explainer's macroscopic tau_v / kRateMacroOverContact; tau_b from the secant of the mean
// hold drop (the stress lost over the last third of the calibration holds, a fraction of the stress at
// the stop) through the baseline and run a, aimed at the recording's. The run with the smaller
// calibration error is scored on the held-out holds. The stress step where the loading speed changes
// without a stop (speedChanges, model-free) is reported for the recording and every run, and not used
// in the choice (a noisy record measures it poorly).
//
// Stiffness_nonlinearity is confirmed only when no other
// accepted mechanism has a DEM counterpart that can run (wall_friction without the device's size
// cannot), or when DemOptions::mechanism names it.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "Explain.h"
#include "Shell.h"
#include "IO/Json.h"

namespace pdpm::recording {
struct Protocol;
}

namespace pdpm::explain {

struct DemOptions {
    std::string mode = "fast";  ///< off | fast (periodic bed, default driver size; wall_friction: a mould 12 mean diameters across) | ft4 (D = H = 50 mm mould; wall_friction: D = 50 mm at the recording's H/D)
    std::string driver;         ///< OedometerRelaxation executable (empty: next to this program)
    /// the accepted mechanism to confirm (empty: the first accepted one with a DEM counterpart)
    std::string mechanism;
    int threads = 1;
    bool figures = true;        ///< dem/comparison.png (gnuplot)
};

/// Largest protocol stress of a plasticity DEM run (Pa): the cocoa material's range (thesis ch. 5).
inline constexpr double kDemMaxStress = 20e3;
/// Largest k/k1 a plasticity DEM run may use.
inline constexpr double kMaxKOverK1 = 50;
/// Largest adhesive stiffness ratio kc/k a cohesion DEM run may use.
inline constexpr double kMaxKcOverK = 2;
/// Largest wall friction coefficient a wall_friction DEM run may use.
inline constexpr double kMaxWallFriction = 1.5;
/// Smallest wall friction coefficient of the first augmented wall_friction run.
inline constexpr double kMinWallFrictionGuess = 0.2;
/// contact_relaxation: when run a's DEM holds (contacts relaxing in the ramps too) fit a t0 more than
/// this many times the contact t0 (median over the calibration holds), the ramp has aged the contacts
/// and run b lets them relax in the holds only (measured on the thesis reconstructions: cocoa 1.23, limestone 547).
inline constexpr double kRampAgedT0Ratio = 3;
/// rate_dependence: the surrogate's macroscopic tau_v over the contact viscous time of the first
/// augmented run (--contact_viscous_time); the secant on the hold drop corrects it. Measured on the
/// DEM-made rate records: 6-12.
inline constexpr double kRateMacroOverContact = 8;
/// rate_dependence: the contact viscous time (lab s) of a run stays within [1e-3, kMaxContactViscousTime].
inline constexpr double kMaxContactViscousTime = 20;
/// rate_dependence: a change of the loading speed counts as one where the strain rates on its two
/// sides differ by at least this factor (speedChanges).
inline constexpr double kRateChangeFactor = 2;
/// Mean particle diameter of the DEM runs (m; the driver's --d_mean, cocoa).
inline constexpr double kDemMeanDiameter = 2.5e-3;
/// Mould diameter of a wall_friction DEM run in `fast` mode, in mean particle diameters (the height
/// follows from the recording's H/D).
inline constexpr double kFastMouldDiameters = 12;

/// Stiffness k (N/m) of the linear contacts of the DEM runs (the cocoa material, thesis Table 5.3).
inline constexpr double kDemContactStiffness = 24067;
/// Volume fraction times coordination number of the poured DEM bed at a few kPa (0.55-0.6 x 4.5-5),
/// in the mean contact force f = pi d^2 sigma / (3 phi Z) of hertzModulusMatching.
inline constexpr double kDemPackingPhiZ = 2.7;
/// stiffness_nonlinearity: the softest Hertzian run has E* = hertzModulusMatching / kHertzSoftest.
inline constexpr double kHertzSoftest = 1000;
/// stiffness_nonlinearity: how far the recording's unloading curvature must exceed the linear bed's
/// (about three times the bed-to-bed scatter of the linear bed's, +-0.04).
inline constexpr double kCurvatureMargin = 0.1;
/// stiffness_nonlinearity: samples of the running mean on which the curvature's window ends are found.
inline constexpr int kCurvatureSmoothing = 9;
/// stiffness_nonlinearity: a recording is "contradicted" only where its curvature plus this many of its
/// noise spreads (unloadCurvatureSpread) is still not above the linear bed's by kCurvatureMargin;
/// where the noise could hide the excess the status is "inconclusive".
inline constexpr double kCurvatureSpreads = 2;
/// stiffness_nonlinearity: the unloading curvature's secant ends where the unload reaches this fraction
/// of its start stress, or just above the lowest stress of the recording's unloads when they stop
/// higher, but not above kCurvatureMaxLowY (then: not_run).
inline constexpr double kCurvatureLowY = 0.2, kCurvatureMaxLowY = 0.6;
/// stiffness_nonlinearity: the unloading stiffness's pressure exponent needs unloads whose start
/// stresses differ by at least this factor; the control run tells the law apart where its exponent
/// misses the recording's by kExponentMargin more than the chosen Hertzian run's.
inline constexpr double kExponentStressRatio = 2, kExponentMargin = 0.1;
/// stiffness_nonlinearity with one unload level: the held-out reload, followed from its start, tells
/// the law where one of the chosen Hertzian run and the control misses it by at least this factor more
/// than the other (measured 2026-12-07: on Hertzian records the control 3.5-28 times the Hertzian run,
/// on records of linear contacts as soft 0.08-0.22 times; Documentation/tools-explain.md).
inline constexpr double kReloadLawRatio = 2;
/// stiffness_nonlinearity: which contacts the control run's judgement favours.
enum class ContactLaw {
    NotTold,       ///< the chosen Hertzian run and the linear control are about as close to the recording
    Hertz,         ///< the control is clearly further: the record needs Hertz's force law
    LinearAsSoft,  ///< the control is clearly closer: linear contacts that soft, not Hertz's law
};
const char* contactLawName(ContactLaw law);
/// The judgement from the two runs' misses of the recording's exponent or curvature: Hertz where the
/// control misses by more than `margin` beyond the Hertzian run, LinearAsSoft the other way round.
ContactLaw favouredLawByMiss(double hertzMiss, double controlMiss, double margin);
/// The judgement from the two runs' held-out errors: Hertz where the control's is at least `ratio`
/// times the Hertzian run's, LinearAsSoft the other way round.
ContactLaw favouredLawByRatio(double hertzError, double controlError, double ratio);
/// stiffness_nonlinearity, fast mode: a laterally periodic bed of about 940 particles (the driver's
/// default 180-particle bed is dominated by collapses).
inline constexpr const char* kNonlinearityFastBed = "--width 10 --fill_height 10";

/// Effective Young's modulus E* whose Hertz force (4/3) E* sqrt(R delta) delta equals the linear force
/// k delta at the overlap delta = f/k of the mean contact force f = pi d^2 stress / (3 phi Z) between two
/// spheres of diameter d (R = d/4) under the bulk stress `stress` (Pa).
double hertzModulusMatching(double k, double d, double stress);
/// Secant stiffness f / delta (N/m) of Hertz's force (4/3) E* sqrt(R delta) delta, R = d/4, at the mean
/// contact force f = pi d^2 stress / (3 phi Z) (the inverse of hertzModulusMatching).
double hertzSecantStiffness(double modulus, double d, double stress);
/// Pressure exponent of the unloading stiffness of a record (time, strain, stress): ln(T_hi/T_lo) /
/// ln(S_hi/S_lo) between its unloads with the highest and lowest start stress S (T: the tangent
/// dsigma/deps over the unload's top 20 % of stress); NaN with fewer than two unloads or S_hi below
/// kExponentStressRatio S_lo. About 1/3 for Hertzian contacts on a fixed network, 0 for linear ones.
double unloadStiffnessExponent(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s);
/// A change of the loading speed inside one loading (no stop), found model-free in a record.
struct RateChange {
    std::size_t index = 0;  ///< first sample of the second piece
    double time = 0;        ///< s, where the two straight pieces of strain against time meet
    double rateRatio = 1;   ///< strain rate after over before
    /// the stress step at the change over the stress there, (R(e_c) - L(e_c)) / L(e_c) at the strain e_c
    /// where the two pieces meet, with L and R
    /// straight lines of stress against strain over the last 40 % of the samples before it (at least 4)
    /// and from an eighth to a half of those after it (at least 4; the first eighth left out: a viscous
    /// stress builds up there), signed so that a stress that grows with the rate gives a positive step
    /// at a speed-up and at a slow-down
    double step = 0;
};
/// The loading-speed changes of a record (time, strain, stress): in every loading (Load or Reload phase
/// of detectPhases) the split of strain against time into two straight pieces with the least squared
/// error, kept where the two rates differ by kRateChangeFactor and each side has 8 samples or more.
std::vector<RateChange> speedChanges(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s);
/// Mean of the steps of speedChanges (NaN without a change).
double meanRateStep(const std::vector<RateChange>& changes);

struct DemRun {
    std::string name;
    double relaxC = 0, relaxT0 = 0;  ///< contact_relaxation runs
    bool relaxInRamps = true;        ///< contact_relaxation runs: the contacts relax in ramps and unloads too
    double kOverK1 = 0;              ///< plasticity runs
    double wallFriction = 0;         ///< wall_friction runs (mu_w)
    double hertzModulus = 0;         ///< stiffness_nonlinearity runs (E*, Pa; 0: linear contacts)
    double kcOverK = 0;              ///< cohesion runs (Luding kc/k of the particle pairs and the walls)
    double viscTime = 0;             ///< rate_dependence runs: the contact viscous time (lab s)
    /// rate_dependence: meanRateStep of the run's record (NaN: no speed change)
    double rateStep = std::numeric_limits<double>::quiet_NaN();
    double normalStiffnessScale = 1; ///< stiffness_nonlinearity's control run: its linear k over the material's
    /// stiffness_nonlinearity: the unloading stiffness's pressure exponent (NaN: fewer than two unloads far enough apart)
    double exponent = std::numeric_limits<double>::quiet_NaN();
    /// bottom/piston stress ratio of the first loading (-1: no bottom stress recorded)
    double transmission = -1;
    double calibrationRmse = -1, heldoutRmse = -1;  ///< Pa
    double heldoutBottomRmse = -1;  ///< wall_friction with a bottom sensor: the held-out branches' bottom stress (Pa)
    /// stiffness_nonlinearity, whose held-out error judges each reload from its own start
    /// (BranchJudge::StressFromStart): the error on the u scale as well (BranchJudge::Stress, Pa), reported only
    double heldoutUScaleRmse = -1;
    /// contact_relaxation: mean fitted C of the DEM calibration holds; rate_dependence: their mean stress
    /// drop (a fraction of the stress at the stop, over the last third of each hold); plasticity, wall_friction:
    /// unloading stiffness ratio measured on the DEM calibration branches; stiffness_nonlinearity: their
    /// unloading curvature
    double macro = -1;
    double wallSeconds = 0;
    std::string command;
};

struct DemResult {
    /// done | not_run | not_needed | not_supported | failed | contradicted (the recording's own
    /// bottom sensor shows no stress lost to the walls although wall_friction was accepted; its unloads
    /// are not more curved than the linear bed's although stiffness_nonlinearity was) | inconclusive
    /// (stiffness_nonlinearity: the unloads look no more curved than the linear bed's, but the
    /// recording's noise could hide the difference)
    std::string status = "not_run";
    std::string reason, mechanism;
    std::vector<DemRun> runs;
    int chosen = -1;  ///< index of the scored augmented run
    /// stiffness_nonlinearity: index of the control run (linear contacts as soft as the chosen
    /// Hertzian ones at the top stress; -1: none), and which law its judgement favours (lawJudge: by the
    /// unloading stiffness exponent, else the reload from its start, else the curvature); Hertz where
    /// the control misses the recording clearly more than the chosen run does
    int control = -1;
    ContactLaw contactLaw = ContactLaw::NotTold;
    /// whether the control run told Hertz's law apart (contactLaw == Hertz; report.json contact_law_distinguished)
    bool contactLawDistinguished() const { return contactLaw == ContactLaw::Hertz; }
    /// unload_stiffness_exponent | reload_from_its_start | unload_curvature (empty: not judged)
    std::string lawJudge;
    /// stiffness_nonlinearity: whether the pressure exponent of the unloading stiffness judged the control
    /// (the recording's, the chosen run's and the control's all measured), else the curvature did
    bool judgedByExponent = false;
    /// stiffness_nonlinearity: the recording's unloading stiffness exponent (NaN: fewer than two unload levels)
    double labExponent = std::numeric_limits<double>::quiet_NaN();
    /// stiffness_nonlinearity: why the control run is missing (it failed; the result stands, the law is not judged)
    std::string controlNote;
    int calibrationHolds = 0, heldoutHolds = 0;  ///< holds (contact_relaxation) or unload/reload branches (the others)
    double stressScale = 1;   ///< plasticity, wall_friction: factor applied to the protocol's stresses
    /// rate_dependence: the recording's mean hold drop (calibration holds);
    /// plasticity, wall_friction: the recording's unloading stiffness ratio (calibration branches);
    /// stiffness_nonlinearity: the recording's unloading curvature (calibration branches)
    double labMacro = -1;
    /// stiffness_nonlinearity: the spread of the recording's curvature from its noise (unloadCurvatureSpread)
    double labMacroSpread = 0;
    /// rate_dependence: the recording's loading-speed changes and their mean step (NaN: none)
    int rateChanges = 0;
    double labRateStep = std::numeric_limits<double>::quiet_NaN();
    /// contact_relaxation: run a's fitted hold t0 over the contact t0, median over the calibration holds (-1: no fit)
    double rampAgedT0Ratio = -1;
    double surrogateValue = -1;  ///< stiffness_nonlinearity: the explainer's exponent n
    double mouldDiameter = 0, mouldHeight = 0;  ///< wall_friction: the DEM mould (m)
    double recordingAspect = 0;  ///< wall_friction: the recording's H/D (the mould's differs where it cannot be kept)
    /// plasticity, wall_friction: the unloading ratio's window, unload samples with y >= ratioYMin;
    /// stiffness_nonlinearity: where the curvature's secant ends (fraction of the start stress)
    double ratioYMin = 0;
    /// plasticity, wall_friction: unload_ratio_secant | unload_error_grid | bottom_over_piston_secant
    std::string calibration;
    /// bottom_over_piston_secant: the recording's bottom/piston ratio on its first loading, and the
    /// value aimed at in the DEM mould (the same where the mould keeps the recording's H/D)
    double labTransmission = -1, transmissionTarget = -1;
    double heldoutBaseline = -1, heldoutAugmented = -1;
    /// wall_friction with a bottom sensor: the held-out branches' bottom stress (Pa), the second
    /// channel of the same held-out part (-1: not recorded)
    double heldoutBottomBaseline = -1, heldoutBottomAugmented = -1;
    /// stiffness_nonlinearity: the held-out errors on the u scale (BranchJudge::Stress), beside the judged
    /// ones from each reload's start (-1: not measured)
    double heldoutUScaleBaseline = -1, heldoutUScaleAugmented = -1;
    double wallSeconds = 0;
};

/// The OedometerRelaxation executable next to the running program ("OedometerRelaxation" if unknown).
std::string defaultDemDriver();
using tools::shellQuote;  // Common/Shell.h

/// Whether a DEM confirmation exists for the mechanism (contact_relaxation, plasticity, wall_friction,
/// stiffness_nonlinearity, cohesion, rate_dependence).
bool demSupported(int comp);
/// Whether a protocol pulls on the bed: an unload with a negative target stress (the lift-off test), the
/// only place where the DEM's adhesion shows (cohesion's confirmation needs one).
bool pullsOnTheBed(const recording::Protocol& p);

/// Runs the confirmation for the first accepted mechanism of `r` that has one (workDir receives the runs).
DemResult confirmWithDem(const ExplainResult& r, const Recording& rec, const std::string& protocolPath,
                         const DemOptions& opt, const std::string& workDir);

/// The report.json block "dem_confirmation".
Json demJson(const DemResult& d);
/// Plain-words paragraph for report.md.
std::string demMarkdown(const DemResult& d);

} // namespace pdpm::explain
