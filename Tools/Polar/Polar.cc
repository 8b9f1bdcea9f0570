#include "Polar.h"

#include "Core/Error.h"
#include "OutputFiles.h"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>

namespace pdpm::tools {

double harmonicY(int l, double c) {
    const double c2 = c * c;
    switch (l) {
    case 0: return 1;
    case 2: return 3 * c2 - 1;
    case 4: return (35 * c2 - 30) * c2 + 3;
    case 6: return ((231 * c2 - 315) * c2 + 105) * c2 - 5;
    default: return 0;
    }
}

double harmonicP6(double a0, const std::array<double, 3>& eps, double theta) {
    const double c = std::cos(theta);
    return a0 * (1 + eps[0] * harmonicY(2, c) + eps[1] * harmonicY(4, c) + eps[2] * harmonicY(6, c));
}

namespace {

/// ∫_0^h Y_l(x) dx
double integralY(int l, double h) {
    const double h2 = h * h;
    switch (l) {
    case 2: return h * (h2 - 1);
    case 4: return h * ((7 * h2 - 10) * h2 + 3);
    case 6: return h * (((33 * h2 - 63) * h2 + 35) * h2 - 5);
    default: return h;
    }
}

struct Lsq {
    Eigen::VectorXd beta;
    Eigen::MatrixXd cov;
};

/// Ordinary least squares y = X β with covariance s² (XᵀX)⁻¹, s² = RSS/(n − p).
Lsq leastSquares(const Eigen::MatrixXd& X, const Eigen::VectorXd& y) {
    const long n = X.rows(), p = X.cols();
    if (n <= p) inputError("harmonic fit needs more bins than parameters (increase the number of bins)");
    Lsq r;
    const Eigen::MatrixXd XtX = X.transpose() * X;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(XtX);
    r.beta = ldlt.solve(X.transpose() * y);
    const double rss = (y - X * r.beta).squaredNorm();
    r.cov = ldlt.solve(Eigen::MatrixXd::Identity(p, p)) * (rss / double(n - p));
    return r;
}

/// ε_l = β_l/β_0 with delta-method errors.
void ratioFit(const Lsq& f, HarmonicFit& out) {
    const double b0 = f.beta(0);
    out.a0 = b0;
    out.a0Se = std::sqrt(std::max(0.0, f.cov(0, 0)));
    for (int k = 0; k < 3; ++k) {
        const double bl = f.beta(k + 1);
        out.eps[k] = bl / b0;
        Eigen::Vector4d g = Eigen::Vector4d::Zero();
        g(0) = -bl / (b0 * b0);
        g(k + 1) = 1 / b0;
        out.se[k] = std::sqrt(std::max(0.0, double(g.transpose() * f.cov * g)));
    }
}

void ratioFit2(const Lsq& f, HarmonicFit& out) {
    const double b0 = f.beta(0), b1 = f.beta(1);
    out.eps2nd = b1 / b0;
    Eigen::Vector2d g(-b1 / (b0 * b0), 1 / b0);
    out.eps2ndSe = std::sqrt(std::max(0.0, double(g.transpose() * f.cov * g)));
}

std::vector<PolarBin> usable(const std::vector<PolarBin>& bins) {
    std::vector<PolarBin> out;
    for (const PolarBin& b : bins)
        if (b.hi > b.lo) out.push_back(b);
    return out;
}

} // namespace

namespace {
// M1 and M3 share one linear least-squares fit of the 2nd and 6th order harmonics; they differ in
// the data (M1: the density P(theta); M3: the bin fractions) and in a per-bin weight on the model.
template <class Data, class Weight>
HarmonicFit linearHarmonicFit(const char* method, const std::vector<PolarBin>& bins, Data data, Weight weight) {
    HarmonicFit out;
    out.method = method;
    const auto b = usable(bins);
    const long n = long(b.size());
    Eigen::MatrixXd X(n, 4), X2(n, 2);
    Eigen::VectorXd y(n);
    for (long k = 0; k < n; ++k) {
        const double c = std::cos(b[k].theta);
        const double s = weight(b[k]);
        X.row(k) << s, s * harmonicY(2, c), s * harmonicY(4, c), s * harmonicY(6, c);
        X2.row(k) << s, s * harmonicY(2, c);
        y(k) = data(b[k]);
    }
    ratioFit(leastSquares(X, y), out);
    ratioFit2(leastSquares(X2, y), out);
    out.points = int(n);
    return out;
}
} // namespace

HarmonicFit fitM1(const std::vector<PolarBin>& bins) {
    return linearHarmonicFit("M1", bins, [](const PolarBin& q) { return q.P; }, [](const PolarBin&) { return 1.0; });
}

HarmonicFit fitM3(const std::vector<PolarBin>& bins) {
    // fraction in a half-range bin (both mirror images) = 2 dtheta sin(theta) P(theta)
    return linearHarmonicFit("M3", bins, [](const PolarBin& q) { return q.fraction; },
                             [](const PolarBin& q) { return 2 * (q.hi - q.lo) * std::sin(q.theta); });
}

HarmonicFit fitM2(const std::vector<PolarBin>& bins) {
    HarmonicFit out;
    out.method = "M2";
    out.a0 = 0.5;
    const auto b = usable(bins);
    const long n = long(b.size());
    Eigen::MatrixXd X(n, 3), X2(n, 1);
    Eigen::VectorXd y(n);
    for (long k = 0; k < n; ++k) {
        const double h1 = std::cos(b[k].hi), h2 = std::cos(b[k].lo);  // h1 < h2
        // fraction with |cos θ| in [h1, h2] = 2 a0 ∫ (1 + Σ ε Y) dh, a0 = 1/2
        for (int l = 0; l < 3; ++l) X(k, l) = integralY(2 * l + 2, h2) - integralY(2 * l + 2, h1);
        X2(k, 0) = X(k, 0);
        y(k) = b[k].fraction - (h2 - h1);
    }
    const Lsq f = leastSquares(X, y);
    for (int l = 0; l < 3; ++l) {
        out.eps[l] = f.beta(l);
        out.se[l] = std::sqrt(std::max(0.0, f.cov(l, l)));
    }
    const Lsq f2 = leastSquares(X2, y);
    out.eps2nd = f2.beta(0);
    out.eps2ndSe = std::sqrt(std::max(0.0, f2.cov(0, 0)));
    out.points = int(n);
    return out;
}

PolarResult analysePolar(const ContactSnapshot& snap, const PolarConfig& cfg) {
    if (cfg.binsTheta < 5 || cfg.binsHeight < 5) inputError("at least 5 bins per method are needed for the sixth-order fits");
    if (!(cfg.mu > 0) || !std::isfinite(cfg.mu)) inputError("friction coefficient mu must be finite and > 0");
    if (!(cfg.chi >= 0 && cfg.chi < 1)) inputError("cone cut-off chi must be in [0, 1)");
    if (cfg.pdfBins < 1 || !(cfg.pdfMax > 0) || !std::isfinite(cfg.pdfMax)) inputError("force pdf needs ≥ 1 bin and a positive, finite range");
    const double an = norm(cfg.axis);
    if (!(an > 0) || !std::isfinite(an)) inputError("reference axis must be non-zero and of finite length");
    const Vec3 e = cfg.axis / an;

    PolarResult r;
    r.time = snap.time;
    r.step = snap.step;
    const int nb = cfg.binsTheta, nh = cfg.binsHeight;
    const double dth = 0.5 * std::numbers::pi / nb, dh = 1.0 / nh;
    r.binWidth.resize(nb);
    r.constHeight.resize(nh);
    std::vector<double> psiCountB(nb, 0), psiCountH(nh, 0);
    std::vector<const ContactRecord*> used;
    for (const ContactRecord& c : snap.contacts) {
        if (c.isWallContact() && !cfg.includeWalls) continue;
        const double nn = norm(c.normal);
        if (!(nn > 0)) continue;
        used.push_back(&c);
    }
    r.contacts = int(used.size());
    if (used.empty()) inputError("no contacts to analyse at time " + fmt(snap.time));
    double fnSum = 0;
    for (const ContactRecord* c : used) {
        const Vec3 n = c->normal / norm(c->normal);
        const double h = std::min(1.0, std::abs(dot(n, e)));
        const double th = std::acos(h);  // folded into [0, π/2]
        const int b = std::min(nb - 1, int(th / dth));
        const int k = std::min(nh - 1, int((1 - h) / dh));  // increasing θ
        const double ft = norm(c->ft);
        for (PolarBin* bin : {&r.binWidth[b], &r.constHeight[k]}) {
            bin->count += 1;
            bin->fn += c->fn;
            bin->ft += ft;
        }
        if (c->fn > 0) {
            const double psi = ft / (cfg.mu * c->fn);
            r.binWidth[b].psi += psi;
            r.constHeight[k].psi += psi;
            psiCountB[b] += 1;
            psiCountH[k] += 1;
        }
        for (int a = 0; a < 3; ++a)
            for (int bb = 0; bb < 3; ++bb) r.fabric[a][bb] += n[a] * n[bb];
        fnSum += c->fn;
    }
    const double C = double(used.size());
    for (auto& row : r.fabric)
        for (double& x : row) x /= C;
    auto finish = [&](PolarBin& bin, double psiCount) {
        bin.fraction = bin.count / C;
        if (bin.count > 0) { bin.fn /= bin.count; bin.ft /= bin.count; }
        if (psiCount > 0) bin.psi /= psiCount;
    };
    for (int b = 0; b < nb; ++b) {
        PolarBin& bin = r.binWidth[b];
        bin.lo = b * dth;
        bin.hi = (b + 1) * dth;
        bin.theta = (b + 0.5) * dth;
        finish(bin, psiCountB[b]);
        const double measure = cfg.cosNormalisation ? std::cos(bin.lo) - std::cos(bin.hi) : dth * std::sin(bin.theta);
        bin.P = bin.fraction / (2 * measure);
    }
    for (int k = 0; k < nh; ++k) {
        PolarBin& bin = r.constHeight[k];
        const double hHi = 1 - k * dh, hLo = 1 - (k + 1) * dh;
        bin.lo = std::acos(hHi);
        bin.hi = std::acos(std::max(0.0, hLo));
        bin.theta = std::acos(0.5 * (hHi + hLo));
        finish(bin, psiCountH[k]);
        bin.P = bin.fraction / (2 * dh);
    }
    r.m1 = fitM1(r.binWidth);
    r.m2 = fitM2(r.constHeight);
    r.m3 = fitM3(r.binWidth);

    // fabric: deviatoric magnitude (Eq. 3.18) and the ε2 it implies for an axisymmetric P_2
    Eigen::Matrix3d F;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) F(a, b) = r.fabric[a][b];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(F);
    const Eigen::Vector3d lam = es.eigenvalues().array() - F.trace() / 3;
    r.Fdev = std::sqrt((std::pow(lam(0) - lam(1), 2) + std::pow(lam(0) - lam(2), 2) + std::pow(lam(1) - lam(2), 2)) / 2);
    const Eigen::Vector3d ev(e.x, e.y, e.z);
    r.eps2Fabric = 15.0 / 4.0 * (double(ev.transpose() * F * ev) - 1.0 / 3.0);

    // normal-force pdf in cones (Sec. 3.4.5)
    r.meanFn = fnSum / C;
    const double df = cfg.pdfMax / cfg.pdfBins;
    r.pdfCentres.resize(cfg.pdfBins);
    for (int k = 0; k < cfg.pdfBins; ++k) r.pdfCentres[k] = (k + 0.5) * df;
    for (auto& p : r.pdf) p.assign(cfg.pdfBins, 0.0);
    r.pdfCounts = {0, 0, 0, 0};
    if (r.meanFn != 0) {
        for (const ContactRecord* c : used) {
            const Vec3 n = c->normal / norm(c->normal);
            const double fs = c->fn / r.meanFn;
            const int k = fs >= 0 ? int(fs / df) : -1;
            for (int a = 0; a < 4; ++a) {
                if (a < 3 && !(std::abs(n[a]) > cfg.chi)) continue;
                r.pdfCounts[a] += 1;
                if (k >= 0 && k < cfg.pdfBins) r.pdf[a][k] += 1;
            }
        }
        for (int a = 0; a < 4; ++a)
            if (r.pdfCounts[a] > 0)
                for (double& x : r.pdf[a]) x /= r.pdfCounts[a] * df;
    }
    return r;
}

void writePolarBinsCsv(const std::string& path, const PolarResult& r) {
    writeFileAtomically(path, [&](std::ostream& os) {
        os << "# pdpm-polar time " << fmt(r.time) << " contacts " << r.contacts << "\n";
        os << "method,theta,theta_deg,theta_lo,theta_hi,count,fraction,P,fn,ft,psi,P6_M1,P6_M2,P6_M3\n";
        auto rows = [&](const std::vector<PolarBin>& bins, const char* m) {
            std::vector<std::pair<double, const PolarBin*>> all;
            for (const PolarBin& b : bins) all.push_back({b.theta, &b});
            for (auto it = bins.rbegin(); it != bins.rend(); ++it) all.push_back({std::numbers::pi - it->theta, &*it});
            for (auto& [th, b] : all) {
                const bool mirrored = th > 0.5 * std::numbers::pi;
                const double lo = mirrored ? std::numbers::pi - b->hi : b->lo, hi = mirrored ? std::numbers::pi - b->lo : b->hi;
                os << m << ',' << fmt(th) << ',' << fmt(th * 180 / std::numbers::pi) << ',' << fmt(lo) << ',' << fmt(hi)
                   << ',' << fmt(b->count) << ',' << fmt(b->fraction) << ',' << fmt(b->P) << ',' << fmt(b->fn) << ','
                   << fmt(b->ft) << ',' << fmt(b->psi) << ',' << fmt(harmonicP6(r.m1.a0, r.m1.eps, th)) << ','
                   << fmt(harmonicP6(r.m2.a0, r.m2.eps, th)) << ',' << fmt(harmonicP6(r.m3.a0, r.m3.eps, th)) << '\n';
            }
        };
        rows(r.binWidth, "b");
        rows(r.constHeight, "h");
    });
}

void writePolarPdfCsv(const std::string& path, const PolarResult& r) {
    writeFileAtomically(path, [&](std::ostream& os) {
        os << "# pdpm-polar time " << fmt(r.time) << " mean_fn " << fmt(r.meanFn) << " contacts x " << r.pdfCounts[0]
           << " y " << r.pdfCounts[1] << " z " << r.pdfCounts[2] << " all " << r.pdfCounts[3] << "\n";
        os << "fstar,P_x,P_y,P_z,P_all\n";
        for (std::size_t k = 0; k < r.pdfCentres.size(); ++k)
            os << fmt(r.pdfCentres[k]) << ',' << fmt(r.pdf[0][k]) << ',' << fmt(r.pdf[1][k]) << ',' << fmt(r.pdf[2][k])
               << ',' << fmt(r.pdf[3][k]) << '\n';
    });
}

std::string polarSeriesHeader() {
    std::string h = "time,step,contacts,strain_axial,strain_dev";
    for (const char* m : {"M1", "M2", "M3"}) {
        const std::string s = m;
        h += "," + s + "_a0," + s + "_eps2," + s + "_eps4," + s + "_eps6," + s + "_se2," + s + "_se4," + s + "_se6," + s +
             "_eps_P2," + s + "_se_P2";
    }
    h += ",Fdev,Fdev_over_sqrt3,eps2_fabric,mean_fn";
    return h;
}

std::string polarSeriesRow(const PolarResult& r, double axialStrain, double devStrain) {
    std::ostringstream os;
    os << fmt(r.time) << ',' << r.step << ',' << r.contacts << ',' << fmt(axialStrain) << ',' << fmt(devStrain);
    for (const HarmonicFit* f : {&r.m1, &r.m2, &r.m3}) {
        os << ',' << fmt(f->a0);
        for (double x : f->eps) os << ',' << fmt(x);
        for (double x : f->se) os << ',' << fmt(x);
        os << ',' << fmt(f->eps2nd) << ',' << fmt(f->eps2ndSe);
    }
    os << ',' << fmt(r.Fdev) << ',' << fmt(r.Fdev / std::sqrt(3.0)) << ',' << fmt(r.eps2Fabric) << ',' << fmt(r.meanFn);
    return os.str();
}

} // namespace pdpm::tools
