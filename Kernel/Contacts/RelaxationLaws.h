// Time-dependent contact relaxation (thesis chapter 4, Eq. 4.1): a wrapper around a normal part
// that makes the force of a contact held at constant overlap decay as
//
//     df/dt = -C f / (t0 + t)      =>     f(t) = f_max (1 + t/t0)^(-C)         (Eqs. 4.1-4.3)
//
// realised through a slowly growing plastic (relaxed) overlap delta_p: the base law is evaluated at
// the elastic overlap delta_e = delta - delta_p, so on later loading and unloading the force stays a
// function of the geometry (the relaxed contact is softer by the amount it has crept).
//
// The clock t (lab seconds) of each contact measures the time since the contact's LAST LOAD
// INCREASE: whenever the unrelaxed (trial) elastic force f_new exceeds (by more than a relative 1e-12,
// against round-off) the largest force f_ref reached since the last reset, f_ref is raised to it and
// t restarts at 0; no relaxation happens in that step. With a clock memory m = relaxMemory > 0 the
// restart is partial: t <- (t + dt * relaxTimeScale) * (f_ref/f_new)^(1/m), so over a reload from f_a
// to f_b the clock shrinks by (f_a/f_b)^(1/m) in all (the per-step factors telescope): an aged
// contact reloaded by a small fraction stays old and relaxes slowly (m -> 0: full restart, the
// default; m -> infinity: pure ageing, the clock never restarts).
// Otherwise t advances by dt * relaxTimeScale (relaxTimeScale = lab seconds per DEM second) and the
// elastic force is multiplied by the exact factor ((t0 + t_new)/(t0 + t_old))^(-C), so a
// held contact follows Eq. (4.3) exactly (the product telescopes). Only repulsive elastic forces
// relax; adhesive (negative) forces are left alone. The clock, delta_p, f_ref and the work done by
// relaxation are part of the contact history (restart files round-trip them).
//
// History layout: Base::H doubles of the base law, then
//   [0] delta_p   plastic (relaxed) overlap (m)
//   [1] t         clock: lab seconds since the last load increase
//   [2] f_ref     largest trial elastic force since the last reset (N)
//   [3] W_relax   energy dissipated by relaxation so far, sum of (f_old+f_new)/2 * d(delta_p) (J)
// Documentation/contact-laws.md ("Time-dependent relaxation") has the equations.
#pragma once
#include <cmath>
#include <string>

#include "Contacts/NormalLaws.h"

namespace pdpm {

/// Elastic overlap at which a base normal law gives the (repulsive) elastic force `f` without
/// dashpot, on the branch selected by the base history `h` (already updated by the last apply()).
/// The primary template solves by bisection on [0, deHi]; the laws of NormalLaws.h invert exactly.
template <class Base>
struct RelaxInverse {
    static double overlapFor(const ContactParameters& p, const ContactState& s, const double* h, double f, double deHi) {
        double lo = 0, hi = deHi;
        double hb[Base::H > 0 ? Base::H : 1];
        for (int it = 0; it < 100; ++it) {
            const double mid = 0.5 * (lo + hi);
            for (int q = 0; q < Base::H; ++q) hb[q] = h[q];
            ContactState s2 = s;
            s2.overlap = mid;
            s2.overlapRate = 0;
            ContactOutput o;
            Base::apply(p, s2, hb, o);
            (o.fn < f ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }
};

template <>
struct RelaxInverse<NormalLinear> {
    static double overlapFor(const ContactParameters& p, const ContactState&, const double*, double f, double) {
        return f / p.k;
    }
};

template <>
struct RelaxInverse<NormalHertz> {
    static double overlapFor(const ContactParameters& p, const ContactState& s, const double*, double f, double) {
        // f = 4/3 E* sqrt(R*) delta^{3/2}
        return std::cbrt(std::pow(f / (4.0 / 3.0 * p.youngEff * std::sqrt(s.rEff)), 2.0));
    }
};

template <>
struct RelaxInverse<NormalLuding> {
    /// Relaxation lowers the force below the loading branch, so the contact is on the unloading
    /// branch f = k2 (delta - delta0) of its current delta_max.
    static double overlapFor(const ContactParameters& p, const ContactState& s, const double* h, double f, double) {
        const double dmax = h[0];
        const double k2v = NormalLuding::k2(p, s.rEff, dmax);
        const double delta0 = (1 - p.k1 / k2v) * dmax;
        return delta0 + f / k2v;
    }
};

/// Normal part `Base` with the slow relaxation of Eq. (4.1). Parameters: relaxC (C >= 0, 0 = off),
/// relaxT0 (t0 > 0, lab seconds), relaxTimeScale (lab seconds per DEM second, >= 0).
template <class Base>
struct Relaxing {
    static constexpr int HB = Base::H;
    static constexpr int H = Base::H + 4;
    static constexpr bool kNeedsMass = Base::kNeedsMass, kNeedsRadius = Base::kNeedsRadius;

    static void validate(const ContactParameters& p, const std::string& who) {
        Base::validate(p, who);
        detail::requireNonNegative(p.relaxC, "relaxation exponent C (relaxC)", who);
        detail::requirePositive(p.relaxT0, "relaxation time t0 (relaxT0)", who);
        detail::requireNonNegative(p.relaxTimeScale, "relaxation time scale (relaxTimeScale)", who);
        detail::requireNonNegative(p.relaxMemory, "relaxation clock memory (relaxMemory)", who);
    }
    static double stiffness(const ContactParameters& p, double rEff) { return Base::stiffness(p, rEff); }
    static double damping(const ContactParameters& p) { return Base::damping(p); }

    /// Factor ((t0 + t + dtau)/(t0 + t))^(-C), computed without cancellation.
    static double decayFactor(double C, double t0, double t, double dtau) {
        return std::exp(-C * std::log1p(dtau / (t0 + t)));
    }

    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        double* r = h + HB;
        const double dp = r[0];
        const double de = s.overlap - dp;
        if (!(de > 0)) {  // unloaded beyond the relaxed state: no force (history kept while touching)
            o.fn = 0;
            o.fnFriction = 0;
            o.energy = 0;
            return;
        }
        ContactState se = s;
        se.overlap = de;
        if (!(p.relaxC > 0)) {
            Base::apply(p, se, h, o);
            return;
        }
        // Trial: elastic force at the unrelaxed elastic overlap (updates the base history).
        se.overlapRate = 0;
        ContactOutput trial;
        Base::apply(p, se, h, trial);
        const double fTrial = trial.fn;
        const double dtau = s.dt * p.relaxTimeScale;
        if (fTrial > 0 && fTrial > r[2] * (1 + 1e-12)) {  // load increase: restart (m = 0) or shorten the clock
            r[1] = p.relaxMemory > 0 && r[2] > 0 ? (r[1] + dtau) * std::pow(r[2] / fTrial, 1 / p.relaxMemory) : 0;
            r[2] = fTrial;
        } else if (fTrial > 0 && dtau > 0) {  // relax the elastic force exactly over this step
            const double fNew = fTrial * decayFactor(p.relaxC, p.relaxT0, r[1], dtau);
            double deNew = RelaxInverse<Base>::overlapFor(p, se, h, fNew, de);
            if (deNew > de) deNew = de;
            if (deNew < 0) deNew = 0;
            const double dpNew = s.overlap - deNew;
            r[3] += 0.5 * (fTrial + fNew) * (dpNew - dp);
            r[0] = dpNew;
            r[1] += dtau;
            se.overlap = deNew;
        } else {
            r[1] += dtau;
        }
        se.overlapRate = s.overlapRate;
        Base::apply(p, se, h, o);
    }
};

} // namespace pdpm
