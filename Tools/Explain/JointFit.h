// pdpm-explain with several recordings: one set of material parameters for all of them.
//
// A mechanism's parameters (C and t0, lambda, sigma_c, muK, tau_v, n) are material constants; the
// recordings' device parameters (E, eps0, compliance and drift — both free in every recording, whether
// or not its own selection kept them, unless the compliance is calibrated —, the loading-curve knots,
// and the other mechanisms a recording accepted on its own) are not. The joint fit maximises the likelihood of all
// recordings together over the shared material parameters, with every recording's device parameters
// refitted at each trial value (a profile likelihood): -2 ln L = sum_k n_k ln RSS_k + const, RSS_k the
// whitened (GLS, the recording's own AR(1)+white noise model) residual energy of recording k.
//
//   - estimate: Nelder-Mead on the profile, in the fitter's internal coordinates (log10 for t0 and
//     lambda), started from the best of the recordings' own estimates;
//   - 95 % intervals: with one material parameter, the likelihood-ratio interval of the profile
//     (-2 ln L within 3.84 of its minimum; scanned outwards with continuation, so that a ridge such as
//     n against the instrument compliance widens it); with several (C and t0), from the curvature of
//     the profile at the optimum (finite-difference Hessian H of -2 ln L in internal coordinates,
//     covariance 2 H^-1);
//   - consistency: each recording is also fitted with its own material parameters; the likelihood
//     ratio Lambda = -2 ln L(joint) + 2 ln L(separate) is compared with chi-square with
//     (recordings - 1) x (material parameters) degrees of freedom. p < kJointConsistencyLevel says
//     the recordings need different values: the effective parameter depends on the device, the
//     geometry or the rate (as the thesis' cocoa: C 0.079 in the lambdameter, 0.044 in the FT4).
//
// Documentation/tools-explain.md ("Several recordings", "One set of material parameters").
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "Explain.h"

namespace pdpm::explain {

/// p-value below which the recordings' separate material parameters are taken to differ.
inline constexpr double kJointConsistencyLevel = 0.01;

struct JointFit {
    int comp = -1;
    std::vector<std::size_t> recordings;  ///< indices of the recordings fitted together
    /// the shared parameters: indices, joint values and 95 % intervals (as a single recording's)
    MechanismResult joint;
    /// per entry of `recordings`: the values of the shared parameters fitted on that recording alone
    std::vector<std::vector<double>> separate;
    double m2lnLJoint = 0, m2lnLSeparate = 0;  ///< -2 ln L up to the same constant
    double statistic = 0;                      ///< likelihood ratio m2lnLJoint - m2lnLSeparate (>= 0)
    /// per entry of `recordings`: its own part of the likelihood ratio, n_k ln RSS_k at the joint
    /// optimum (device refitted there) minus at its own values, clamped at 0. They add up to about
    /// `statistic`. A part grows with how far the recording's own values sit from the joint ones and
    /// with its precision, so with three or more recordings the largest part usually points at the one
    /// that differs (a pointer, not a test: two imprecise recordings that agree can outweigh it).
    std::vector<double> recordingStatistic;
    int dof = 0;
    double pValue = 1;
    bool consistent = true;  ///< pValue >= kJointConsistencyLevel
    int evaluations = 0;     ///< profile evaluations (each refits every recording's device parameters)
    /// per entry of `recordings`: n_k ln RSS_k with the recording's own material parameters (its term
    /// of m2lnLSeparate)
    std::vector<double> recordingOwnTerm;
    /// With three or more recordings, each one left out in turn (leaveOneOut): the likelihood ratio of
    /// "all share one set" against "the others share one set, this one has its own", chi-square with
    /// (material parameters) dof. The recording differs from the others when the others are consistent
    /// among themselves (their own joint fit) and p < kJointConsistencyLevel; when the others disagree
    /// among themselves as well, leaving this one out does not explain the inconsistency.
    struct LeftOut {
        std::size_t recording = 0;
        double statistic = 0, pValue = 1;
        int dof = 0;
        bool othersConsistent = true;
        bool differs = false;
    };
    std::vector<LeftOut> leftOut;
    /// how the 95 % intervals were found: profile_likelihood_ratio (one material parameter: where
    /// -2 ln L rises by 3.84 along the profile), profile_curvature (several), or not_determined (the
    /// profile is not curved upwards at the optimum; the intervals are the parameters' whole ranges)
    std::string intervalMethod;
};

/// Upper tail of the chi-square distribution with `dof` degrees of freedom.
double chiSquareUpperTail(double x, int dof);

/// The joint fit of mechanism `comp` over the recordings `which` (at least two).
JointFit fitJointly(int comp, const std::vector<std::size_t>& which, const std::vector<Recording>& recs,
                    const std::vector<Protocol>& protos, const std::vector<ExplainResult>& per);

/// Fills J.leftOut when J has three or more recordings: for each recording k, the joint fit of the
/// others (fitJointly) and the likelihood ratio m2lnLJoint(all) - m2lnLJoint(others) - (k's own term),
/// which tests whether k shares the others' material parameters whatever they are among themselves.
void leaveOneOut(JointFit& J, const std::vector<Recording>& recs, const std::vector<Protocol>& protos,
                 const std::vector<ExplainResult>& per);

} // namespace pdpm::explain
