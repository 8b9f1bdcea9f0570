#include "HoldFits.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Fitting.h"

namespace pdpm::explain {

namespace {

// Eq. 4.3 for one hold, parameters {sigma_h, C, ln t0}.
double holdModel(double dt, const std::vector<double>& p) { return p[0] * std::pow(1 + dt / std::exp(p[2]), -p[1]); }

HoldFit fitOne(const Recording& rec, std::size_t b, std::size_t e, double widen) {
    HoldFit h;
    h.tStart = rec.t[b];
    h.tEnd = rec.t[e - 1];
    h.samples = e - b;
    std::vector<double> y(rec.stress.begin() + long(b), rec.stress.begin() + long(e)), dt(e - b);
    for (std::size_t i = b; i < e; ++i) dt[i - b] = rec.t[i] - rec.t[b];
    const auto f = [&](std::size_t i, const std::vector<double>& p) { return holdModel(dt[i], p); };
    // start: C from the log-log slope between the middle and the end of the hold, several t0
    const std::size_t n = y.size(), mid = n / 2;
    double c0 = 0.03;
    if (y[mid] > 0 && y[n - 1] > 0 && dt[n - 1] > dt[mid] && dt[mid] > 0)
        c0 = std::clamp(-std::log(y[n - 1] / y[mid]) / std::log(dt[n - 1] / dt[mid]), 1e-4, 2.0);
    pdpm::FitResult best;
    best.rss = std::numeric_limits<double>::infinity();
    const double span = std::max(dt[n - 1], 1e-9);
    for (double t0 : {1e-3 * span, 1e-2 * span, 1e-1 * span}) {
        try {
            auto r = pdpm::levenbergMarquardt(y, f, {"sigma_h", "C", "ln_t0"}, {y[0], c0, std::log(t0)}, {}, 200);
            if (std::isfinite(r.rss) && r.rss < best.rss) best = r;
        } catch (const std::exception&) {
            // a start the model cannot evaluate: try the next one
        }
    }
    if (!std::isfinite(best.rss)) return h;
    h.stressStart = best.value[0];
    h.C = best.value[1];
    h.cLo = h.C - 1.96 * widen * best.stderror[1];
    h.cHi = h.C + 1.96 * widen * best.stderror[1];
    h.t0 = std::exp(best.value[2]);
    h.t0Lo = std::exp(best.value[2] - 1.96 * widen * best.stderror[2]);
    h.t0Hi = std::exp(best.value[2] + 1.96 * widen * best.stderror[2]);
    h.rmse = best.rms;
    return h;
}

} // namespace

HoldFitSummary fitHolds(const Recording& rec, double rho, std::size_t minSamples, const std::vector<char>& creep) {
    HoldFitSummary s;
    rho = std::clamp(rho, 0.0, 0.99);
    const double widen = std::sqrt((1 + rho) / (1 - rho));  // AR(1): variance of a mean grows by this factor
    std::size_t lastBegin = 0, lastEnd = std::size_t(-1);
    double lastStrain = 0;
    bool lastKept = false;
    for (const auto& ph : detectPhases(rec.t, rec.strain))
        if (ph.phase == Phase::Hold && ph.end - ph.begin >= minSamples &&
            !(creep.size() == rec.size() && creep[ph.begin + (ph.end - ph.begin) / 2])) {
            // the run of equal strain around the hold's middle (holdExtent): t0 depends on the start, C does not
            const PhaseSegment ext = holdExtent(rec.strain, ph);
            std::size_t b = ext.begin;
            const std::size_t e = ext.end;
            const double eh = rec.strain[ph.begin + (ph.end - ph.begin) / 2];
            // one hold split in two by the detector (same strain, contiguous): fitted once, as a whole
            if (lastEnd != std::size_t(-1) && atHoldStrain(lastStrain, eh) && b <= lastEnd + holdReach(rec.size())) {
                b = lastBegin;
                if (lastKept) s.holds.pop_back();
            }
            HoldFit h = fitOne(rec, b, e, widen);
            lastBegin = b;
            lastEnd = e;
            lastStrain = eh;
            lastKept = std::isfinite(h.C) && std::isfinite(h.stressStart) && h.C > 0 && h.stressStart > 0;
            if (lastKept) s.holds.push_back(h);
        }
    s.beta = s.betaSe = std::numeric_limits<double>::quiet_NaN();
    if (s.holds.empty()) return s;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, sumC = 0;
    const double m = double(s.holds.size());
    for (const auto& h : s.holds) {
        const double x = std::log(h.stressStart), yv = std::log(h.C);
        sx += x;
        sy += yv;
        sxx += x * x;
        sxy += x * yv;
        sumC += h.C;
    }
    s.meanC = sumC / m;
    const double den = m * sxx - sx * sx;
    if (s.holds.size() >= 3 && den > 0) {
        const double slope = (m * sxy - sx * sy) / den, icpt = (sy - slope * sx) / m;
        double rss = 0;
        for (const auto& h : s.holds) {
            const double r = std::log(h.C) - (icpt + slope * std::log(h.stressStart));
            rss += r * r;
        }
        s.beta = -slope;
        s.betaSe = std::sqrt(rss / (m - 2) * m / den);
    }
    return s;
}

namespace {
Json finiteOrNull(double x) { return std::isfinite(x) ? Json(x) : Json(); }
} // namespace

Json holdFitsJson(const HoldFitSummary& s) {
    Json a = Json::array();
    for (const auto& h : s.holds) {
        Json o = Json::object();
        o.set("t_start_s", h.tStart);
        o.set("t_end_s", h.tEnd);
        o.set("samples", double(h.samples));
        o.set("stress_start_Pa", finiteOrNull(h.stressStart));
        o.set("C", finiteOrNull(h.C));
        o.set("C_ci95", Json::array({finiteOrNull(h.cLo), finiteOrNull(h.cHi)}));
        o.set("t0_s", finiteOrNull(h.t0));
        o.set("t0_ci95", Json::array({finiteOrNull(h.t0Lo), finiteOrNull(h.t0Hi)}));
        o.set("rmse_Pa", finiteOrNull(h.rmse));
        a.push(o);
    }
    Json j = Json::object();
    j.set("method", "thesis Eq. 4.3 fitted to each hold separately (sigma_h, C, t0 free; raw recorded stress)");
    j.set("holds", a);
    j.set("mean_C", s.holds.empty() ? Json() : finiteOrNull(s.meanC));
    const bool trend = std::isfinite(s.beta) && std::isfinite(s.betaSe);
    j.set("C_stress_exponent", trend ? Json(s.beta) : Json());
    j.set("C_stress_exponent_se", trend ? Json(s.betaSe) : Json());
    return j;
}

} // namespace pdpm::explain
