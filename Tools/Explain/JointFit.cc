#include "JointFit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pdpm::explain {

double chiSquareUpperTail(double x, int dof) {
    if (!(x > 0) || dof <= 0) return 1;
    // regularised upper incomplete gamma Q(a, z), a = dof/2, z = x/2: the power series of P for
    // z < a + 1, else the continued fraction of Q (evaluated by Lentz's method)
    const double a = 0.5 * dof, z = 0.5 * x;
    const double logPrefactor = a * std::log(z) - z - std::lgamma(a);
    if (z < a + 1) {
        double term = 1 / a, sum = term;
        for (int n = 1; n < 1000 && std::fabs(term) > 1e-16 * std::fabs(sum); ++n) {
            term *= z / (a + n);
            sum += term;
        }
        return std::clamp(1 - std::exp(logPrefactor) * sum, 0.0, 1.0);
    }
    const double tiny = 1e-300;
    double b = z + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int n = 1; n < 1000; ++n) {
        const double an = -n * (n - a);
        b += 2;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1) < 1e-15) break;
    }
    return std::clamp(std::exp(logPrefactor) * h, 0.0, 1.0);
}

namespace {

/// One recording's part of the joint fit: its model with the mechanism on, its device parameters.
struct Part {
    const Recording* rec = nullptr;
    Model model;
    std::vector<char> on;
    FitOptions device;          ///< device parameters free, the material parameters held
    std::vector<double> start;  ///< full parameter vector: device parameters at the best material values so far
    bool acceptedOwn = false;   ///< the recording accepted the mechanism on its own
    std::vector<double> ownFinal;
};

double internalOf(const ParDef& d, double v) { return d.logScale ? std::log10(v) : v / d.scale; }
double physicalOf(const ParDef& d, double u) { return d.logScale ? std::pow(10.0, u) : u * d.scale; }

class Profile {
public:
    Profile(std::vector<Part>& parts, const std::vector<int>& shared, std::vector<double> lo, std::vector<double> hi)
        : parts_(parts), shared_(shared), lo_(std::move(lo)), hi_(std::move(hi)) {}

    /// -2 ln L (up to a constant) with the shared parameters at internal coordinates u. Every part's
    /// device fit starts from its parameters at the best value so far (warm start along the search)
    /// and, with `bothStarts`, also from the recording's own final fit; `keep` makes this evaluation's
    /// fits the starts whatever its value.
    double operator()(const std::vector<double>& u, bool keep = false) {
        ++evaluations;
        double f = 0;
        std::vector<std::vector<double>> fitted;
        for (Part& pt : parts_) {
            // two starts (while searching for the start): the device parameters at the best value so
            // far, and the recording's own final fit (the device fit can have several minima, e.g.
            // eps0 against the cohesive loose-packing strain); then warm starts only
            FitResult r;
            r.rss = -1;
            for (const std::vector<double>* from : {&pt.start, &pt.ownFinal}) {
                if (from == &pt.ownFinal && (!bothStarts || pt.ownFinal == pt.start)) break;  // the same start gives the same fit
                std::vector<double> p = *from;
                setShared(u, p);
                FitResult q = fitModel(pt.model, pt.rec->stress, pt.on, p, pt.device);
                if (r.rss < 0 || q.rss < r.rss) r = std::move(q);
            }
            f += double(pt.rec->size()) * std::log(std::max(r.rss, 1e-300));
            fitted.push_back(std::move(r.p));
        }
        if (!std::isfinite(f)) return std::numeric_limits<double>::infinity();
        if (keep || f < best_) {
            best_ = f;
            for (std::size_t q = 0; q < parts_.size(); ++q) parts_[q].start = std::move(fitted[q]);
        }
        return f;
    }
    /// Sets the shared parameters of a full parameter vector. The internal coordinates are those of
    /// the first recording's definitions: a parameter's scale can depend on the recording (the
    /// tension's on its largest stress, tau_v's on its rates), its physical value must not.
    void setShared(const std::vector<double>& u, std::vector<double>& p) const {
        const Model& ref = parts_.front().model;
        for (std::size_t j = 0; j < shared_.size(); ++j)
            p[std::size_t(shared_[j])] = std::clamp(physicalOf(ref.defs()[std::size_t(shared_[j])], u[j]), lo_[j], hi_[j]);
    }
    std::vector<double> clampInternal(std::vector<double> u) const {
        const auto& defs = parts_.front().model.defs();
        for (std::size_t j = 0; j < u.size(); ++j)
            u[j] = std::clamp(u[j], internalOf(defs[std::size_t(shared_[j])], lo_[j]),
                              internalOf(defs[std::size_t(shared_[j])], hi_[j]));
        return u;
    }
    int evaluations = 0;
    bool bothStarts = true;
    std::vector<std::vector<double>> starts() const {
        std::vector<std::vector<double>> v;
        for (const Part& pt : parts_) v.push_back(pt.start);
        return v;
    }
    void setStarts(const std::vector<std::vector<double>>& v) {
        for (std::size_t q = 0; q < parts_.size(); ++q) parts_[q].start = v[q];
    }

private:
    std::vector<Part>& parts_;
    const std::vector<int>& shared_;
    std::vector<double> lo_, hi_;
    double best_ = std::numeric_limits<double>::infinity();
};

/// Nelder-Mead minimisation of the profile (dimension 1 or 2 in practice), inside the bounds.
std::vector<double> nelderMead(Profile& f, std::vector<double> u0, const std::vector<double>& step, double& fBest) {
    const std::size_t d = u0.size();
    std::vector<std::vector<double>> x{f.clampInternal(u0)};
    for (std::size_t j = 0; j < d; ++j) {
        std::vector<double> v = x[0];
        v[j] += step[j];
        if (f.clampInternal(v)[j] == x[0][j]) v[j] = x[0][j] - step[j];  // at a bound: step inwards
        x.push_back(f.clampInternal(v));
    }
    std::vector<double> fx;
    for (const auto& v : x) fx.push_back(f(v));
    const int maxEval = 60 + 40 * int(d);
    for (int it = 0; f.evaluations < maxEval; ++it) {
        std::vector<std::size_t> order(d + 1);
        for (std::size_t i = 0; i <= d; ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fx[a] < fx[b]; });
        std::vector<std::vector<double>> xs;
        std::vector<double> fs;
        for (std::size_t i : order) {
            xs.push_back(x[i]);
            fs.push_back(fx[i]);
        }
        x = xs;
        fx = fs;
        double size = 0;
        for (std::size_t i = 1; i <= d; ++i)
            for (std::size_t j = 0; j < d; ++j) size = std::max(size, std::fabs(x[i][j] - x[0][j]));
        // f is -2 ln L: 0.02 is far below the 3.84 of an interval; a flat simplex must also be small
        // (one that straddles a sharp minimum or lies along a ridge can have nearly equal values)
        if ((fx[d] - fx[0] < 0.02 && size < 0.02) || size < 1e-4) break;
        std::vector<double> c(d, 0.0);
        for (std::size_t i = 0; i < d; ++i)
            for (std::size_t j = 0; j < d; ++j) c[j] += x[i][j] / double(d);
        auto along = [&](double t) {
            std::vector<double> v(d);
            for (std::size_t j = 0; j < d; ++j) v[j] = c[j] + t * (x[d][j] - c[j]);
            return f.clampInternal(v);
        };
        const std::vector<double> xr = along(-1);
        const double fr = f(xr);
        if (fr < fx[0]) {
            const std::vector<double> xe = along(-2);
            const double fe = f(xe);
            if (fe < fr) {
                x[d] = xe;
                fx[d] = fe;
            } else {
                x[d] = xr;
                fx[d] = fr;
            }
        } else if (fr < fx[d - 1]) {
            x[d] = xr;
            fx[d] = fr;
        } else {
            const std::vector<double> xc = fr < fx[d] ? along(-0.5) : along(0.5);
            const double fc = f(xc);
            if (fc < std::min(fr, fx[d])) {
                x[d] = xc;
                fx[d] = fc;
            } else {  // shrink towards the best vertex
                for (std::size_t i = 1; i <= d; ++i) {
                    for (std::size_t j = 0; j < d; ++j) x[i][j] = x[0][j] + 0.5 * (x[i][j] - x[0][j]);
                    fx[i] = f(x[i]);
                }
            }
        }
    }
    const std::size_t best = std::size_t(std::min_element(fx.begin(), fx.end()) - fx.begin());
    fBest = fx[best];
    return x[best];
}

} // namespace

JointFit fitJointly(int comp, const std::vector<std::size_t>& which, const std::vector<Recording>& recs,
                    const std::vector<Protocol>& protos, const std::vector<ExplainResult>& per) {
    JointFit J;
    J.comp = comp;
    J.recordings = which;
    std::vector<Part> parts;
    for (std::size_t k : which) {
        Part pt{&recs[k], Model(makeModelInput(recs[k], protos[k])), per[k].onFinal, {}, per[k].pFinal, false, per[k].pFinal};
        pt.model.limitsForLoadingCurve(per[k].onBaseline[kLoadingCurve] != 0);  // as in its own explain()
        pt.acceptedOwn = pt.on[std::size_t(comp)] != 0;
        pt.on[std::size_t(comp)] = 1;
        // every nuisance free (a calibrated compliance stays held): a nuisance the recording's own
        // selection left out can still trade off against the material parameter (compliance against
        // n or lambda), and its own intervals allow for that too (MechanismResult::widenedBy)
        pt.on[kCompliance] = pt.on[kDrift] = 1;
        const std::vector<int> material = pt.model.paramsOf(comp);
        for (int j : freeParamsFor(pt.model, pt.on, per[k].heldParam))
            if (std::find(material.begin(), material.end(), j) == material.end()) pt.device.freeParams.push_back(j);
        pt.device.whitener = per[k].noise.whitener();
        parts.push_back(std::move(pt));
    }
    const std::vector<int> shared = parts.front().model.paramsOf(comp);
    const std::size_t d = shared.size();
    // bounds: the intersection of the recordings' ranges (some scale with the recorded stress)
    std::vector<double> lo(d, -std::numeric_limits<double>::infinity()), hi(d, std::numeric_limits<double>::infinity());
    for (const Part& pt : parts)
        for (std::size_t j = 0; j < d; ++j) {
            lo[j] = std::max(lo[j], pt.model.defs()[std::size_t(shared[j])].lo);
            hi[j] = std::min(hi[j], pt.model.defs()[std::size_t(shared[j])].hi);
        }
    const auto& defs = parts.front().model.defs();
    Profile prof(parts, shared, lo, hi);

    // start: the best of the recordings' own estimates and their mean (internal coordinates)
    std::vector<std::vector<double>> starts;
    for (const Part& src : parts) {
        if (!src.acceptedOwn) continue;
        std::vector<double> u(d);
        for (std::size_t j = 0; j < d; ++j) u[j] = internalOf(defs[std::size_t(shared[j])], src.ownFinal[std::size_t(shared[j])]);
        starts.push_back(prof.clampInternal(u));
    }
    if (starts.size() >= 2) {
        std::vector<double> mean(d, 0.0);
        for (const auto& u : starts)
            for (std::size_t j = 0; j < d; ++j) mean[j] += u[j] / double(starts.size());
        starts.push_back(mean);
    }
    std::vector<double> u0;
    double f0 = std::numeric_limits<double>::infinity();
    for (const auto& u : starts) {
        const double f = prof(u);
        if (f < f0) {
            f0 = f;
            u0 = u;
        }
    }
    if (u0.empty()) {  // no recording accepted it on its own (not expected): the first one's values
        for (std::size_t j = 0; j < d; ++j) u0.push_back(internalOf(defs[std::size_t(shared[j])], parts.front().ownFinal[std::size_t(shared[j])]));
        u0 = prof.clampInternal(u0);
    }
    prof(u0, true);  // device parameters at the start
    prof.bothStarts = false;
    std::vector<double> step(d);
    for (std::size_t j = 0; j < d; ++j)
        step[j] = defs[std::size_t(shared[j])].logScale ? 0.1 : std::max(0.25, 0.1 * std::fabs(u0[j]));
    double fBest = 0;
    std::vector<double> uBest = nelderMead(prof, u0, step, fBest);
    J.m2lnLJoint = prof(uBest, true);  // and every part's start = its fit at the joint optimum

    J.joint.comp = comp;
    J.joint.params = shared;
    auto setValues = [&] {
        J.joint.value.clear();
        for (std::size_t j = 0; j < d; ++j)
            J.joint.value.push_back(std::clamp(physicalOf(defs[std::size_t(shared[j])], uBest[j]), lo[j], hi[j]));
    };
    setValues();
    std::vector<std::vector<double>> atOptimum = prof.starts();
    if (d == 1) {
        // one material parameter: the likelihood-ratio interval {u : f(u) <= f* + 3.84}, scanned outwards
        // from the optimum with each step's fits as the next step's starts (continuation along a
        // ridge, e.g. n against the compliance, which a curvature at the optimum misses), then bisected.
        // A scan that finds a lower value than the optimum's moves the optimum there and starts again.
        const double uLo = prof.clampInternal({-1e300})[0], uHi = prof.clampInternal({1e300})[0];
        for (int attempt = 0; attempt < 3; ++attempt) {
            const double target = J.m2lnLJoint + 3.841459;
            double fLow = J.m2lnLJoint, uLow = uBest[0];
            auto eval = [&](double u) {
                const double f = prof({u}, true);
                if (f < fLow) {
                    fLow = f;
                    uLow = u;
                }
                return f;
            };
            J.joint.lo.clear();
            J.joint.hi.clear();
            for (int dir : {-1, 1}) {
                prof.setStarts(atOptimum);
                const double bound = dir < 0 ? uLo : uHi;
                double in = uBest[0], out = bound;
                double step = defs[std::size_t(shared[0])].logScale ? 0.02 : 0.02 * std::max(1.0, std::fabs(uBest[0]));
                bool found = false;
                for (int k = 0; k < 14 && !found; ++k, step *= 2) {
                    const double u = dir < 0 ? std::max(bound, uBest[0] - step) : std::min(bound, uBest[0] + step);
                    if (eval(u) >= target) {
                        out = u;
                        found = true;
                    } else {
                        in = u;
                        if (u == bound) break;
                    }
                }
                if (found)
                    for (int k = 0; k < 7; ++k) {
                        const double mid = 0.5 * (in + out);
                        (eval(mid) >= target ? out : in) = mid;
                    }
                const double edge = found ? 0.5 * (in + out) : bound;
                const double v = std::clamp(physicalOf(defs[std::size_t(shared[0])], edge), lo[0], hi[0]);
                (dir < 0 ? J.joint.lo : J.joint.hi).push_back(v);
            }
            if (fLow >= J.m2lnLJoint - 0.01) break;
            prof.setStarts(atOptimum);
            uBest = {uLow};
            J.m2lnLJoint = prof(uBest, true);
            setValues();
            atOptimum = prof.starts();
        }
        prof.setStarts(atOptimum);
        J.intervalMethod = "profile_likelihood_ratio";
    } else {
        // several: from the profile's curvature, -2 ln L ~ f, covariance 2 H^-1 (internal coordinates)
        std::vector<double> h(d);
        for (std::size_t j = 0; j < d; ++j) {
            h[j] = defs[std::size_t(shared[j])].logScale ? 0.02 : 0.02 * std::max(1.0, std::fabs(uBest[j]));
            for (int tries = 0; tries < 6; ++tries) {  // a step that moves f by O(1): above the fits' tolerance
                std::vector<double> up = uBest;
                up[j] += h[j];
                const double df = prof(prof.clampInternal(up)) - J.m2lnLJoint;
                if (df < 0.5) h[j] *= 2;
                else if (df > 20) h[j] /= 3;
                else break;
            }
        }
        auto at = [&](std::size_t a, double sa, std::size_t b, double sb) {
            std::vector<double> u = uBest;
            u[a] += sa * h[a];
            u[b] += sb * h[b];
            return prof(u);  // may leave the bounds: the profile clamps the physical value
        };
        const long nd = long(d);
        Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nd, nd);
        for (std::size_t a = 0; a < d; ++a) {
            H(long(a), long(a)) = (at(a, 1, a, 0) - 2 * J.m2lnLJoint + at(a, -1, a, 0)) / (h[a] * h[a]);
            for (std::size_t b = a + 1; b < d; ++b) {
                const double v = (at(a, 1, b, 1) - at(a, 1, b, -1) - at(a, -1, b, 1) + at(a, -1, b, -1)) / (4 * h[a] * h[b]);
                H(long(a), long(b)) = H(long(b), long(a)) = v;
            }
        }
        Eigen::LLT<Eigen::MatrixXd> llt(H);
        // a central difference across a bound sees one flat side: no curvature claimed there
        bool inside = true;
        for (std::size_t j = 0; j < d; ++j) {
            std::vector<double> a = uBest, b = uBest;
            a[j] -= h[j];
            b[j] += h[j];
            inside = inside && prof.clampInternal(a) == a && prof.clampInternal(b) == b;
        }
        const bool curved = inside && llt.info() == Eigen::Success;
        J.intervalMethod = curved ? "profile_curvature" : "not_determined";
        const Eigen::MatrixXd cov = curved ? Eigen::MatrixXd(2 * llt.solve(Eigen::MatrixXd::Identity(nd, nd)))
                                           : Eigen::MatrixXd::Zero(nd, nd);
        for (std::size_t j = 0; j < d; ++j) {
            const ParDef& pd = defs[std::size_t(shared[j])];
            const double su = std::sqrt(std::max(cov(long(j), long(j)), 0.0));
            J.joint.lo.push_back(curved ? std::clamp(physicalOf(pd, uBest[j] - 1.96 * su), lo[j], hi[j]) : lo[j]);
            J.joint.hi.push_back(curved ? std::clamp(physicalOf(pd, uBest[j] + 1.96 * su), lo[j], hi[j]) : hi[j]);
        }
        prof.setStarts(atOptimum);
    }

    // each recording with its own material parameters, started at the joint optimum (so never worse)
    // and at its own estimate
    J.m2lnLSeparate = 0;
    for (Part& pt : parts) {
        // this recording's term of -2 ln L at the joint optimum (its device refitted from the optimum's fit)
        std::vector<double> pj = pt.start;
        prof.setShared(uBest, pj);
        const FitResult atJoint = fitModel(pt.model, pt.rec->stress, pt.on, pj, pt.device);
        const double termJoint = double(pt.rec->size()) * std::log(std::max(atJoint.rss, 1e-300));
        FitOptions fo = pt.device;
        fo.freeParams.insert(fo.freeParams.end(), shared.begin(), shared.end());
        FitResult best = fitModel(pt.model, pt.rec->stress, pt.on, pt.start, fo);
        if (pt.acceptedOwn) {
            FitResult own = fitModel(pt.model, pt.rec->stress, pt.on, pt.ownFinal, fo);
            if (own.rss < best.rss) best = std::move(own);
        }
        std::vector<double> vals;
        for (int j : shared) vals.push_back(best.p[std::size_t(j)]);
        J.separate.push_back(vals);
        const double termOwn = double(pt.rec->size()) * std::log(std::max(best.rss, 1e-300));
        J.m2lnLSeparate += termOwn;
        J.recordingStatistic.push_back(std::max(0.0, termJoint - termOwn));
        J.recordingOwnTerm.push_back(termOwn);
    }
    J.statistic = std::max(0.0, J.m2lnLJoint - J.m2lnLSeparate);
    J.dof = int(d) * int(parts.size() - 1);
    J.pValue = chiSquareUpperTail(J.statistic, J.dof);
    J.consistent = J.pValue >= kJointConsistencyLevel;
    J.evaluations = prof.evaluations;
    return J;
}

void leaveOneOut(JointFit& J, const std::vector<Recording>& recs, const std::vector<Protocol>& protos,
                 const std::vector<ExplainResult>& per) {
    J.leftOut.clear();
    if (J.recordings.size() < 3 || J.recordingOwnTerm.size() != J.recordings.size()) return;
    const int d = static_cast<int>(J.joint.params.size());
    for (std::size_t q = 0; q < J.recordings.size(); ++q) {
        std::vector<std::size_t> others;
        for (std::size_t r = 0; r < J.recordings.size(); ++r)
            if (r != q) others.push_back(J.recordings[r]);
        const JointFit O = fitJointly(J.comp, others, recs, protos, per);
        JointFit::LeftOut L;
        L.recording = J.recordings[q];
        L.statistic = std::max(0.0, J.m2lnLJoint - O.m2lnLJoint - J.recordingOwnTerm[q]);
        L.dof = d;
        L.pValue = chiSquareUpperTail(L.statistic, d);
        L.othersConsistent = O.consistent;
        L.differs = O.consistent && L.pValue < kJointConsistencyLevel;
        J.leftOut.push_back(L);
    }
}

} // namespace pdpm::explain
