#include "LateralChannel.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "Explain.h"
#include "ExplainData.h"

namespace pdpm::explain {

namespace {

/// Through-origin least-squares slope of y on x over the pairs, with its standard error: residual
/// variance over sum x^2, inflated by n / n_eff for the residuals' lag-1 autocorrelation (between
/// consecutive pairs only when `adjacent` says they are neighbouring samples).
void originSlope(const std::vector<double>& x, const std::vector<double>& y, const std::vector<char>& adjacent, double& slope,
                 double& se) {
    double sxy = 0, sxx = 0;
    for (std::size_t k = 0; k < x.size(); ++k) sxy += x[k] * y[k], sxx += x[k] * x[k];
    slope = sxx > 0 ? sxy / sxx : -1;
    se = -1;
    const std::size_t n = x.size();
    if (!(sxx > 0) || n < 3) return;
    double ss = 0, s01 = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const double r = y[k] - slope * x[k];
        ss += r * r;
        if (k > 0 && adjacent[k]) s01 += r * (y[k - 1] - slope * x[k - 1]);
    }
    const double rho = ss > 0 ? std::clamp(s01 / ss, 0.0, 0.99) : 0.0;
    const double nEff = std::max(2.0, static_cast<double>(n) * (1 - rho) / (1 + rho));
    se = std::sqrt(ss / static_cast<double>(n - 1) / sxx * static_cast<double>(n) / nEff);
}

double asinDeg(double x) { return x > 0 && x < 1 ? std::asin(x) * 180 / std::numbers::pi : -1; }

} // namespace

LateralSummary summariseLateral(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                const std::vector<double>& lateral) {
    LateralSummary L;
    const std::size_t n = s.size();
    if (lateral.size() != n || e.size() != n || t.size() != n || n < 5) return L;
    const std::vector<PhaseSegment> phases = detectPhases(t, e);
    std::vector<Phase> phase(n, Phase::Hold);
    for (const PhaseSegment& seg : phases)
        for (std::size_t i = seg.begin; i < seg.end && i < n; ++i) phase[i] = seg.phase;
    double top = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (std::isfinite(s[i])) top = std::max(top, s[i]);
    if (!(top > 0)) return L;
    // virgin loading: the Load phases, where the strain (the control channel, not the noisy stress)
    // passes its largest value so far (detectPhases calls a loading below it a reload)
    std::vector<double> xs, ys;
    std::vector<char> adj;
    std::size_t last = n;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(s[i]) || !std::isfinite(lateral[i])) continue;
        if (phase[i] == Phase::Load && s[i] >= 0.3 * top) {
            xs.push_back(s[i]), ys.push_back(lateral[i]), adj.push_back(last + 1 == i);
            last = i;
        }
    }
    L.loadingSamples = static_cast<int>(xs.size());
    if (xs.size() < 5) return L;
    originSlope(xs, ys, adj, L.k0, L.k0Se);
    if (!(L.k0 > 0)) return L;
    L.present = true;
    L.phiJakyDeg = asinDeg(1 - L.k0);
    // unloading: ln(K0 / K0_NC) against ln(OCR)
    xs.clear(), ys.clear(), adj.clear();
    double sMax = 0;
    last = n;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(s[i]) || !std::isfinite(lateral[i])) continue;
        sMax = std::max(sMax, s[i]);
        if (phase[i] != Phase::Unload || !(s[i] >= 0.05 * sMax) || !(lateral[i] > 0)) continue;
        const double ocr = sMax / s[i];
        if (ocr < 1.02) continue;
        xs.push_back(std::log(ocr)), ys.push_back(std::log(lateral[i] / (L.k0 * s[i]))), adj.push_back(last + 1 == i);
        last = i;
        L.ocrMax = std::max(L.ocrMax, ocr);
    }
    L.unloadSamples = static_cast<int>(xs.size());
    if (xs.size() >= 5) {
        originSlope(xs, ys, adj, L.m, L.mSe);
        L.phiUnloadDeg = asinDeg(L.m);
    }
    return L;
}

Json lateralJson(const LateralSummary& L) {
    Json o = Json::object();
    o.set("usable", L.present);
    o.set("virgin_loading_samples", L.loadingSamples);
    if (!L.present) return o;
    o.set("k0_virgin_loading", L.k0);
    o.set("k0_virgin_loading_se", L.k0Se >= 0 ? Json(L.k0Se) : Json());
    o.set("friction_angle_jaky_deg", L.phiJakyDeg >= 0 ? Json(L.phiJakyDeg) : Json());
    o.set("unload_samples", L.unloadSamples);
    o.set("unload_ocr_exponent", L.unloadSamples >= 5 ? Json(L.m) : Json());
    o.set("unload_ocr_exponent_se", L.mSe >= 0 ? Json(L.mSe) : Json());
    o.set("unload_ocr_max", L.unloadSamples > 0 ? Json(L.ocrMax) : Json());
    o.set("friction_angle_unloading_deg", L.phiUnloadDeg >= 0 ? Json(L.phiUnloadDeg) : Json());
    o.set("modelled", false);
    o.set("definition",
          "K0: lateral / axial stress on virgin loading (Jaky: 1 - sin phi); unloading: K0 = K0_NC OCR^m (Mayne & Kulhawy: m ~ sin phi)");
    return o;
}

std::string lateralWords(const LateralSummary& L) {
    if (!L.present) {
        if (L.loadingSamples == 0) return "";
        return "Lateral stress: recorded, but fewer than 5 samples on virgin loading above 30 % of the top stress, so no K0 is given.\n\n";
    }
    std::string w = "Lateral stress (summarised, not modelled: the mechanisms act on the axial stress, so rolling_resistance stays untestable): "
                    "on virgin loading the lateral stress is K0 = " + num(L.k0, 3);
    if (L.k0Se >= 0) w += " +- " + num(2 * L.k0Se, 2);
    w += " times the axial stress";
    if (L.phiJakyDeg >= 0) w += " (Jaky's K0 = 1 - sin phi: phi = " + num(L.phiJakyDeg, 3) + " deg)";
    w += ".";
    if (L.unloadSamples >= 5) {
        w += " On unloading K0 grows with the overconsolidation ratio as OCR^" + num(L.m, 3);
        if (L.mSe >= 0) w += " +- " + num(2 * L.mSe, 2);
        w += " (up to OCR " + num(L.ocrMax, 3) + "; Mayne and Kulhawy's empirical correlation, exponent about sin phi";
        if (L.phiUnloadDeg >= 0) w += ", gives phi = " + num(L.phiUnloadDeg, 3) + " deg";
        w += ").";
        if (L.phiJakyDeg >= 0 && L.phiUnloadDeg >= 0) {
            const double d = std::abs(L.phiJakyDeg - L.phiUnloadDeg);
            w += d <= 5 ? " The two friction angles are within " + num(d, 2) +
                              " deg of each other: the lateral stress is consistent with one friction angle, as for a frictional "
                              "(Coulomb) granular material."
                        : " The two friction angles are " + num(d, 2) +
                              " deg apart: one friction angle does not describe both branches. Both relations are empirical "
                              "and scatter between materials, so this is a pointer, not a test: physics acting on the lateral "
                              "stress (rolling resistance, cohesion, a stress-dependent friction) could cause it.";
        }
    } else {
        w += " The recording has no unloading with enough samples for the overconsolidation exponent.";
    }
    return w + "\n\n";
}

} // namespace pdpm::explain
