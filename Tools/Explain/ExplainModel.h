// pdpm-explain: the macroscopic oedometric surrogate (baseline + nuisances + mechanism terms), a
// bounded Levenberg-Marquardt fitter, and the noise model.
//
// The model maps the recorded strain history eps(t) (the control channel, compression positive) to
// the axial stress at the piston. Every mechanism is a term that is exactly "off" at one value of
// its parameter, so a model with the mechanism nests the baseline.
//
//   baseline        virgin loading  s_v(e) = E * e_r * ((e - e0)_+ / e_r)^n, n = 1 (linear elastic);
//                   unloading / reloading below the largest strain so far along the same curve
//   stiffness_nonlinearity   n != 1 (power law; off: n = 1)
//   plasticity      unloading branch  s = lam * s_v(e) - (lam - 1) * s_v(e_max)  (off: lam = 1),
//                   i.e. lam times stiffer than loading, leaving a strain at zero stress
//   cohesion        sigma_c (off: 0): the unloading branch continues below zero force into tension
//                   down to -sigma_c (only after first contact), and the cohesive loose packing gives
//                   an extra first-loading compliance of strain scale x_c = sigma_c/E (first-loading
//                   curve E x^2/(x + x_c); the collapse is permanent, unload/reload keep the deficit;
//                   with loading_curve in the model the curve takes that shape: x_c = 0)
//   contact_relaxation  during each hold (constant strain) the stress decays as thesis Eq. 4.3,
//                   s = s_h (1 + (t - t_h)/t0)^(-C) (off: C = 0); after the hold the deficit is
//                   recovered over the strain the loading curve needs to make it up
//   rate_dependence viscous stress E * tau_v * d(eps)/dt (off: tau_v = 0)
//   wall_friction   Janssen factor: piston stress = inner stress * u/(1 - exp(-u)),
//                   u = m * 4 muK H(eps)/D, m = +1 loading, -1 unloading (mobilised over 2 % of the
//                   strain range); off: muK = 0
//   rolling_resistance  acts on the lateral stress / q-p ratio only: not testable on axial stress
//   loading_curve   (baseline only, never a candidate) a free shape of the skeleton curve: s_v(e) is
//                   multiplied by 1 + c(e), c piecewise linear in strain through knots at every virgin
//                   hold strain (a virgin creep step: the largest strain it reaches) and at most epsRange/8 apart, the last held at 0 (E sets the level; off: every knot 0). A function of strain
//                   alone, so it cannot imitate anything that happens at constant strain (hold decay,
//                   rate steps); it absorbs stiffness_nonlinearity, which is then not tested
//   hysteresis      (baseline only, never a candidate) the unload-reload loop of a frictional bed:
//                   below the largest strain the model above gives the branch value L(e) (the
//                   plasticity line, clamped at the cohesion floor); an unload from a reversal point
//                   (L_a, s_a) follows s = s_a (L/L_a)^h_u while L > 0 (s = L below), a reload
//                   s = s_a + (s_top - s_a) v^h_r, v = (L - L_a)/(s_top - L_a), back to the top of the
//                   branch at the largest strain (off: h_u = h_r = 1, i.e. s = L). An unload from a
//                   reversal in tension (L_a < 0 or s_a < 0) runs parallel to L; the result is floored at the
//                   cohesion tension, and the term acts only after first contact. A reversal is
//                   committed after a strain turn of more than 0.5 % of the strain range (inside that
//                   band the new branch is already followed: continuous at every turn)
//   relaxation_stress_dependence  (a refinement of contact_relaxation, never a candidate; inert
//                   without it) the C of each hold depends on the stress at its start,
//                   C_h = C (s_h / s_ref)^(-beta), s_ref = ModelInput::holdStressRef (off: beta = 0);
//                   C is then the value at s_ref. Tested by explain() after the mechanisms are chosen.
//   instrument_compliance (nuisance)  eps_true = eps_meas - kappa/E * stress (off: kappa = 0)
//   sensor_drift (nuisance)           stress + a + b (t - t_0) (off: a = b = 0)
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "ExplainData.h"

namespace pdpm::explain {

enum Comp : int {
    kBaseline = 0,
    kCompliance,
    kDrift,
    kRelaxation,
    kPlasticity,
    kCohesion,
    kWallFriction,
    kRate,
    kNonlinearity,
    kRolling,
    kLoadingCurve,
    kHysteresis,
    kRelaxStress,
    kNumComp
};
constexpr int kLastMechanism = kRolling;  ///< mechanisms are kRelaxation..kLastMechanism

/// Public names: "contact_relaxation", "instrument_compliance", ...
const char* compName(int c);
int compFromName(const std::string& name);  ///< -1 if unknown
bool isNuisance(int c);
bool isMechanism(int c);

/// Fixed parameters; the loading_curve knots follow from index kNumPar on (Model::knotStrains()).
enum Par : int {
    pE = 0, pEps0, pKappa, pOffset, pDrift, pRelaxC, pRelaxT0, pLambda, pTension, pMuK, pTauV, pExpN, pUnloadExp, pReloadExp, pRelaxBeta, kNumPar
};

struct ParDef {
    const char* name;
    const char* unit;
    int comp;
    double lo, hi;
    double off;     ///< value at which the term vanishes (NaN: none, e.g. t0)
    double scale;   ///< typical size (internal coordinate = value/scale), ignored for log params
    bool logScale;
};

/// Everything the model needs about one recording, precomputed once.
struct ModelInput {
    std::vector<double> t, eps, rate;
    std::vector<char> hold;   ///< 1 where the control channel holds
    std::vector<char> creep;  ///< 1 in the creep steps (constant stress) of the protocol (also hold)
    double height = 0.06, diameter = 0.149;
    double epsRange = 1, epsMin = 0, stressMax = 1, duration = 1;
    /// reference stress of relaxation_stress_dependence: geometric mean of the recorded stress at the
    /// first sample of every hold with a positive stress (stressMax / 2 when there is none)
    double holdStressRef = 0.5;
    /// The record's strain rate changes only where the piston stops or starts: loads at one speed
    /// (the median rates of all Load phases within 20 % of each other) and holds, no unloading, reload
    /// or creep step. There the viscous step of rate_dependence at a hold's start is the fast first
    /// drop of contact relaxation, and its step at a ramp's start the reload's stiffness: the protocol
    /// cannot tell them apart, so rate_dependence is not screened (Explain.cc, screenCandidate).
    bool rateChangesOnlyAtStops = false;
    /// the protocol's device.zero_before_contact: first contact (eps0)
    /// at or after the first sample's strain: the bed is not loaded before the record begins
    bool contactAtStart = false;
};

ModelInput makeModelInput(const Recording& rec, const Protocol& proto);

class Model {
public:
    explicit Model(const ModelInput& in);
    const ModelInput& input() const { return in_; }
    const std::vector<ParDef>& defs() const { return defs_; }
    /// A parameter vector with every term off and a rough baseline guess.
    std::vector<double> defaults() const;
    /// Stress at every sample, with the components flagged in `on` (on[kBaseline] is implied).
    void evaluate(const std::vector<double>& p, const std::vector<char>& on, std::vector<double>& out) const;
    /// Parameter indices that belong to component c.
    std::vector<int> paramsOf(int c) const;
    /// Narrows the sensor drift to |drift_rate| <= fraction * stressMax / duration (stressMax: the
    /// largest recorded |stress|).
    void limitDrift(double fraction);
    /// With loading_curve on, a drift shows only in the holds, where it would take their decay: the
    /// drift is bounded to 2 % of stressMax over the record. Every fit with loading_curve calls this.
    void limitsForLoadingCurve(bool loadingCurveOn) {
        if (loadingCurveOn) limitDrift(0.02);
    }
    /// Strains of the loading_curve knots (parameter kNumPar + k belongs to knot k; the last knot has none).
    const std::vector<double>& knotStrains() const { return knots_; }

private:
    /// State of the hysteresis term along one evaluation (see the header comment).
    struct Loop {
        double hu = 1, hr = 1, turn = 0;      ///< exponents; strain turn that counts as a reversal
        bool virgin = true, up = false;       ///< on the virgin curve; reloading (else unloading)
        double aL = 0, aS = 0, ext = 0, extL = 0;  ///< reversal point (branch value, stress); extreme strain and its L
        /// Stress at strain e whose loop-free branch value is L; top: the branch value at the largest
        /// strain; floor: the cohesion tension (negative) or 0.
        double branch(double e, double L, double top, double floor);
    };
    double curveFactor(const std::vector<double>& p, double e) const;  ///< 1 + c(e) of loading_curve
    ModelInput in_;
    std::vector<ParDef> defs_;
    std::vector<double> knots_;
};

struct FitResult {
    std::vector<double> p;
    double rss = 0;            ///< weighted (and, with a whitener, whitened) residual sum of squares
    std::vector<double> model; ///< prediction at every sample
    std::vector<double> se;    ///< standard errors (physical units; 0 for fixed parameters)
    int iterations = 0;
};

/// Innovation filter of AR(1) + white noise, written as ARMA(1,1): e_i = x_i - phi x_{i-1} + theta e_{i-1}
/// (the first sample of every contiguous kept stretch scaled by `startScale`). Identity by default.
struct Whitener {
    double phi = 0, theta = 0, startScale = 1;
    bool identity() const { return phi == 0 && theta == 0 && startScale == 1; }
    /// In place; samples with w[i] == 0 are set to 0 and restart the filter.
    void apply(std::vector<double>& x, const std::vector<double>& w) const;
};

struct FitOptions {
    std::vector<int> freeParams;
    std::vector<double> weights;  ///< 0/1 mask (empty: all 1)
    Whitener whitener;            ///< generalised least squares: the cost is the whitened residual energy
    double covInflation = 1.0;    ///< n / n_eff, multiplies the covariance
    int maxIterations = 80;
};

/// Bounded Levenberg-Marquardt from start `p0`.
FitResult fitModel(const Model& m, const std::vector<double>& y, const std::vector<char>& on,
                   const std::vector<double>& p0, const FitOptions& opt);

/// Noise model from a residual: marginal sd, lag-1 autocorrelation (AR(1)) and the effective
/// sample size. Estimated from robust (trimmed) variances of lag-k differences,
/// v_k = 2 s2 (1 - rho^k) + 2 w, k = 1..10 (AR(1) part s2, rho plus a white part w such as
/// quantisation), so smooth misfit does not count as noise. n_eff = n (s2 + w) / (s2 (1+rho)/(1-rho) + w),
/// i.e. n(1-rho)/(1+rho) for pure AR(1).
struct NoiseModel {
    double sigma = 0, rho = 0, nEff = 0;  ///< total sd, lag-1 coefficient of the AR(1) part, n_eff
    double arVar = 0, whiteVar = 0;       ///< variance of the AR(1) part and of the white part
    std::size_t n = 0;
    /// The innovation filter of this noise model (exact ARMA(1,1) form of AR(1) + white).
    Whitener whitener() const;
    double innovationVar() const;  ///< variance of the innovations of whitener()
};
/// `segment` (optional, same length): phase id of each sample, -1 to exclude it; only differences
/// within one phase enter, so that misfit jumps at phase changes are not taken for noise.
NoiseModel estimateNoise(const std::vector<double>& resid, const std::vector<int>& segment = {});
/// Segment ids for estimateNoise: the protocol phases of a strain history, with `margin` samples at
/// each end of every phase excluded (-1).
std::vector<int> noiseSegments(const std::vector<double>& t, const std::vector<double>& strain, std::size_t margin = 3);

/// Block chi-square test of "the residual is zero-mean AR(1) noise": block means over blocks much
/// longer than the correlation time, each divided by its exact AR(1) standard deviation. Returns
/// the upper-tail p-value (Wilson-Hilferty), with `dofRemoved` fitted parameters.
double blockChiSquarePValue(const std::vector<double>& resid, const NoiseModel& nm, int dofRemoved,
                            double* statistic = nullptr, int* blocks = nullptr);

/// Upper tail of the standard normal.
double normalUpperTail(double z);

} // namespace pdpm::explain
