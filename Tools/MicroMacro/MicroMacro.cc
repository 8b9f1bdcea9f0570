#include "MicroMacro.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numbers>

#include "Boundaries/FaceDistance.h"
#include "Core/Error.h"
#include "IO/Csv.h"

namespace pdpm {

namespace {
Eigen::Vector3d ev(const Vec3& v) { return {v.x, v.y, v.z}; }
double sphereVolume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }
constexpr double kDeg = 180.0 / std::numbers::pi;
} // namespace

TensorSummary summariseTensor(const Eigen::Matrix3d& tIn) {
    TensorSummary s;
    const Eigen::Matrix3d t = 0.5 * (tIn + tIn.transpose());
    const Eigen::Matrix3d dev = t - t.trace() / 3.0 * Eigen::Matrix3d::Identity();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(dev);
    // ascending -> descending
    for (int k = 0; k < 3; ++k) {
        const int src = 2 - k;
        s.lambda[k] = es.eigenvalues()(src);
        const double cz = std::min(1.0, std::fabs(es.eigenvectors()(2, src)));
        s.theta[k] = std::acos(cz) * kDeg;
    }
    s.shape = s.lambda[0] != 0 ? s.lambda[1] / s.lambda[0] : 0.0;
    const double a = s.lambda[0] - s.lambda[1], b = s.lambda[1] - s.lambda[2], c = s.lambda[2] - s.lambda[0];
    s.devMagnitude = std::sqrt(0.5 * (a * a + b * b + c * c));
    // Eq. 3.19 in the box axes (the thesis' footnote to Eq. 3.14: "the other two fixed directions"):
    // t_zz - (t_xx + t_yy)/2. It equals lambda_z - (the other two)/2 when the principal axes are the
    // box axes, and unlike an eigenvector pick it stays continuous through isotropy, where the
    // eigenvectors of two nearly equal eigenvalues turn freely and the pick could jump.
    s.axialStar = t(2, 2) - 0.5 * (t(0, 0) + t(1, 1));
    return s;
}

MacroResult computeMacro(const ParticleData& P, const std::vector<ContactRecord>& C, const MacroInput& in) {
    if (!(in.volume > 0)) inputError("micro-macro: volume must be positive");
    MacroResult r;
    const std::size_t n = P.size();
    const double V = in.volume;
    double solid = 0, rsum = 0;
    Eigen::Matrix3d kin = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
        solid += sphereVolume(P.r[i]);
        rsum += P.r[i];
        const Eigen::Vector3d v = ev(P.v[i]);
        kin += P.m[i] * v * v.transpose();
    }
    r.volumeFraction = solid / V;
    r.meanRadius = n ? rsum / static_cast<double>(n) : 0.0;
    r.stressKinetic = kin / V;

    // mean normal force over particle-particle contacts -> strong / weak split (Eq. 3.22, 3.23)
    double fnSum = 0;
    long pp = 0;
    for (const auto& c : C)
        if (c.j >= 0) {
            fnSum += c.fn;
            ++pp;
        }
    r.contacts = pp;
    const double fnMean = pp ? fnSum / static_cast<double>(pp) : 0.0;

    Eigen::Matrix3d sc = Eigen::Matrix3d::Zero(), ss = Eigen::Matrix3d::Zero(), sw = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d fab = Eigen::Matrix3d::Zero(), fs = Eigen::Matrix3d::Zero(), fw = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d nn = Eigen::Matrix3d::Zero();
    std::vector<int> z(n, 0);
    long weak = 0, wsl = 0, wst = 0, ssl = 0, sst = 0, mobCount = 0;
    double mob = 0;
    // face layer of the mobilisation ratio: within kFaceLayer L of a face of a face axis
    const Eigen::Vector3d boxL = in.boxHi - in.boxLo;
    bool anyFaceAxis = false;
    for (int a = 0; a < 3; ++a) anyFaceAxis = anyFaceAxis || (in.faceAxes[static_cast<std::size_t>(a)] && boxL[a] > 0);
    const auto inFaceLayer = [&](const Vec3& point) {
        for (int a = 0; a < 3; ++a) {
            if (!in.faceAxes[static_cast<std::size_t>(a)] || !(boxL[a] > 0)) continue;
            if (faceDistanceFraction(point[a], in.boxLo[a], boxL[a]) < kFaceLayer) return true;
        }
        return false;
    };
    double mobFace = 0, mobInner = 0;
    long mobFaceCount = 0, mobInnerCount = 0;
    for (const auto& c : C) {
        const Eigen::Vector3d f = c.fn * ev(c.n) + ev(c.ft);
        const Eigen::Matrix3d fl = f * ev(c.branch).transpose();
        sc += fl;
        if (c.j < 0) {  // wall contact: stress only
            if (c.i >= 0 && static_cast<std::size_t>(c.i) < n) ++z[c.i];
            continue;
        }
        const Eigen::Vector3d nv = ev(c.n);
        const Eigen::Matrix3d nnc = nv * nv.transpose();
        const double vp = sphereVolume(P.r[c.i]) + sphereVolume(P.r[c.j]);
        fab += vp * nnc;
        nn += nnc;
        ++z[c.i];
        ++z[c.j];
        const bool strong = c.fn > fnMean;
        if (strong) {
            ss += fl;
            fs += vp * nnc;
            (c.sliding ? ssl : sst) += 1;
        } else {
            sw += fl;
            fw += vp * nnc;
            ++weak;
            (c.sliding ? wsl : wst) += 1;
        }
        if (in.mu > 0 && c.fn > 0) {
            const double psi = norm(c.ft) / (in.mu * c.fn);
            mob += psi;
            ++mobCount;
            if (anyFaceAxis) {
                if (inFaceLayer(c.point)) mobFace += psi, ++mobFaceCount;
                else mobInner += psi, ++mobInnerCount;
            }
        }
    }
    r.stress = kin / V + sc / V;
    r.stress = 0.5 * (r.stress + r.stress.transpose()).eval();
    r.fabric = fab / V;
    r.fabricNormalised = pp ? Eigen::Matrix3d(nn / static_cast<double>(pp)) : Eigen::Matrix3d::Zero();

    const double tr = r.stress.trace();
    r.p = tr / 3;
    r.pNd = in.stiffness > 0 ? 2 * r.meanRadius * tr / (3 * in.stiffness) : 0.0;
    r.stressAll = summariseTensor(r.stress);
    r.stressStrong = summariseTensor(ss / V);
    r.stressWeak = summariseTensor(sw / V);
    r.sigmaDev = r.stressAll.devMagnitude;
    r.sDev = r.p != 0 ? r.sigmaDev / r.p : 0.0;
    r.sDevStar = r.p != 0 ? r.stressAll.axialStar / r.p : 0.0;
    r.fabricAll = summariseTensor(r.fabric);
    r.fabricStrong = summariseTensor(fs / V);
    r.fabricWeak = summariseTensor(fw / V);
    r.Fv = r.fabric.trace() / 3;
    r.Fdev = r.fabricAll.devMagnitude;
    r.FdevStar = r.fabricAll.axialStar;
    const TensorSummary fn = summariseTensor(r.fabricNormalised);
    r.FnDev = fn.devMagnitude;
    r.FnDevStar = fn.axialStar;

    long M = 0, M4 = 0, N4 = 0;
    for (int k : z) {
        M += k;
        if (k >= kRattlerContacts) {
            M4 += k;
            ++N4;
        }
    }
    const double N = static_cast<double>(n);
    r.Cr = n ? static_cast<double>(M) / N : 0.0;
    r.Cm = n ? static_cast<double>(M4) / N : 0.0;
    r.Cstar = N4 ? static_cast<double>(M4) / static_cast<double>(N4) : 0.0;
    r.phiR = n ? (N - static_cast<double>(N4)) / N : 0.0;

    if (pp) {
        const double dpp = static_cast<double>(pp);
        r.weakFraction = static_cast<double>(weak) / dpp;
        if (in.mu > 0) {
            r.wsl = static_cast<double>(wsl) / dpp;
            r.wst = static_cast<double>(wst) / dpp;
            r.ssl = static_cast<double>(ssl) / dpp;
            r.sst = static_cast<double>(sst) / dpp;
        }
    }
    r.mobilisation = mobCount ? mob / static_cast<double>(mobCount) : 0.0;
    if (mobFaceCount > 0 && mobInnerCount > 0 && mobInner > 0)
        r.mobilisationFaceRatio = (mobFace / static_cast<double>(mobFaceCount)) / (mobInner / static_cast<double>(mobInnerCount));
    r.ekOverEp = in.elasticEnergy > 0 ? in.kineticEnergy / in.elasticEnergy : 0.0;
    r.ekFluctOverEp = in.elasticEnergy > 0 && in.fluctuationKineticEnergy >= 0
                          ? in.fluctuationKineticEnergy / in.elasticEnergy
                          : 0.0;
    return r;
}

double fluctuationKineticEnergy(const ParticleData& P, const Vec3& rate, const Vec3& centre,
                                const std::array<bool, 3>& flowAxis) {
    const std::size_t n = P.size();
    auto rel = [&](std::size_t i) {
        Vec3 u = P.v[i];
        for (int a = 0; a < 3; ++a)
            if (flowAxis[static_cast<std::size_t>(a)]) u[a] -= rate[a] * (P.x[i][a] - centre[a]);
        return u;
    };
    double mass = 0;
    Vec3 mom{};
    for (std::size_t i = 0; i < n; ++i) {
        mass += P.m[i];
        mom = mom + P.m[i] * rel(i);
    }
    if (!(mass > 0)) return 0.0;
    const Vec3 mean = (1.0 / mass) * mom;
    double e = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 u = rel(i) - mean;
        e += 0.5 * P.m[i] * dot(u, u);
    }
    return e;
}

namespace {
void addSummaryColumns(std::vector<std::string>& c, const std::string& p) {
    for (const char* s : {"_l1", "_l2", "_l3", "_theta1", "_theta2", "_theta3", "_Lambda"}) c.push_back(p + s);
}
void addSummaryValues(std::vector<double>& v, const TensorSummary& s) {
    v.insert(v.end(), {s.lambda[0], s.lambda[1], s.lambda[2], s.theta[0], s.theta[1], s.theta[2], s.shape});
}
} // namespace

const std::vector<std::string>& macroColumns() {
    static const std::vector<std::string> cols = [] {
        std::vector<std::string> c = {"time", "tau", "volume_fraction", "eps_v", "eps_dev", "sigma_xx", "sigma_yy",
                                      "sigma_zz", "sigma_xy", "sigma_xz", "sigma_yz", "p", "p_nd", "sigma_dev",
                                      "s_dev", "F_xx", "F_yy", "F_zz", "F_v", "F_dev", "F_dev_star", "C_r", "C_m",
                                      "C_star", "phi_r", "Ek_over_Ep",
                                      // extras
                                      "eps_xx", "eps_yy", "eps_zz", "s_dev_star", "F_xy", "F_xz", "F_yz", "Fn_xx",
                                      "Fn_yy", "Fn_zz", "Fn_dev", "Fn_dev_star", "contacts", "mean_radius"};
        addSummaryColumns(c, "sig");
        addSummaryColumns(c, "sig_strong");
        addSummaryColumns(c, "sig_weak");
        addSummaryColumns(c, "fab");
        addSummaryColumns(c, "fab_strong");
        addSummaryColumns(c, "fab_weak");
        for (const char* s : {"weak_fraction", "f_wsl", "f_wst", "f_ssl", "f_sst", "mobilisation", "Ek", "Ep",
                              "Ek_fluct_over_Ep", "mobilisation_face_ratio", "eps_dev_eng"})
            c.push_back(s);
        return c;
    }();
    return cols;
}

std::vector<double> macroRow(const MacroResult& r, const MacroInput& in) {
    const auto& s = r.stress;
    const auto& f = r.fabric;
    const auto& g = r.fabricNormalised;
    std::vector<double> v = {in.time, in.tau, r.volumeFraction, in.epsV, in.epsDev, s(0, 0), s(1, 1), s(2, 2),
                             s(0, 1), s(0, 2), s(1, 2), r.p, r.pNd, r.sigmaDev, r.sDev, f(0, 0), f(1, 1), f(2, 2),
                             r.Fv, r.Fdev, r.FdevStar, r.Cr, r.Cm, r.Cstar, r.phiR, r.ekOverEp,
                             in.strain(0), in.strain(1), in.strain(2), r.sDevStar, f(0, 1), f(0, 2), f(1, 2),
                             g(0, 0), g(1, 1), g(2, 2), r.FnDev, r.FnDevStar, static_cast<double>(r.contacts),
                             r.meanRadius};
    addSummaryValues(v, r.stressAll);
    addSummaryValues(v, r.stressStrong);
    addSummaryValues(v, r.stressWeak);
    addSummaryValues(v, r.fabricAll);
    addSummaryValues(v, r.fabricStrong);
    addSummaryValues(v, r.fabricWeak);
    v.insert(v.end(), {r.weakFraction, r.wsl, r.wst, r.ssl, r.sst, r.mobilisation, in.kineticEnergy, in.elasticEnergy,
                      r.ekFluctOverEp, r.mobilisationFaceRatio, in.epsDevEngineering});
    return v;
}

void MacroCsv::append(const std::vector<double>& row) {
    rows_.push_back(row);
    flush();
}

void MacroCsv::truncateAfter(double t) {
    while (!rows_.empty() && rows_.back().at(0) > t) rows_.pop_back();
}

void MacroCsv::reload() {
    rows_.clear();
    if (path_.empty() || !std::filesystem::exists(path_)) return;
    const CsvTable t = readCsv(path_);
    const std::vector<std::string>& cols = macroColumns();
    if (t.columns == cols) {
        rows_ = t.rows;
        return;
    }
    // written by an earlier version (a subset of today's columns): keep its rows, columns matched by
    // name, the new ones not a number
    std::vector<int> from(cols.size(), -1);
    std::size_t found = 0;
    for (std::size_t c = 0; c < cols.size(); ++c)
        for (std::size_t k = 0; k < t.columns.size(); ++k)
            if (t.columns[k] == cols[c]) from[c] = static_cast<int>(k), ++found;
    if (found == t.columns.size() && from[0] == 0) {
        for (const auto& r : t.rows) {
            std::vector<double> row(cols.size(), std::numeric_limits<double>::quiet_NaN());
            for (std::size_t c = 0; c < cols.size(); ++c)
                if (from[c] >= 0) row[c] = r[static_cast<std::size_t>(from[c])];
            rows_.push_back(std::move(row));
        }
        std::cerr << "note: " << path_ << " has " << t.columns.size() << " of today's " << cols.size()
                  << " columns (an earlier version); its rows are kept, the new columns are nan until the restart\n";
        return;
    }
    // a foreign file: moved aside, not overwritten
    const std::string aside = path_ + ".old";
    std::filesystem::rename(path_, aside);
    std::cerr << "note: " << path_ << " is not a macro file of this version (other columns); moved to " << aside << "\n";
}

void MacroCsv::flush() const {
    if (path_.empty()) return;
    writeCsv(path_, macroColumns(), rows_);
}

} // namespace pdpm
