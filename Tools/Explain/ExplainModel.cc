#include "ExplainModel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Core/Error.h"

namespace pdpm::explain {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kCompNames[kNumComp] = {"baseline",   "instrument_compliance", "sensor_drift",
                                          "contact_relaxation", "plasticity", "cohesion",
                                          "wall_friction", "rate_dependence", "stiffness_nonlinearity",
                                          "rolling_resistance", "loading_curve", "hysteresis",
                                          "relaxation_stress_dependence"};
constexpr std::size_t kMaxKnots = 48;
const char* knotName(std::size_t k) {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (std::size_t i = 0; i < kMaxKnots; ++i) v.push_back("curve_knot_" + std::to_string(i + 1));
        return v;
    }();
    return names[k].c_str();
}
} // namespace

const char* compName(int c) { return (c >= 0 && c < kNumComp) ? kCompNames[c] : "?"; }
int compFromName(const std::string& name) {
    for (int c = 0; c < kNumComp; ++c)
        if (name == kCompNames[c]) return c;
    return -1;
}
bool isNuisance(int c) { return c == kCompliance || c == kDrift; }
bool isMechanism(int c) { return c >= kRelaxation && c <= kLastMechanism; }

ModelInput makeModelInput(const Recording& rec, const Protocol& proto) {
    ModelInput in;
    in.t = rec.t;
    in.eps = rec.strain;
    const std::size_t n = rec.size();
    in.rate = smoothedRate(rec.t, rec.strain, std::max(1, int(n / 800)));
    in.hold.assign(n, 0);
    const std::vector<PhaseSegment> phases = detectPhases(rec.t, rec.strain);
    for (const auto& s : phases)
        if (s.phase == Phase::Hold) {
            // The hold begins at its first sample at the hold's strain (holdExtent): the phase detector
            // finds it several samples late, and a hold whose t0 is below the sampling interval loses
            // several per cent of its stress in those samples. (Its end stays where the detector puts
            // it, as measured in the benchmark; the hold has all but stopped relaxing there.)
            for (std::size_t i = std::min(s.begin, holdExtent(rec.strain, s).begin); i < s.end; ++i) in.hold[i] = 1;
        }
    // a creep step (constant stress) is a hold of the relaxation term from its first sample: the
    // strain it creeps is what keeps the stress up while the contacts relax (the stress rate is
    // zero, the strain rate is not, so the strain-rate phases call its start a loading)
    in.creep = creepSamples(rec, proto);
    for (std::size_t i = 0; i < n; ++i) in.hold[i] = in.hold[i] || in.creep[i];
    in.height = proto.height;
    in.contactAtStart = proto.zeroBeforeContact;
    in.diameter = proto.diameter;
    const auto [lo, hi] = std::minmax_element(rec.strain.begin(), rec.strain.end());
    in.epsMin = *lo;
    in.epsRange = std::max(*hi - *lo, 1e-12);
    double smax = 0;
    for (double s : rec.stress) smax = std::max(smax, std::abs(s));
    in.stressMax = std::max(smax, 1e-12);
    {  // reference stress of relaxation_stress_dependence
        double sumLog = 0;
        int holds = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (in.hold[i] && (i == 0 || !in.hold[i - 1]) && rec.stress[i] > 0) {
                sumLog += std::log(rec.stress[i]);
                ++holds;
            }
        in.holdStressRef = holds > 0 ? std::exp(sumLog / holds) : 0.5 * in.stressMax;
    }
    in.duration = std::max(rec.t.back() - rec.t.front(), 1e-12);
    {  // one loading speed between holds, nothing else (rateChangesOnlyAtStops)
        bool others = std::find(in.creep.begin(), in.creep.end(), char(1)) != in.creep.end();
        bool anyLoad = false;
        double vmin = 0, vmax = 0;
        for (const auto& s : phases) {
            if (s.phase == Phase::Hold) continue;
            if (s.phase != Phase::Load || s.end <= s.begin) {
                others = true;
                continue;
            }
            std::vector<double> r(in.rate.begin() + long(s.begin), in.rate.begin() + long(s.end));
            std::nth_element(r.begin(), r.begin() + long(r.size() / 2), r.end());
            const double v = r[r.size() / 2];
            vmin = anyLoad ? std::min(vmin, v) : v;
            vmax = anyLoad ? std::max(vmax, v) : v;
            anyLoad = true;
        }
        in.rateChangesOnlyAtStops = anyLoad && !others && vmin > 0 && vmax <= 1.2 * vmin;
    }
    return in;
}

Model::Model(const ModelInput& in) : in_(in) {
    const double E0 = in.stressMax / in.epsRange;
    double rmax = 0;
    for (double r : in.rate) rmax = std::max(rmax, std::abs(r));
    const double tauScale = rmax > 0 ? 0.02 / rmax : 1.0;  // gives 2 % of E*range at the top rate
    defs_ = {
        {"E", "Pa", kBaseline, E0 * 1e-3, E0 * 1e3, kNaN, 0, true},
        {"eps0", "-", kBaseline, in.contactAtStart ? std::min(in.eps.front(), in.epsMin + 0.95 * in.epsRange) : in.epsMin - in.epsRange, in.epsMin + 0.95 * in.epsRange, kNaN, 0.05 * in.epsRange, false},
        {"compliance_ratio", "-", kCompliance, 0, 0.3, 0, 0.05, false},
        {"offset", "Pa", kDrift, -in.stressMax, in.stressMax, 0, 0.01 * in.stressMax, false},
        {"drift_rate", "Pa/s", kDrift, -in.stressMax / in.duration, in.stressMax / in.duration, 0,
         0.01 * in.stressMax / in.duration, false},
        {"C", "-", kRelaxation, 0, 0.5, 0, 0.02, false},
        {"t0", "s", kRelaxation, 1e-4, 1e3, kNaN, 0, true},
        {"unload_stiffness_ratio", "-", kPlasticity, 1, 200, 1, 0, true},
        {"tension", "Pa", kCohesion, 0, in.stressMax, 0, 0.01 * in.stressMax, false},
        {"muK", "-", kWallFriction, 0, 1.5, 0, 0.05, false},
        {"tau_v", "s", kRate, 0, 1e3 * tauScale, 0, tauScale, false},
        {"n", "-", kNonlinearity, 0.2, 4, 1, 0.1, false},
        {"unload_exponent", "-", kHysteresis, 0.25, 8, 1, 0.1, false},
        {"reload_exponent", "-", kHysteresis, 0.25, 8, 1, 0.1, false},
        // |beta| < 1: the stress a hold loses, about C s_h ln(1 + t/t0) ~ s_h^(1 - beta), grows with the
        // hold stress (more force in the contacts, more to relax); beta = 1 would make it independent
        {"C_stress_exponent", "-", kRelaxStress, -1, 1, 0, 0.1, false},
    };
    // loading_curve knots: every virgin hold strain (where the stress level of a hold is set), the
    // largest strain, and fill-in knots so that no gap exceeds epsRange/8. A creep step that begins
    // on the virgin curve (its first sample at the largest strain so far) gets its knot at the
    // largest strain it reaches, not where it begins: the strain it creeps is time-dependent
    // deformation, and a kink of the skeleton curve exactly at its start would let a plateau of the
    // curve stand in for it (the curve is a function of strain only). The controller may let the
    // strain of a creep step move back a little, so neither its first nor its last sample is used.
    std::vector<double> ks;
    {
        double emax = -std::numeric_limits<double>::infinity();
        bool inHold = false;
        const bool anyCreep = in.creep.size() == in.eps.size();
        bool virginCreep = false;
        double creepTop = 0;
        for (std::size_t i = 0; i < in.eps.size(); ++i) {
            const bool isCreep = anyCreep && in.creep[i];
            const bool virginHold = in.hold[i] && in.eps[i] >= emax - 1e-9 * in.epsRange;
            if (virginHold && !inHold && !isCreep) ks.push_back(in.eps[i]);
            if (isCreep && (i == 0 || !in.creep[i - 1])) {  // a creep step begins
                // on the virgin curve: within the knot-merge distance (1 % of the range) of the largest
                // strain so far (the piston may step back a little when the creep control takes over)
                virginCreep = in.eps[i] >= emax - 0.01 * in.epsRange;
                creepTop = in.eps[i];
            }
            if (isCreep) creepTop = std::max(creepTop, in.eps[i]);
            if (isCreep && virginCreep && (i + 1 == in.eps.size() || !in.creep[i + 1])) ks.push_back(creepTop);
            inHold = in.hold[i];
            emax = std::max(emax, in.eps[i]);
        }
        ks.push_back(in.epsMin + in.epsRange);
        ks.push_back(in.epsMin);
        std::sort(ks.begin(), ks.end());
        std::vector<double> merged;
        for (double k : ks)
            if (merged.empty() || k - merged.back() > 0.01 * in.epsRange) merged.push_back(k);
        for (std::size_t a = 0; a + 1 < merged.size(); ++a) {
            knots_.push_back(merged[a]);
            const int parts = int(std::ceil((merged[a + 1] - merged[a]) / (in.epsRange / 8) - 1e-9));
            for (int q = 1; q < parts; ++q) knots_.push_back(merged[a] + (merged[a + 1] - merged[a]) * q / parts);
        }
        knots_.push_back(merged.back());
        if (knots_.size() > kMaxKnots) {  // thin evenly (many holds)
            std::vector<double> thin;
            for (std::size_t q = 0; q < kMaxKnots; ++q) thin.push_back(knots_[q * (knots_.size() - 1) / (kMaxKnots - 1)]);
            knots_ = thin;
        }
    }
    // the last knot is held at 0: a common level of all knots would only rescale E
    for (std::size_t k = 0; k + 1 < knots_.size(); ++k)
        defs_.push_back({knotName(k), "-", kLoadingCurve, -0.95, 5.0, 0, 0.02, false});
}

void Model::limitDrift(double fraction) {
    defs_[pDrift].hi = fraction * in_.stressMax / in_.duration;
    defs_[pDrift].lo = -defs_[pDrift].hi;
}

double Model::curveFactor(const std::vector<double>& p, double e) const {
    const std::size_t K = knots_.size();
    if (K < 2) return 1.0;
    auto val = [&](std::size_t k) { return k + 1 < K ? p[kNumPar + k] : 0.0; };
    if (e <= knots_[0]) return 1.0 + val(0);
    if (e >= knots_[K - 1]) return 1.0;
    const std::size_t hi = std::size_t(std::upper_bound(knots_.begin(), knots_.end(), e) - knots_.begin());
    const std::size_t lo = hi - 1;
    const double f = (e - knots_[lo]) / (knots_[hi] - knots_[lo]);
    return 1.0 + (1 - f) * val(lo) + f * val(hi);
}

std::vector<double> Model::defaults() const {
    std::vector<double> p(defs_.size());
    for (std::size_t k = 0; k < defs_.size(); ++k) p[k] = std::isnan(defs_[k].off) ? 0 : defs_[k].off;
    p[pE] = in_.stressMax / in_.epsRange;
    p[pEps0] = std::max(in_.epsMin, defs_[pEps0].lo);
    p[pRelaxT0] = 1.0;
    return p;
}

std::vector<int> Model::paramsOf(int c) const {
    std::vector<int> out;
    for (std::size_t k = 0; k < defs_.size(); ++k)
        if (defs_[k].comp == c) out.push_back(int(k));
    return out;
}

void Model::evaluate(const std::vector<double>& p, const std::vector<char>& on, std::vector<double>& out) const {
    const std::size_t n = in_.t.size();
    out.assign(n, 0.0);
    const double E = p[pE], e0 = p[pEps0], er = in_.epsRange;
    const double nExp = on[kNonlinearity] ? p[pExpN] : 1.0;
    const double lam = on[kPlasticity] ? p[pLambda] : 1.0;
    const double floorS = on[kCohesion] ? -p[pTension] : 0.0;
    const double kap = on[kCompliance] ? p[pKappa] : 0.0;
    const double C = on[kRelaxation] ? p[pRelaxC] : 0.0;
    const double t0 = p[pRelaxT0];
    const double beta = on[kRelaxation] && on[kRelaxStress] ? p[pRelaxBeta] : 0.0;
    double Ch = C;  // C of the current hold
    const double tauV = on[kRate] ? p[pTauV] : 0.0;
    const double muK = on[kWallFriction] ? p[pMuK] : 0.0;
    const double a = on[kDrift] ? p[pOffset] : 0.0, b = on[kDrift] ? p[pDrift] : 0.0;
    const bool linear = nExp == 1.0;
    const double hu = on[kHysteresis] ? p[pUnloadExp] : 1.0, hr = on[kHysteresis] ? p[pReloadExp] : 1.0;
    const bool hy = hu != 1.0 || hr != 1.0;
    const bool curve = on[kLoadingCurve] && !knots_.empty();
    // cohesion: the cohesive bonds hold a looser packing on first loading, which yields an extra
    // compaction of strain scale x_c = sigma_c / E (first-loading curve E x^2 / (x + x_c) instead of
    // E x; the collapse is permanent, so unloading and reloading keep the deficit reached at the
    // largest strain); on unloading the branch continues below zero force into tension down to
    // -sigma_c. No tension before the first contact.
    // With a free loading curve the loose packing is one of the first-loading shapes the curve already
    // takes (it is a function of strain on first loading, its deficit kept by the branch below):
    // cohesion is then the tension branch alone, so an unidentified strength (an unload stopped
    // before the bed lets go) cannot reshape the first loading through x_c.
    const bool coh = on[kCohesion] && p[pTension] > 0;
    const double xc = coh && !curve ? p[pTension] / E : 0.0;
    auto virgin = [&](double e) {  // elastic skeleton curve (linear extension into tension with cohesion)
        const double x = e - e0;
        if (x <= 0) return coh ? E * x : 0.0;
        const double s = linear ? E * x : E * er * std::pow(x / er, nExp);
        return curve ? s * curveFactor(p, e) : s;
    };
    auto loose = [&](double e) {  // stress deficit of the loose cohesive packing on first loading
        const double x = e - e0;
        return (coh && x > 0) ? E * x * xc / (x + xc) : 0.0;
    };
    auto tangent = [&](double e) {
        const double x = std::max(e - e0, 1e-9 * er);
        const double k = linear ? E : E * nExp * std::pow(x / er, nExp - 1);
        return curve ? k * std::max(curveFactor(p, e), 0.05) : k;
    };
    const int passes = kap > 0 ? 4 : 1;
    std::vector<double> inner(n, 0.0);
    const double mobil = 0.02 * er;
    for (int pass = 0; pass < passes; ++pass) {
        double emax = -std::numeric_limits<double>::infinity(), sAtMax = 0, dLoose = 0;
        double Dcur = 0, Dprev = 0, Dend = 0, eEnd = 0, selEnd = 0, th = 0, sh = 0;
        bool inHold = false;
        double m = 1.0, ePrev = 0;
        Loop hyst{hu, hr, 0.005 * er};
        for (std::size_t i = 0; i < n; ++i) {
            const double e = in_.eps[i] - (kap > 0 ? kap / E * inner[i] : 0.0);
            const double x = virgin(e);
            double sel;
            if (e >= emax) {
                emax = e;
                sAtMax = x;
                dLoose = loose(e);
                sel = e > e0 ? x - dLoose : 0.0;
                hyst.virgin = true;
            } else {
                sel = lam * x - (lam - 1) * sAtMax - dLoose;
            }
            sel = std::max(sel, emax > e0 ? floorS : 0.0);
            if (hy && e < emax && emax > e0) sel = hyst.branch(e, sel, sAtMax - dLoose, floorS);
            if (C > 0) {
                if (in_.hold[i]) {
                    if (!inHold) {
                        inHold = true;
                        th = in_.t[i];
                        Dprev = Dcur;
                        sh = std::max(sel - Dcur, 0.0);
                        Ch = beta != 0 && sh > 0 ? C * std::pow(sh / in_.holdStressRef, -beta) : C;
                    }
                    Dcur = Dprev + sh * (1 - std::pow(1 + (in_.t[i] - th) / t0, -Ch));
                } else {
                    if (inHold) {
                        inHold = false;
                        Dend = Dcur;
                        eEnd = e;
                        selEnd = sel;
                    }
                    if (Dend > 0) {
                        if (e >= eEnd) {
                            const double erec = std::max(Dend / tangent(eEnd), 1e-12 * er);
                            Dcur = Dend * std::exp(-(e - eEnd) / erec);
                        } else {
                            Dcur = selEnd > 0 ? Dend * std::max(sel, 0.0) / selEnd : 0.0;
                        }
                    }
                }
            }
            double s = sel - Dcur + (tauV > 0 ? E * tauV * in_.rate[i] : 0.0);
            if (muK > 0 && in_.diameter > 0) {  // no side wall (laterally periodic): no wall friction
                if (i > 0) m = std::clamp(m + 2 * (e - ePrev) / mobil, -1.0, 1.0);
                const double u = m * 4 * muK * in_.height * (1 - e) / in_.diameter;
                const double g = std::abs(u) < 1e-8 ? 1 + 0.5 * u : u / (1 - std::exp(-u));
                s *= g;
            }
            ePrev = e;
            inner[i] = s;
        }
    }
    for (std::size_t i = 0; i < n; ++i) out[i] = inner[i] + a + b * (in_.t[i] - in_.t[0]);
}

// ---- hysteresis: the unload-reload loop below the largest strain --------------------------------

double Model::Loop::branch(double e, double L, double top, double floor) {
    // an unload from a reversal above zero force in both L and stress scales with (L/L_a)^h_u down
    // to zero force and follows L below; from any other reversal it runs parallel to L (monotone in
    // L either way); every value floored at the cohesion tension, the reversal points included
    auto value = [&](double Lq) {
        double s;
        if (!up) {
            s = (aL > 0 && aS > 0) ? (Lq > 0 ? aS * std::pow(Lq / aL, hu) : Lq) : Lq + aS - aL;
        } else {
            const double v = top > aL ? std::clamp((Lq - aL) / (top - aL), 0.0, 1.0) : 1.0;
            s = aS + (top - aS) * std::pow(v, hr);
        }
        return std::max(s, floor);
    };
    if (virgin) {  // the first sample below the largest strain: an unload from the top
        virgin = false;
        up = false;
        aL = aS = top;
        ext = e;
        extL = L;
    }
    if (up ? e >= ext : e <= ext) {  // on along the current branch
        ext = e;
        extL = L;
        return value(L);
    }
    // turned back from the extreme: the new branch, anchored where the old one was at the extreme
    // (continuous there); committed once the turn exceeds `turn`, so that strain noise in a hold does
    // not re-anchor the loop at every sample
    const double sExt = value(extL);
    const bool wasUp = up;
    const double oldL = aL, oldS = aS;
    up = !up;
    aL = extL;
    aS = sExt;
    const double s = value(L);
    if (std::abs(e - ext) > turn) {
        ext = e;
        extL = L;
    } else {
        up = wasUp;
        aL = oldL;
        aS = oldS;
    }
    return s;
}

// ---- fitting --------------------------------------------------------------------------------

namespace {

double toInternal(const ParDef& d, double v) { return d.logScale ? std::log10(v) : v / d.scale; }
double toPhysical(const ParDef& d, double u) { return d.logScale ? std::pow(10.0, u) : u * d.scale; }
double lowerInternal(const ParDef& d) { return toInternal(d, d.lo); }
double upperInternal(const ParDef& d) { return toInternal(d, d.hi); }

} // namespace

void Whitener::apply(std::vector<double>& x, const std::vector<double>& w) const {
    double xPrev = 0, ePrev = 0;
    bool prevOk = false;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!w.empty() && w[i] == 0) {
            x[i] = 0;
            prevOk = false;
            continue;
        }
        const double xi = x[i];
        const double e = prevOk ? xi - phi * xPrev + theta * ePrev : xi * startScale;
        xPrev = xi;
        ePrev = e;
        prevOk = true;
        x[i] = e;
    }
}

FitResult fitModel(const Model& model, const std::vector<double>& y, const std::vector<char>& on,
                   const std::vector<double>& p0, const FitOptions& opt) {
    const auto& defs = model.defs();
    const std::size_t n = y.size();
    const std::vector<int>& fr = opt.freeParams;
    const int k = int(fr.size());
    std::vector<double> w = opt.weights.empty() ? std::vector<double>(n, 1.0) : opt.weights;
    FitResult res;
    res.p = p0;
    for (int j : fr) res.p[j] = std::clamp(res.p[j], defs[j].lo, defs[j].hi);
    std::vector<double> mvals;
    const Whitener& wh = opt.whitener;
    const bool gls = !wh.identity();
    std::vector<double> rbuf(n);
    // weighted (whitened) residual
    auto residualOf = [&](const std::vector<double>& mv, std::vector<double>& r) {
        r.resize(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = w[i] * (y[i] - mv[i]);
        if (gls) wh.apply(r, w);
    };
    auto costOf = [&](const std::vector<double>& p, std::vector<double>& mv) {
        model.evaluate(p, on, mv);
        residualOf(mv, rbuf);
        double c = 0;
        for (double r : rbuf) c += r * r;
        return std::isfinite(c) ? c : std::numeric_limits<double>::infinity();
    };
    double cost = costOf(res.p, mvals);
    Eigen::VectorXd u(k), lo(k), hi(k);
    for (int a = 0; a < k; ++a) {
        u[a] = toInternal(defs[fr[a]], res.p[fr[a]]);
        lo[a] = lowerInternal(defs[fr[a]]);
        hi[a] = upperInternal(defs[fr[a]]);
    }
    Eigen::MatrixXd J(n, std::max(k, 1));
    std::vector<double> mp;
    auto jacobian = [&](const std::vector<double>& p, const std::vector<double>& m0) {
        for (int a = 0; a < k; ++a) {
            std::vector<double> q = p;
            double h = 1e-6 * std::max(1.0, std::abs(u[a]));
            if (u[a] + h > hi[a]) h = -h;
            q[fr[a]] = toPhysical(defs[fr[a]], u[a] + h);
            model.evaluate(q, on, mp);
            std::vector<double> col(n);
            for (std::size_t i = 0; i < n; ++i) col[i] = w[i] * (mp[i] - m0[i]) / h;
            if (gls) wh.apply(col, w);
            for (std::size_t i = 0; i < n; ++i) J(long(i), a) = col[i];
        }
    };
    double lambda = 1e-3;
    int stall = 0;
    int it = 0;
    if (k > 0) {
        for (; it < opt.maxIterations; ++it) {
            jacobian(res.p, mvals);
            residualOf(mvals, rbuf);
            Eigen::VectorXd r(n);
            for (std::size_t i = 0; i < n; ++i) r[long(i)] = rbuf[i];
            const Eigen::MatrixXd A = J.leftCols(k).transpose() * J.leftCols(k);
            const Eigen::VectorXd g = J.leftCols(k).transpose() * r;  // descent direction for +du
            bool accepted = false;
            for (int tries = 0; tries < 12 && !accepted; ++tries) {
                Eigen::MatrixXd M = A;
                for (int a = 0; a < k; ++a) M(a, a) += lambda * std::max(A(a, a), 1e-12) + 1e-14;
                const Eigen::VectorXd du = M.ldlt().solve(g);
                Eigen::VectorXd un = u + du;
                for (int a = 0; a < k; ++a) un[a] = std::clamp(un[a], lo[a], hi[a]);
                std::vector<double> q = res.p;
                for (int a = 0; a < k; ++a) q[fr[a]] = toPhysical(defs[fr[a]], un[a]);
                std::vector<double> mq;
                const double cq = costOf(q, mq);
                if (cq < cost) {
                    const double rel = (cost - cq) / std::max(cost, 1e-300);
                    u = un;
                    res.p = q;
                    mvals.swap(mq);
                    cost = cq;
                    lambda = std::max(lambda / 4, 1e-9);
                    accepted = true;
                    stall = rel < 1e-10 ? stall + 1 : 0;
                } else {
                    lambda *= 8;
                }
            }
            if (!accepted || stall >= 2) break;
        }
    }
    res.iterations = it;
    res.rss = cost;
    res.model = mvals;
    res.se.assign(defs.size(), 0.0);
    if (k > 0) {
        jacobian(res.p, mvals);
        double nw = 0;
        for (double x : w) nw += x > 0 ? 1 : 0;
        const double s2 = cost / std::max(1.0, nw - k) * opt.covInflation;
        const Eigen::MatrixXd A = J.leftCols(k).transpose() * J.leftCols(k);
        const Eigen::MatrixXd cov = A.completeOrthogonalDecomposition().pseudoInverse() * s2;
        for (int a = 0; a < k; ++a) {
            const double sdu = std::sqrt(std::max(cov(a, a), 0.0));
            const ParDef& d = defs[fr[a]];
            res.se[fr[a]] = d.logScale ? res.p[fr[a]] * std::log(10.0) * sdu : sdu * d.scale;
        }
    }
    return res;
}

// ---- noise ----------------------------------------------------------------------------------

namespace {
/// Robust variance of zero-mean differences: mean square after trimming the largest 2 % of |d|,
/// corrected for the trimming (Gaussian), so that quantised data are not biased as a MAD would be.
double trimmedVariance(std::vector<double> d) {
    if (d.empty()) return 0;
    for (double& x : d) x = x * x;
    std::sort(d.begin(), d.end());
    const std::size_t keep = std::max<std::size_t>(1, std::size_t(0.98 * double(d.size())));
    double s = 0;
    for (std::size_t i = 0; i < keep; ++i) s += d[i];
    return s / double(keep) / 0.87327;
}
} // namespace

namespace {
/// AR(1) + white noise fitted to the robust variances of lag-k differences of order `order`:
/// first differences r_i - r_{i-k}: v_k = 2 s2 (1 - rho^k) + 2 w;
/// second differences r_i - 2 r_{i-k} + r_{i-2k}: v_k = 2 s2 (3 - 4 rho^k + rho^2k) + 6 w (a linear
/// trend of the misfit cancels).
NoiseModel fitDifferenceVariances(const std::vector<double>& r, const std::vector<int>& segment, int order) {
    NoiseModel nm;
    nm.n = r.size();
    const int K = 10;
    std::vector<double> v;
    const bool useSeg = segment.size() == r.size();
    std::size_t pairs = 0;
    for (int k = 1; k <= K && std::size_t(order * k) + 4 < r.size(); ++k) {
        const std::size_t span = std::size_t(order * k), kk = std::size_t(k);
        std::vector<double> d, dAll;
        for (std::size_t i = span; i < r.size(); ++i) {
            const double x = order == 1 ? r[i] - r[i - kk] : r[i] - 2 * r[i - kk] + r[i - 2 * kk];
            dAll.push_back(x);
            if (useSeg && segment[i] >= 0 && segment[i] == segment[i - span]) d.push_back(x);
        }
        // differences spanning a protocol phase change see the model's misfit jump there, not noise
        const std::vector<double>& use = (useSeg && d.size() >= std::max<std::size_t>(30, dAll.size() / 3)) ? d : dAll;
        v.push_back(std::max(trimmedVariance(use), 1e-300));
        if (k == 1) pairs = use.size();
    }
    const double wFactor = order == 1 ? 2.0 : 6.0;
    auto g = [&](double rho, std::size_t k) {
        const double rk = std::pow(rho, double(k + 1));
        return order == 1 ? 1 - rk : 3 - 4 * rk + rk * rk;
    };
    // v_k = A g_k(rho) + B, A = 2 s2, B = wFactor w: least squares in relative error on a rho grid
    double best = std::numeric_limits<double>::infinity(), bestRho = 0, bestA = v.empty() ? 0 : v[0], bestB = 0;
    for (int gi = 0; gi <= 196; ++gi) {
        const double rho = gi * 0.005;
        double saa = 0, sab = 0, sbb = 0, say = 0, sby = 0;
        std::vector<double> gk(v.size());
        for (std::size_t k = 0; k < v.size(); ++k) {
            gk[k] = g(rho, k);
            const double wt = 1 / (v[k] * v[k]);
            saa += wt * gk[k] * gk[k]; sab += wt * gk[k]; sbb += wt;
            say += wt * gk[k] * v[k]; sby += wt * v[k];
        }
        double A, B;
        const double det = saa * sbb - sab * sab;
        A = det > 0 ? (say * sbb - sby * sab) / det : say / saa;
        B = det > 0 ? (saa * sby - sab * say) / det : 0;
        if (B < 0) { B = 0; A = say / saa; }
        if (A < 0) { A = 0; B = sby / sbb; }
        double err = 0;
        for (std::size_t k = 0; k < v.size(); ++k) {
            const double d = (v[k] - A * gk[k] - B) / v[k];
            err += d * d;
        }
        if (err < best - 1e-15) {
            best = err;
            bestRho = rho;
            bestA = A;
            bestB = B;
        }
    }
    // Keep the AR(1) part only when the difference variances show it: for white noise the
    // unconstrained fit often finds a small AR part with rho near 1 (within the sampling error of
    // v_k), which would cut n_eff several-fold. Statistic: (relative misfit of "white only" - that
    // of the full fit) * pairs; white noise (simulated, n = 2000, quantised): 99 % below 11 (first
    // differences) / 16 (second); AR(1) with rho = 0.3: above 150 / 300.
    if (!v.empty()) {
        double sw = 0, s1 = 0;
        for (double x : v) {
            sw += 1 / x;
            s1 += 1 / (x * x);
        }
        const double Bw = sw / s1;
        double errW = 0;
        for (double x : v) errW += ((x - Bw) / x) * ((x - Bw) / x);
        if ((errW - best) * double(pairs) < (order == 1 ? 20 : 30)) {
            bestRho = 0;
            bestA = 0;
            bestB = Bw;
        }
    }
    const double s2 = bestA / 2, w = bestB / wFactor;
    nm.sigma = std::sqrt(std::max(s2 + w, 1e-300));
    nm.rho = bestRho;
    nm.arVar = s2;
    nm.whiteVar = w;
    const double lowFreq = s2 * (1 + nm.rho) / (1 - nm.rho) + w;  // spectral density at zero frequency
    nm.nEff = std::max(2.0, double(nm.n) * (s2 + w) / std::max(lowFreq, 1e-300));
    return nm;
}
} // namespace

NoiseModel estimateNoise(const std::vector<double>& r, const std::vector<int>& segment) {
    // First differences are the more precise estimate for pure noise; second differences are
    // immune to a locally linear misfit (e.g. a slow relaxation the baseline lacks). Misfit can
    // only add variance, so when the second-difference estimate is clearly smaller the first one
    // is contaminated and the second is used.
    const NoiseModel n1 = fitDifferenceVariances(r, segment, 1);
    const NoiseModel n2 = fitDifferenceVariances(r, segment, 2);
    return n2.sigma < 0.8 * n1.sigma ? n2 : n1;
}

std::vector<int> noiseSegments(const std::vector<double>& t, const std::vector<double>& strain, std::size_t margin) {
    std::vector<int> seg(t.size(), -1);
    int id = 0;
    for (const auto& ph : detectPhases(t, strain)) {
        for (std::size_t i = ph.begin + margin; i + margin < ph.end; ++i) seg[i] = id;
        ++id;
    }
    return seg;
}

double NoiseModel::innovationVar() const {
    // x = a + u, a AR(1) (variance arVar, coefficient rho), u white (whiteVar): (1 - rho B) x is
    // MA(1) with lag-0 / lag-1 autocovariances g0, g1; its innovation variance is -g1/theta.
    const double g0 = arVar * (1 - rho * rho) + whiteVar * (1 + rho * rho), g1 = -rho * whiteVar;
    const double th = whitener().theta;
    return th > 1e-12 ? -g1 / th : g0;
}

Whitener NoiseModel::whitener() const {
    Whitener w;
    if (!(rho > 0) || !(arVar > 0)) return w;  // white (or no AR part): identity
    const double g0 = arVar * (1 - rho * rho) + whiteVar * (1 + rho * rho), g1 = -rho * whiteVar;
    const double c = g0 > 0 ? -g1 / g0 : 0;  // = theta / (1 + theta^2), in [0, 0.5)
    w.phi = rho;
    w.theta = c > 1e-12 ? (1 - std::sqrt(std::max(0.0, 1 - 4 * c * c))) / (2 * c) : 0.0;
    const double sInn = c > 1e-12 ? -g1 / w.theta : g0;
    w.startScale = std::sqrt(sInn / std::max(arVar + whiteVar, 1e-300));
    return w;
}

double normalUpperTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

double blockChiSquarePValue(const std::vector<double>& r, const NoiseModel& nm, int dofRemoved, double* stat,
                            int* blocksOut) {
    const std::size_t n = r.size();
    const double rho = nm.rho;
    const double corr = double(n) / nm.nEff;
    std::size_t L = std::max<std::size_t>({20, std::size_t(std::ceil(10 * corr)), n / 100});
    L = std::min(L, std::max<std::size_t>(1, n / 5));
    const std::size_t B = n / L;
    const double Ld = double(L);
    const double varMean = nm.arVar / Ld * ((1 + rho) / (1 - rho) - 2 * rho * (1 - std::pow(rho, Ld)) / (Ld * (1 - rho) * (1 - rho))) +
                           nm.whiteVar / Ld;
    double T = 0;
    for (std::size_t b = 0; b < B; ++b) {
        double s = 0;
        for (std::size_t i = b * L; i < (b + 1) * L; ++i) s += r[i];
        const double m = s / Ld;
        T += m * m / std::max(varMean, 1e-300);
    }
    const double k = std::max(1.0, double(B) - dofRemoved);
    if (stat) *stat = T;
    if (blocksOut) *blocksOut = int(B);
    // Wilson-Hilferty: (T/k)^(1/3) ~ N(1 - 2/(9k), 2/(9k))
    const double z = (std::cbrt(T / k) - (1 - 2 / (9 * k))) / std::sqrt(2 / (9 * k));
    return normalUpperTail(z);
}

} // namespace pdpm::explain
