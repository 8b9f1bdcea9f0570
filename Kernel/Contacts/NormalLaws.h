// Normal force parts of contact laws. Each part has: H (number of history doubles it owns),
// validate(), stiffness() (for the time step) and apply(). See Documentation/contact-laws.md.
#pragma once
#include <cmath>
#include <limits>
#include <string>

#include "Contacts/ContactParameters.h"
#include "Contacts/ContactState.h"
#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

namespace detail {
inline void requirePositive(double v, const std::string& what, const std::string& who) {
    if (!(v > 0) || !std::isfinite(v)) inputError(who + ": " + what + " must be > 0 (got " + fmt(v) + ")");
}
inline void requireNonNegative(double v, const std::string& what, const std::string& who) {
    if (!(v >= 0) || !std::isfinite(v)) inputError(who + ": " + what + " must be >= 0 (got " + fmt(v) + ")");
}
} // namespace detail

/// Linear visco-elastic normal force, Eq. (2.1): f = k delta + gamma d(delta)/dt.
/// The force is not clipped when the dashpot makes it attractive at the end of a contact.
struct NormalLinear {
    static constexpr int H = 0;
    static constexpr bool kNeedsMass = false, kNeedsRadius = false;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requirePositive(p.k, "stiffness k", who);
        detail::requireNonNegative(p.gamma, "normal damping gamma", who);
    }
    static double stiffness(const ContactParameters& p, double /*rEff*/) { return p.k; }
    static double damping(const ContactParameters& p) { return p.gamma; }
    static void apply(const ContactParameters& p, const ContactState& s, double* /*h*/, ContactOutput& o) {
        o.fn = p.k * s.overlap + p.gamma * s.overlapRate;
        o.fnFriction = o.fn > 0 ? o.fn : 0.0;
        o.energy = 0.5 * p.k * s.overlap * s.overlap;
    }
};

/// Hertz normal force f = 4/3 E* sqrt(R*) delta^{3/2} with the Tsuji-type dashpot
/// f_d = 2 sqrt(5/6) beta sqrt(S_n m*) d(delta)/dt, S_n = 2 E* sqrt(R* delta),
/// beta = -ln e / sqrt(ln^2 e + pi^2).
struct NormalHertz {
    static constexpr int H = 0;
    static constexpr bool kNeedsMass = true, kNeedsRadius = true;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requirePositive(p.youngEff, "effective Young's modulus", who);
        if (!(p.restitution > 0 && p.restitution <= 1)) inputError(who + ": restitution must be in (0, 1]");
    }
    /// Tangent stiffness at a reference overlap of 1 % of the reduced radius (for the time step).
    static double stiffness(const ContactParameters& p, double rEff) {
        return 2 * p.youngEff * std::sqrt(rEff * 0.01 * rEff);
    }
    static double damping(const ContactParameters&) { return 0.0; }
    static double beta(double e) {
        const double l = std::log(e);
        return -l / std::sqrt(l * l + M_PI * M_PI);
    }
    static void apply(const ContactParameters& p, const ContactState& s, double* /*h*/, ContactOutput& o) {
        const double sqrtRd = std::sqrt(s.rEff * s.overlap);
        const double fel = 4.0 / 3.0 * p.youngEff * sqrtRd * s.overlap;
        const double sn = 2 * p.youngEff * sqrtRd;
        const double gd = 2 * std::sqrt(5.0 / 6.0) * beta(p.restitution) * std::sqrt(sn * s.mEff);
        o.fn = fel + gd * s.overlapRate;
        o.fnFriction = o.fn > 0 ? o.fn : 0.0;
        o.energy = 0.4 * fel * s.overlap;  // 8/15 E* sqrt(R) delta^{5/2}
    }
};

/// Luding's linear hysteretic plastic-adhesive normal force, Eqs. (5.5)-(5.7), plus a dashpot.
/// History: h[0] = delta_max. k (= k2-hat) is the maximal unloading stiffness.
struct NormalLuding {
    static constexpr int H = 1;
    static constexpr bool kNeedsMass = false, kNeedsRadius = true;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requirePositive(p.k, "maximal unloading stiffness k2 (k)", who);
        detail::requirePositive(p.k1, "loading stiffness k1", who);
        if (p.k1 > p.k) inputError(who + ": k1 > k2 (loading stiffness k1 must not exceed k2 = k)");
        detail::requireNonNegative(p.kc, "adhesive stiffness kc", who);
        detail::requireNonNegative(p.gamma, "normal damping gamma", who);
        if (!(p.phiF >= 0 && p.phiF <= 1)) inputError(who + ": plasticity depth phi_f must be in [0, 1]");
    }
    static double stiffness(const ContactParameters& p, double) { return p.k; }
    static double damping(const ContactParameters& p) { return p.gamma; }

    /// Plastic flow limit overlap, Eq. (5.6), with 2 a1 a2/(a1+a2) = 2 rEff.
    static double deltaMaxStar(const ContactParameters& p, double rEff) {
        if (p.k <= p.k1) return 0.0;  // k2 == k1: no interpolation needed
        return p.k / (p.k - p.k1) * p.phiF * 2 * rEff;
    }
    /// Unloading stiffness k2(delta_max), Eq. (5.7).
    static double k2(const ContactParameters& p, double rEff, double deltaMax) {
        const double dStar = deltaMaxStar(p, rEff);
        if (deltaMax >= dStar) return p.k;
        return p.k1 + (p.k - p.k1) * deltaMax / dStar;
    }
    /// The hysteretic force for overlap delta with history delta_max (already updated), Eq. (5.5).
    static double hysteresisForce(const ContactParameters& p, double rEff, double delta, double deltaMax) {
        const double k2v = k2(p, rEff, deltaMax);
        const double delta0 = (1 - p.k1 / k2v) * deltaMax;
        double f = k2v * (delta - delta0);
        if (f >= p.k1 * delta) f = p.k1 * delta;
        if (f <= -p.kc * delta) f = -p.kc * delta;
        return f;
    }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        if (s.overlap > h[0]) h[0] = s.overlap;
        const double dmax = h[0];
        const double k2v = k2(p, s.rEff, dmax);
        const double delta0 = (1 - p.k1 / k2v) * dmax;
        const double fh = hysteresisForce(p, s.rEff, s.overlap, dmax);
        o.fn = fh + p.gamma * s.overlapRate;
        const double fr = fh + p.kc * s.overlap;  // friction acts on the adhesion-shifted load
        o.fnFriction = fr > 0 ? fr : 0.0;
        // Energy recoverable by unloading along k2 to delta0 (repulsive part only; documented choice).
        const double e = s.overlap - delta0;
        o.energy = e > 0 ? 0.5 * k2v * e * e : 0.0;
    }
};

} // namespace pdpm
