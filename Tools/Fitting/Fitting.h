// Non-linear least squares (Levenberg-Marquardt, Eigen) and the fit functions of thesis chapter 2:
// Eq. (2.11) C*(v), (2.12) phi_r(v), (2.14) p(v), (2.15) p*(eps_v), (2.17) s_dev(eps_dev),
// (2.18) F_dev(eps_dev), (2.20) Q(v); plus the reduced anisotropy model of Sec. 2.7 (calibrate on
// D2/D3 runs, predict a uniaxial run). Standard errors come from the Jacobian at the optimum:
// se_k = sqrt(s^2 [(J^T J)^-1]_kk) with s^2 = RSS / (n - free parameters).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "IO/Csv.h"

namespace pdpm {

struct FitResult {
    std::vector<std::string> names;
    std::vector<double> value, stderror;  ///< stderror 0 for fixed parameters
    std::vector<bool> fixed;
    double rss = 0, rms = 0;
    int points = 0, iterations = 0;
    bool converged = false;
    /// false when the data leave some free parameter undetermined (a numerically zero singular value
    /// of the Jacobian: e.g. C*(v) through points at one volume fraction). `undetermined[k]` marks
    /// those parameters; their stderror is that of the pseudo-inverse, which leaves the undetermined
    /// direction out and so looks small: do not report it.
    bool determined = true;
    std::vector<bool> undetermined;
    double get(const std::string& name) const;
    double se(const std::string& name) const;
};

/// Model value of data point i for parameters p.
using PointModel = std::function<double(std::size_t i, const std::vector<double>& p)>;

/// Minimises sum_i (y_i - f(i, p))^2 over the parameters not marked fixed, starting from p0.
FitResult levenbergMarquardt(const std::vector<double>& y, const PointModel& f, const std::vector<std::string>& names,
                             std::vector<double> p0, std::vector<bool> fixed = {}, int maxIterations = 500);

// ---- the thesis' functions ----------------------------------------------------------------------
double cstarModel(double v, double c0, double c1, double alpha, double vc);               ///< Eq. (2.11)
double rattlerModel(double v, double phiC, double phiV, double vc);                       ///< Eq. (2.12)
double pressureModel(double v, double C, double p0, double gammaP, double vc);            ///< Eq. (2.14), C = C_m
double scaledPressureModel(double negEpsV, double p0, double gammaP);                     ///< Eq. (2.15)
double saturationModel(double eps, double qMax, double q0, double beta);                  ///< Eq. (2.17)/(2.18)
double volumeDependenceModel(double v, double qMax, double qV, double alpha, double vc);   ///< Eq. (2.20)

/// Eq. (2.11) with C0 fixed (default 6): parameters C1, alpha, v_c.
FitResult fitCstar(const std::vector<double>& v, const std::vector<double>& cstar, double c0 = 6);
/// Eq. (2.12) with v_c fixed: phi_c, phi_v.
FitResult fitRattlers(const std::vector<double>& v, const std::vector<double>& phi, double vc);
/// Eq. (2.14): p0, gamma_p, v_c from dimensionless pressure p and C = C_m.
FitResult fitPressure(const std::vector<double>& v, const std::vector<double>& C, const std::vector<double>& p);
/// Eq. (2.17)/(2.18): q_max, q_0, beta.
FitResult fitSaturation(const std::vector<double>& eps, const std::vector<double>& q);
/// Eq. (2.20) with v_c fixed; `qMaxFixedZero` for the fabric parameters (Table 2.3).
FitResult fitVolumeDependence(const std::vector<double>& v, const std::vector<double>& q, double vc,
                              bool qMaxFixedZero);

// ---- macro CSV helpers ----------------------------------------------------------------------------
enum class BranchSelect { Loading, Unloading, Test, Auto };
/// Rows of a RUN.macro.csv on a branch (tau in (0, 0.5] / (0.5, 1] / >= 0); Auto: unloading when the
/// run has rows with tau > 0.5 and its axial strain eps_zz turns back (a cycle; without an eps_zz
/// column the rows past 0.5 decide alone), else every test row (deviatoric and triaxial tests). Only
/// jammed rows (p_nd > pMin) if pMin > 0.
std::vector<std::vector<double>> selectRows(const CsvTable& t, BranchSelect b, double pMin = 0);
std::vector<double> column(const CsvTable& t, const std::vector<std::vector<double>>& rows, const std::string& name);

/// Reduced anisotropy model (Sec. 2.7): Eq. (2.20) fits of s_dev^max, beta_s, F_dev^max, beta_F.
struct AnisotropyModel {
    FitResult sMax, betaS, fMax, betaF;
    double vc = 0.6653;
    /// Eq. 2.20 is evaluated at max(v, vLo): below the lowest calibration run the exponential of a fit
    /// over a few points is not extrapolated towards v_c (where it runs away). Above it, Eq. 2.20 is
    /// used as fitted: it tends to Q_max when alpha > 0, but alpha is not constrained, and a fit with
    /// alpha < 0 grows exponentially beyond the highest run. vLo = 0 (no bound) for table coefficients.
    double vLo = 0;
    /// true when s_dev^max and beta_s were fitted with Q_max = 0 (only 3 volume fractions)
    bool stressQmaxFixed = false;
    /// Prediction along a path (v(eps), eps): s(eps) = s_max(v) - (s_max(v) - s0) exp(-beta_s(v) eps).
    std::vector<double> predictS(const std::vector<double>& v, const std::vector<double>& eps, double s0) const;
    std::vector<double> predictF(const std::vector<double>& v, const std::vector<double>& eps, double f0) const;
};
/// A Table 2.3-style coefficient file: CSV with the header `parameter,Q_max,Q_c,alpha` and one row
/// each for s_dev_max, beta_s, F_dev_max, beta_F (`#` comments allowed; e.g. the thesis' table in
/// ../shared/data/thesis/table_2_3_deviatoric_evolution.csv). InputError names a malformed file.
AnisotropyModel readAnisotropyTable(const std::string& path, double vc);
/// Calibrate from deviatoric runs: per run one Eq. (2.17) and one Eq. (2.18) fit at the run's volume
/// fraction, then Eq. (2.20) over the runs. Needs at least 3 runs; `perRun` receives the per-run fits.
AnisotropyModel calibrateAnisotropy(const std::vector<CsvTable>& deviatoricRuns, double vc,
                                    std::vector<std::pair<double, std::pair<FitResult, FitResult>>>* perRun = nullptr);

} // namespace pdpm
