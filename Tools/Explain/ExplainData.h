// pdpm-explain: input data (recording + protocol), phase detection.
//
// Reads the recording format (Documentation/recording-format.md): the protocol JSON through the
// shared recording library (Tools/Recording), the CSV with the strict CSV reader, keeping the
// channels the explainer uses (time_s, axial_strain or piston_position_m, axial_stress_Pa,
// lateral_stress_Pa).
//
// The explainer treats the axial strain (compression positive) as the control channel and the
// axial stress as the response. The strain comes from `axial_strain`, or else from
// `piston_position_m` and the protocol's geometry.height_m (strain = (z0 - z) / height).
#pragma once
#include <string>
#include <vector>

namespace pdpm::recording {
struct Protocol;
}

namespace pdpm::explain {

enum class StepType { Ramp, Hold, Unload, Creep };

struct ProtocolStep {
    StepType type = StepType::Ramp;
    double velocity = -1;      ///< m/s, <0: not given
    double targetStress = -1;  ///< Pa, <0: not given
    double duration = -1;      ///< s, <0: not given
    double tension = 0;        ///< unload into tension (lift-off test): the target tension, Pa (> 0; 0: none)
};

struct Protocol {
    std::string device;
    double diameter = 0;  ///< m
    double height = 0;    ///< m (initial fill height)
    std::string material;
    bool zeroBeforeContact = false;  ///< device.zero_before_contact (Documentation/recording-format.md)
    std::vector<ProtocolStep> steps;
    std::string source;
};

struct Recording {
    std::vector<double> t;       ///< s, strictly increasing
    std::vector<double> strain;  ///< axial strain, compression positive
    std::vector<double> stress;  ///< axial stress at the piston, Pa
    std::vector<double> lateral; ///< lateral stress, Pa (empty if not recorded)
    std::vector<double> bottom;  ///< stress on the bottom plate, Pa (empty if not recorded)
    /// protocol step index of each sample (the `step` column; empty if not recorded). With it, the
    /// samples of a creep step (hold_stress) are known exactly (creepSamples()).
    std::vector<int> step;
    std::string source;
    std::string strainSource;    ///< "axial_strain" or "piston_position_m"
    std::size_t size() const { return t.size(); }
};

/// Protocol JSON in the documented format (Documentation/recording-format.md, read by the shared
/// recording library); InputError with a clear message on anything malformed.
Protocol readProtocol(const std::string& path);
/// The explainer's protocol in the documented format (for the generators).
recording::Protocol toRecordingProtocol(const Protocol& p);
/// Recording CSV; needs the protocol for piston-position recordings. InputError when malformed,
/// when the control or response channel is missing, or when it is inconsistent with the protocol.
Recording readRecording(const std::string& path, const Protocol& proto);
/// Cross-checks (durations vs record length, stress levels); InputError on inconsistency.
void checkConsistency(const Recording& rec, const Protocol& proto);

const char* stepTypeName(StepType t);

/// 1 for the samples of creep (hold_stress) steps: from the recording's `step` column and the
/// protocol's step types; all 0 without a step column. During a creep step the strain moves at
/// constant stress, so the strain rate alone labels its start a loading (detectPhases).
std::vector<char> creepSamples(const Recording& rec, const Protocol& proto);

/// Phase of each sample derived from the control channel.
enum class Phase { Load, Hold, Unload, Reload };
const char* phaseName(Phase p);

struct PhaseSegment {
    Phase phase;
    std::size_t begin, end;  ///< sample range [begin, end)
};

/// Smoothed strain rate (local linear regression over a centred window).
std::vector<double> smoothedRate(const std::vector<double>& t, const std::vector<double>& x, int halfWindow);
/// Phase segments of a strain history: hold where |rate| is below 2 % of the typical ramp rate (the
/// 95th percentile of |rate|, or, when that is below 10 % of the mean |rate| (ramps under 5 % of the
/// record), the median of the samples moving faster than that),
/// load / reload (below the previous maximum strain) / unload otherwise; short pieces merged.
std::vector<PhaseSegment> detectPhases(const std::vector<double>& t, const std::vector<double>& strain);
/// The exact extent of a hold found by detectPhases. The detector smooths the strain rate over about
/// size/800 samples on either side, so it finds a hold that many samples late and ends it that many
/// early; where the control channel is exactly constant over the hold (a stopped piston recorded
/// without noise) the run of equal strain (within 1e-9 relative) around the hold's middle gives its true
/// first and last sample, looked for no further than 2*(size/800)+3 samples beyond the detected ends (so
/// that a quantised strain channel on a slow ramp cannot pull the start into the ramp). When that run
/// covers less than half of the detected hold (a noisy control channel) the detected extent is kept;
/// otherwise the run's last sample is left out unless the record ends there (it may be the first
/// sample of the next ramp, which starts from the hold's strain).
/// A hold with a relaxation time below the sampling interval loses several per cent of its stress in
/// the samples the detector misses: every fit of a hold starts from this extent.
PhaseSegment holdExtent(const std::vector<double>& strain, const PhaseSegment& hold);
/// How far (samples) beyond a detected hold's ends holdExtent looks in a record of n samples: 2*(n/800)+3.
std::size_t holdReach(std::size_t n);
/// Whether a strain sample equals a hold's strain eh within holdExtent's tolerance (1e-9 relative).
bool atHoldStrain(double strain, double eh);
/// The phases of a recording as pdpm-explain reports them: detectPhases, except that every creep step
/// of the protocol (creepSamples: the recording's `step` column names a hold_stress step) is one Hold
/// segment from its first sample to its last. A creep step moves the strain, fast at its start, so the
/// strain rate alone calls its start a loading; it is a hold of the stress.
std::vector<PhaseSegment> recordPhases(const Recording& rec, const Protocol& proto);
/// The bottom plate's share of the piston stress on the first loading (its Load phases and the holds
/// that follow a load, before the first unload), from the strain at which the loading passes 30 % of
/// its largest piston stress on: the line b = intercept + slope * s of the bottom stress b against the
/// piston stress s, the slope estimated with the strain as instrumental variable (cov(b, e)/cov(s, e),
/// not biased by the piston stress's own noise). For a bed loaded from the top in a mould with wall
/// friction (Janssen) the slope is exp(-4 mu_w K H/D) and the intercept the part of the bed's weight
/// that reaches the bottom; without wall friction the slope is 1. Holds keep the transmission of the
/// loading before them (the wall shear stays mobilised while the piston stands).
/// Smallest share of the piston stress lost to the walls on loading that the bottom sensor reports
/// as wall friction (a 3 % gain mismatch between two load cells is within a lab's calibration).
inline constexpr double kMinWallLoss = 0.03;
struct Transmission {
    double slope = -1;     ///< -1: no bottom channel, or fewer than 5 such samples
    double intercept = 0;  ///< Pa
    double se = -1;        ///< standard error of the slope, the residuals' lag-1 autocorrelation allowed for
    int samples = 0;
    double residualSd = 0;  ///< sd of b - intercept - slope * s (Pa)
    double nEff = 0;        ///< effective number of samples, n (1 - r)/(1 + r)
    /// blocked cross-validation (the samples cut into 4 contiguous parts, each predicted from the
    /// other three): RMSE of the bottom stress with no loss (the slope fitted on the other parts,
    /// clamped into the no-loss band [1 - kMinWallLoss, 1]; intercept fitted) and with the fitted
    /// line (Pa); -1 when not computed
    double heldoutNoLoss = -1, heldoutFitted = -1;
};
Transmission loadingTransmission(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                 const std::vector<double>& b);

} // namespace pdpm::explain
