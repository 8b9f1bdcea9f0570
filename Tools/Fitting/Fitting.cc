#include "Fitting.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "Core/Error.h"

namespace pdpm {

double FitResult::get(const std::string& n) const {
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == n) return value[k];
    inputError("fit: no parameter " + n);
}
double FitResult::se(const std::string& n) const {
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == n) return stderror[k];
    inputError("fit: no parameter " + n);
}

namespace {
double rssOf(const std::vector<double>& y, const PointModel& f, const std::vector<double>& p) {
    double s = 0;
    for (std::size_t i = 0; i < y.size(); ++i) {
        const double r = y[i] - f(i, p);
        s += r * r;
    }
    return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
}
} // namespace

FitResult levenbergMarquardt(const std::vector<double>& y, const PointModel& f, const std::vector<std::string>& names,
                             std::vector<double> p, std::vector<bool> fixed, int maxIterations) {
    const std::size_t np = p.size(), n = y.size();
    if (fixed.empty()) fixed.assign(np, false);
    if (names.size() != np || fixed.size() != np) inputError("fit: parameter lists of different lengths");
    std::vector<int> freeIdx;
    for (std::size_t k = 0; k < np; ++k)
        if (!fixed[k]) freeIdx.push_back(static_cast<int>(k));
    const int m = static_cast<int>(freeIdx.size());
    if (static_cast<int>(n) <= m) inputError("fit: " + std::to_string(n) + " points are too few for " +
                                             std::to_string(m) + " free parameters");
    FitResult res;
    res.names = names;
    res.fixed = fixed;
    auto jacobian = [&](const std::vector<double>& q) {
        Eigen::MatrixXd J(n, m);
        for (int c = 0; c < m; ++c) {
            const int k = freeIdx[c];
            const double h = 1e-6 * std::max(std::fabs(q[k]), 1e-6);
            auto qp = q, qm = q;
            qp[k] += h;
            qm[k] -= h;
            for (std::size_t i = 0; i < n; ++i) J(i, c) = (f(i, qp) - f(i, qm)) / (2 * h);
        }
        return J;
    };
    double rss = rssOf(y, f, p);
    if (!std::isfinite(rss)) inputError("fit: the model is not finite at the start values");
    double lambda = 1e-3;
    int it = 0;
    for (; it < maxIterations; ++it) {
        const Eigen::MatrixXd J = jacobian(p);
        Eigen::VectorXd r(n);
        for (std::size_t i = 0; i < n; ++i) r(i) = y[i] - f(i, p);
        const Eigen::MatrixXd A = J.transpose() * J;
        const Eigen::VectorXd g = J.transpose() * r;
        bool improved = false;
        while (lambda < 1e12) {
            Eigen::MatrixXd B = A;
            for (int c = 0; c < m; ++c) B(c, c) += lambda * std::max(A(c, c), 1e-12);
            const Eigen::VectorXd d = B.ldlt().solve(g);
            auto q = p;
            for (int c = 0; c < m; ++c) q[freeIdx[c]] += d(c);
            const double rq = rssOf(y, f, q);
            if (rq < rss) {
                const double rel = (rss - rq) / std::max(rss, 1e-300);
                p = q;
                rss = rq;
                lambda = std::max(lambda / 10, 1e-12);
                improved = true;
                if (rel < 1e-12 || rss < 1e-300) res.converged = true;
                break;
            }
            lambda *= 10;
        }
        if (!improved) {
            res.converged = true;  // no descent direction left: at a minimum (to round-off)
            break;
        }
        if (res.converged) break;
    }
    res.iterations = it;
    res.value = p;
    res.rss = rss;
    res.points = static_cast<int>(n);
    res.rms = std::sqrt(rss / static_cast<double>(n));
    res.stderror.assign(np, 0.0);
    const Eigen::MatrixXd J = jacobian(p);
    const Eigen::MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse();
    const double s2 = rss / static_cast<double>(static_cast<int>(n) - m);
    for (int c = 0; c < m; ++c) res.stderror[freeIdx[c]] = std::sqrt(std::max(0.0, s2 * cov(c, c)));
    // The pseudo-inverse drops directions the data do not constrain, which would show as tiny errors:
    // a parameter with a share in a (numerically) zero singular direction of J is undetermined.
    res.undetermined.assign(np, false);
    if (m > 0) {
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinV);
        const Eigen::VectorXd& sv = svd.singularValues();
        const Eigen::MatrixXd& V = svd.matrixV();
        for (int k = 0; k < m; ++k) {
            if (sv(k) > 1e-8 * sv(0) && sv(0) > 0) continue;
            for (int c = 0; c < m; ++c)
                if (std::fabs(V(c, k)) > 1e-3) {
                    res.undetermined[freeIdx[c]] = true;
                    res.determined = false;
                }
        }
    }
    return res;
}

// ---- models ------------------------------------------------------------------------------------------
double cstarModel(double v, double c0, double c1, double alpha, double vc) {
    const double x = v / vc - 1;
    return c0 + (x > 0 ? c1 * std::pow(x, alpha) : 0.0);
}
double rattlerModel(double v, double phiC, double phiV, double vc) { return phiC * std::exp(-phiV * (v / vc - 1)); }
double pressureModel(double v, double C, double p0, double gammaP, double vc) {
    const double e = std::log(v / vc);  // -varepsilon_v, Eq. (2.13)
    return p0 * v * C / vc * e * (1 - gammaP * e);
}
double scaledPressureModel(double e, double p0, double gammaP) { return p0 * e * (1 - gammaP * e); }
double saturationModel(double eps, double qMax, double q0, double beta) {
    return qMax - (qMax - q0) * std::exp(-beta * eps);
}
double volumeDependenceModel(double v, double qMax, double qV, double alpha, double vc) {
    return qMax + qV * std::exp(-alpha * (v / vc - 1));
}

namespace {
void sameSize(std::size_t a, std::size_t b) {
    if (a != b) inputError("fit: x and y have different lengths");
}
} // namespace

FitResult fitCstar(const std::vector<double>& v, const std::vector<double>& c, double c0) {
    sameSize(v.size(), c.size());
    const double vmin = *std::min_element(v.begin(), v.end());
    return levenbergMarquardt(
        c, [&](std::size_t i, const std::vector<double>& p) { return cstarModel(v[i], p[0], p[1], p[2], p[3]); },
        {"C0", "C1", "alpha", "v_c"}, {c0, 8.0, 0.6, 0.98 * vmin}, {true, false, false, false});
}

FitResult fitRattlers(const std::vector<double>& v, const std::vector<double>& phi, double vc) {
    sameSize(v.size(), phi.size());
    return levenbergMarquardt(
        phi, [&](std::size_t i, const std::vector<double>& p) { return rattlerModel(v[i], p[0], p[1], vc); },
        {"phi_c", "phi_v"}, {0.13, 15.0});
}

FitResult fitPressure(const std::vector<double>& v, const std::vector<double>& C, const std::vector<double>& p) {
    sameSize(v.size(), p.size());
    sameSize(C.size(), p.size());
    const double vmin = *std::min_element(v.begin(), v.end());
    return levenbergMarquardt(
        p, [&](std::size_t i, const std::vector<double>& q) { return pressureModel(v[i], C[i], q[0], q[1], q[2]); },
        {"p0", "gamma_p", "v_c"}, {0.04, 0.05, 0.98 * vmin});
}

namespace {
// Models of the form a + b g(x; c): for each c on a logarithmic grid, a and b follow from linear least
// squares; the best c gives the start values of the non-linear fit (robust against sign and scale).
std::vector<double> linearisedStart(const std::vector<double>& x, const std::vector<double>& y,
                                    const std::function<double(double, double)>& g, bool aZero, double cLo,
                                    double cHi) {
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> start = {0, 0, cLo};
    for (int k = 0; k <= 200; ++k) {
        const double c = cLo * std::pow(cHi / cLo, k / 200.0);
        Eigen::MatrixXd A(x.size(), aZero ? 1 : 2);
        Eigen::VectorXd b(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            A(i, 0) = g(x[i], c);
            if (!aZero) A(i, 1) = 1.0;
            b(i) = y[i];
        }
        const Eigen::VectorXd sol = A.colPivHouseholderQr().solve(b);
        const double r = (A * sol - b).squaredNorm();
        if (r < best) {
            best = r;
            start = {aZero ? 0.0 : sol(1), sol(0), c};
        }
    }
    return start;
}
} // namespace

FitResult fitSaturation(const std::vector<double>& eps, const std::vector<double>& q) {
    sameSize(eps.size(), q.size());
    // q = q_max + (q_0 - q_max) exp(-beta eps)
    const auto s = linearisedStart(eps, q, [](double x, double c) { return std::exp(-c * x); }, false, 0.1, 1e4);
    return levenbergMarquardt(
        q, [&](std::size_t i, const std::vector<double>& p) { return saturationModel(eps[i], p[0], p[1], p[2]); },
        {"q_max", "q_0", "beta"}, {s[0], s[0] + s[1], s[2]});
}

FitResult fitVolumeDependence(const std::vector<double>& v, const std::vector<double>& q, double vc, bool zero) {
    sameSize(v.size(), q.size());
    const auto s = linearisedStart(v, q, [vc](double x, double c) { return std::exp(-c * (x / vc - 1)); }, zero, 0.01, 200);
    return levenbergMarquardt(
        q, [&](std::size_t i, const std::vector<double>& p) { return volumeDependenceModel(v[i], p[0], p[1], p[2], vc); },
        {"Q_max", "Q_v", "alpha"}, s, {zero, false, false});
}

// ---- macro CSV ---------------------------------------------------------------------------------------
std::vector<std::vector<double>> selectRows(const CsvTable& t, BranchSelect b, double pMin) {
    const int tau = t.column("tau");
    const int p = t.column("p_nd");
    // values no packing can have (a foreign or edited file): refused, not fitted
    if (t.hasColumn("volume_fraction")) {
        const int vf = t.column("volume_fraction");
        for (std::size_t k = 0; k < t.rows.size(); ++k)
            if (!(t.rows[k][vf] > 0 && t.rows[k][vf] < 1))
                inputError(t.source + ": volume_fraction " + std::to_string(t.rows[k][vf]) + " in data row " + std::to_string(k + 1) +
                           " is outside (0, 1)");
    }
    if (b == BranchSelect::Auto) {
        // unloading when the test has one: rows past tau = 0.5 and, where the file has eps_zz, a
        // reversal of the axial strain (a cycle of IsotropicCompression or UniaxialCyclic). A
        // deviatoric or triaxial test also runs tau from 0 to 1, but its axial strain never turns
        // back, so the whole test is taken.
        bool unloading = false;
        for (const auto& r : t.rows) unloading = unloading || r[tau] > 0.5 + 1e-9;
        if (unloading && t.hasColumn("eps_zz")) {
            const int ezz = t.column("eps_zz");
            double start = 0, top = -std::numeric_limits<double>::infinity(), end = 0;
            bool first = true;
            for (const auto& r : t.rows)
                if (r[tau] >= 0) {
                    if (first) start = r[ezz], first = false;
                    top = std::max(top, r[ezz]);
                    end = r[ezz];
                }
            // any turn back: a cycle cut short just past tau = 0.5 has reversed by 0.1 % of its strain
            unloading = !first && top > start && top - end > 1e-6 * (top - start);
        }
        b = unloading ? BranchSelect::Unloading : BranchSelect::Test;
    }
    std::vector<std::vector<double>> out;
    for (const auto& r : t.rows) {
        const double x = r[tau];
        const bool in = b == BranchSelect::Loading ? (x > 0 && x <= 0.5)
                        : b == BranchSelect::Unloading ? (x > 0.5)
                                                       : (x >= 0);
        if (in && r[p] > pMin) out.push_back(r);
    }
    return out;
}

std::vector<double> column(const CsvTable& t, const std::vector<std::vector<double>>& rows, const std::string& name) {
    const int c = t.column(name);
    std::vector<double> v;
    v.reserve(rows.size());
    for (const auto& r : rows) v.push_back(r[c]);
    return v;
}

namespace {
/// Eq. 2.17/2.18 along a path with Eq. 2.20 coefficients: q(eps) = q_max(v) - (q_max(v) - q0) exp(-beta(v) eps).
std::vector<double> predictAlong(const FitResult& qMax, const FitResult& beta, double vc, double vLo,
                                 const std::vector<double>& v, const std::vector<double>& eps, double q0) {
    std::vector<double> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double vi = std::max(v[i], vLo);
        const double qm = volumeDependenceModel(vi, qMax.value[0], qMax.value[1], qMax.value[2], vc);
        const double b = volumeDependenceModel(vi, beta.value[0], beta.value[1], beta.value[2], vc);
        out.push_back(saturationModel(eps[i], qm, q0, b));
    }
    return out;
}
} // namespace

std::vector<double> AnisotropyModel::predictS(const std::vector<double>& v, const std::vector<double>& eps,
                                              double s0) const {
    return predictAlong(sMax, betaS, vc, vLo, v, eps, s0);
}
std::vector<double> AnisotropyModel::predictF(const std::vector<double>& v, const std::vector<double>& eps,
                                              double f0) const {
    return predictAlong(fMax, betaF, vc, vLo, v, eps, f0);
}

AnisotropyModel readAnisotropyTable(const std::string& path, double vc) {
    AnisotropyModel m;
    m.vc = vc;
    const CsvTable t = readCsv(path, true);
    if (t.labelColumn != "parameter" || t.columns != std::vector<std::string>{"Q_max", "Q_c", "alpha"})
        inputError(path + ": expected the header parameter,Q_max,Q_c,alpha");
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
        const std::string& name = t.labels[i];
        const std::string where = path + ":" + std::to_string(t.rowLines[i]) + ": ";
        const auto& q = t.rows[i];
        FitResult r;
        r.names = {"Q_max", "Q_v", "alpha"};
        r.value = {q[0], q[1] - q[0], q[2]};  // Eq. 2.20 with Q_v = Q_c - Q_max
        r.stderror = {0, 0, 0};
        r.fixed = {true, true, true};
        FitResult* dst = name == "s_dev_max" ? &m.sMax
                         : name == "beta_s"  ? &m.betaS
                         : name == "F_dev_max" ? &m.fMax
                         : name == "beta_F"  ? &m.betaF
                                             : nullptr;
        if (!dst) inputError(where + "unknown parameter '" + name + "' (s_dev_max, beta_s, F_dev_max, beta_F)");
        if (!dst->value.empty()) inputError(where + "parameter '" + name + "' given twice");
        *dst = r;
    }
    if (m.sMax.value.empty() || m.betaS.value.empty() || m.fMax.value.empty() || m.betaF.value.empty())
        inputError(path + ": needs the rows s_dev_max, beta_s, F_dev_max and beta_F");
    return m;
}

AnisotropyModel calibrateAnisotropy(const std::vector<CsvTable>& runs, double vc,
                                    std::vector<std::pair<double, std::pair<FitResult, FitResult>>>* perRun) {
    if (runs.size() < 3) inputError("model: at least 3 deviatoric runs are needed (one per volume fraction)");
    std::vector<double> v, sm, bs, fm, bf;
    for (const auto& t : runs) {
        const auto rows = selectRows(t, BranchSelect::Test);
        if (rows.size() < 5) inputError("model: " + t.source + " has fewer than 5 test rows");
        const auto eps = column(t, rows, "eps_dev");
        const FitResult s = fitSaturation(eps, column(t, rows, "s_dev"));
        const FitResult f = fitSaturation(eps, column(t, rows, "F_dev"));
        const double vol = column(t, rows, "volume_fraction").front();
        v.push_back(vol);
        sm.push_back(s.get("q_max"));
        bs.push_back(s.get("beta"));
        fm.push_back(f.get("q_max"));
        bf.push_back(f.get("beta"));
        if (perRun) perRun->push_back({vol, {s, f}});
    }
    // Runs at the same volume fraction add no information on the v dependence of Eq. 2.20
    std::vector<double> distinct = v;
    std::sort(distinct.begin(), distinct.end());
    std::size_t nv = distinct.empty() ? 0 : 1;
    for (std::size_t k = 1; k < distinct.size(); ++k)
        if (distinct[k] - distinct[k - 1] > 1e-4) ++nv;
    if (nv < 3)
        inputError("model: the runs are at " + std::to_string(nv) +
                   " distinct volume fraction(s); Eq. 2.20 needs at least 3 (one run per volume fraction)");
    AnisotropyModel m;
    m.vc = vc;
    // 3 free parameters need more than 3 volume fractions; with 3, Q_max is fixed at 0 for the stress
    // parameters as well (the thesis fixes it at 0 for the fabric ones only)
    const bool enough = nv > 3;
    m.stressQmaxFixed = !enough;
    m.sMax = enough ? fitVolumeDependence(v, sm, vc, false) : fitVolumeDependence(v, sm, vc, true);
    m.betaS = enough ? fitVolumeDependence(v, bs, vc, false) : fitVolumeDependence(v, bs, vc, true);
    m.fMax = fitVolumeDependence(v, fm, vc, true);
    m.betaF = fitVolumeDependence(v, bf, vc, true);
    m.vLo = *std::min_element(v.begin(), v.end());
    return m;
}

} // namespace pdpm
