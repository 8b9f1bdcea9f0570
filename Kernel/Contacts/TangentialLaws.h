// Tangential (sliding friction) parts of contact laws.
#pragma once
#include <cmath>
#include <string>

#include "Contacts/NormalLaws.h"

namespace pdpm {

namespace detail {
/// Rotate a spring vector into the tangent plane of n, keeping its length.
inline void projectKeepingLength(Vec3& xi, const Vec3& n) {
    const double len2 = norm2(xi);
    if (len2 == 0) return;
    xi -= dot(xi, n) * n;
    const double newLen2 = norm2(xi);
    if (newLen2 > 0) xi *= std::sqrt(len2 / newLen2);
}

/// Spring-dashpot with a Coulomb-type cap, shared by sliding and rolling friction.
/// h[0..2] spring, h[3] = 1 while at the limit (then the dynamic coefficient applies).
/// kFlag = false: no h[3]; for muS == muD, where the flag changes nothing (the same arithmetic).
/// Returns the force; sets `capped`.
template <bool kFlag = true>
inline Vec3 cappedSpring(double* h, const Vec3& n, const Vec3& vel, double k, double g, double muS,
                         double muD, double load, double dt, bool& capped) {
    Vec3 xi{h[0], h[1], h[2]};
    projectKeepingLength(xi, n);
    xi += vel * dt;
    Vec3 f = -k * xi - g * vel;
    double limit = muS * load;
    if constexpr (kFlag) limit = (h[3] != 0 ? muD : muS) * load;
    const double f2 = norm2(f);
    capped = f2 > limit * limit;
    if (capped) {
        const double fm = std::sqrt(f2);
        f *= muD * load / fm;
        if (k > 0) xi = -(f + g * vel) / k;
        if constexpr (kFlag) h[3] = 1;
    } else {
        if constexpr (kFlag) h[3] = 0;
    }
    h[0] = xi.x; h[1] = xi.y; h[2] = xi.z;
    return f;
}
} // namespace detail

/// No part (frictionless, no rolling, ...).
struct NoPart {
    static constexpr int H = 0;
    static constexpr bool kNeedsMass = false, kNeedsRadius = false;
    static void validate(const ContactParameters&, const std::string&) {}
    static double stiffness(const ContactParameters&, double) { return 0; }
    static void apply(const ContactParameters&, const ContactState&, double*, ContactOutput&) {}
};

/// Linear tangential spring k_t + dashpot gamma_t with Coulomb sliding (static mu_s, dynamic mu_d).
/// History: spring (3) + sliding flag (1). The spring is rotated into the current tangent plane every
/// step and capped at the Coulomb limit.
struct TangentialCoulomb {
    static constexpr int H = 4;
    static constexpr bool kNeedsMass = false, kNeedsRadius = false;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requireNonNegative(p.kt, "tangential stiffness kt", who);
        detail::requireNonNegative(p.gammaT, "tangential damping gammaT", who);
        detail::requireNonNegative(p.muS, "static friction mu_s", who);
        detail::requireNonNegative(p.muD, "dynamic friction mu_d", who);
        if (p.muD > p.muS) inputError(who + ": dynamic friction mu_d must not exceed static mu_s");
    }
    static double stiffness(const ContactParameters& p, double) { return p.kt; }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        o.ft = detail::cappedSpring(h, s.n, s.vt, p.kt, p.gammaT, p.muS, p.muD, o.fnFriction, s.dt, o.sliding);
        o.energy += 0.5 * p.kt * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    }
};

/// TangentialCoulomb for a species table in which every pair has mu_s = mu_d: the sliding flag then
/// selects between two equal coefficients, so it is not stored (history: spring (3), 8 B per pair
/// less) and the forces are bitwise those of TangentialCoulomb. Never chosen by name: ComposedLaw::
/// specialised() swaps it in for TangentialCoulomb (and back) when the species table allows.
struct TangentialCoulombOneMu {
    static constexpr int H = 3;
    static constexpr bool kNeedsMass = false, kNeedsRadius = false;
    static void validate(const ContactParameters& p, const std::string& who) {
        TangentialCoulomb::validate(p, who);
        if (p.muD != p.muS) inputError(who + ": the one-coefficient friction part needs mu_d = mu_s");
    }
    static double stiffness(const ContactParameters& p, double) { return p.kt; }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        o.ft = detail::cappedSpring<false>(h, s.n, s.vt, p.kt, p.gammaT, p.muS, p.muD, o.fnFriction, s.dt, o.sliding);
        o.energy += 0.5 * p.kt * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    }
};

/// Mindlin no-slip tangential stiffness for the Hertz family: k_t = 8 G* sqrt(R* delta), Tsuji damping
/// 2 sqrt(5/6) beta sqrt(k_t m*), Coulomb cap. History as TangentialCoulomb.
struct TangentialMindlin {
    static constexpr int H = 4;
    static constexpr bool kNeedsMass = true, kNeedsRadius = true;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requirePositive(p.shearEff, "effective shear modulus G*", who);
        detail::requireNonNegative(p.muS, "static friction mu_s", who);
        detail::requireNonNegative(p.muD, "dynamic friction mu_d", who);
        if (p.muD > p.muS) inputError(who + ": dynamic friction mu_d must not exceed static mu_s");
    }
    static double stiffness(const ContactParameters& p, double rEff) {
        return 8 * p.shearEff * std::sqrt(rEff * 0.01 * rEff);
    }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        const double kt = 8 * p.shearEff * std::sqrt(s.rEff * s.overlap);
        const double gt = 2 * std::sqrt(5.0 / 6.0) * NormalHertz::beta(p.restitution) * std::sqrt(kt * s.mEff);
        o.ft = detail::cappedSpring(h, s.n, s.vt, kt, gt, p.muS, p.muD, o.fnFriction, s.dt, o.sliding);
        o.energy += 0.5 * kt * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    }
};

/// Rolling resistance (Luding 2008): rolling velocity v_r = -R* n x (w_i - w_j); spring k_r, dashpot
/// gamma_r, limit mu_r f_n. Torque on i: R* n x f_r. History: spring (3) + limit flag (1).
struct RollingResistance {
    static constexpr int H = 4;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requireNonNegative(p.kr, "rolling stiffness kr", who);
        detail::requireNonNegative(p.gammaR, "rolling damping gammaR", who);
        detail::requireNonNegative(p.muR, "rolling friction mu_r", who);
    }
    static double stiffness(const ContactParameters& p, double) { return p.kr; }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        const Vec3 vr = -s.rEff * cross(s.n, s.wRel);
        bool capped = false;
        const Vec3 fr = detail::cappedSpring(h, s.n, vr, p.kr, p.gammaR, p.muR, p.muR, o.fnFriction, s.dt, capped);
        o.torqueRT += s.rEff * cross(s.n, fr);
        o.energy += 0.5 * p.kr * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    }
};

/// Torsion resistance: v_o = R* ((w_i - w_j).n), spring k_o, dashpot gamma_o, limit mu_o f_n.
/// Torque on i: R* f_o n. History: spring (1).
struct TorsionResistance {
    static constexpr int H = 1;
    static void validate(const ContactParameters& p, const std::string& who) {
        detail::requireNonNegative(p.ko, "torsion stiffness ko", who);
        detail::requireNonNegative(p.gammaO, "torsion damping gammaO", who);
        detail::requireNonNegative(p.muO, "torsion friction mu_o", who);
    }
    static double stiffness(const ContactParameters& p, double) { return p.ko; }
    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        const double vo = s.rEff * dot(s.wRel, s.n);
        double xi = h[0] + vo * s.dt;
        double f = -p.ko * xi - p.gammaO * vo;
        const double limit = p.muO * o.fnFriction;
        if (std::fabs(f) > limit) {
            f = f > 0 ? limit : -limit;
            if (p.ko > 0) xi = -(f + p.gammaO * vo) / p.ko;
        }
        h[0] = xi;
        o.torqueRT += (s.rEff * f) * s.n;
        o.energy += 0.5 * p.ko * xi * xi;
    }
};

} // namespace pdpm
