// Contact viscosity on the lab clock: a wrapper around a normal part that adds a viscous force
// acting at the rate of the LAB experiment a DEM run stands for, not at the rate of the DEM run.
//
// Why not a dashpot. A DEM of an oedometer test runs its ramps hundreds of times faster than the lab
// (the driver keeps the lab clock: viscTimeScale = lab seconds per DEM second). A contact viscosity
// with viscous time tau_v (lab seconds), f_v = k tau_v d(delta)/dt_lab, is then a dashpot
// gamma = k tau_v / viscTimeScale of 10-2000 kg/s, far beyond the explicit integrator's stability
// limit (about 2 m*/dt). So the viscous force is carried by a Maxwell branch (a spring k_m in series
// with the dashpot eta = k tau_v) in parallel with the base law, integrated exactly over each step:
//
//     dg/dt_lab = k_m d(delta)/dt_lab - g / tau_m,     tau_m = eta / k_m = tau_v / M,  k_m = M k,
//     g(t + dt) = g e^(-x) + eta (d(delta)/dt_lab) (1 - e^(-x)),   x = dt viscTimeScale / tau_m
//
// (exact for a constant overlap rate over the step). At a steady lab rate g tends to eta d(delta)/dt_lab,
// the viscous force of the dashpot, within a lag of tau_m lab seconds; at a stop it decays with tau_m.
// The branch is never stiffer than k_m = M k, so the contact is at most (1 + M) times as stiff as the
// base law: stiffness() reports that, and the time step chosen from it stays stable. M
// (viscStiffnessRatio, default 4) trades the lag tau_v / M against the smaller time step.
//
// k is the base law's stiffness() (the linear k; Luding's maximal unloading stiffness k2; Hertz's
// stiffness scale). While no lab time passes (viscTimeScale = 0, e.g. filling a mould) the branch
// holds its force and gains none. The total normal force may become attractive while the overlap
// decreases at a lab rate (as a dashpot's); the Coulomb limits use max(0, base load + g).
//
// History layout: Base::H doubles of the base law, then
//   [0] g        force of the Maxwell branch (N)
//   [1] W_visc   energy dissipated by the branch so far (J)
// Documentation/contact-laws.md ("Contact viscosity on the lab clock") has the equations.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>

#include "Contacts/NormalLaws.h"

namespace pdpm {

/// Normal part `Base` with a Maxwell branch of viscous time viscTime (lab s, 0 = off) and stiffness
/// ratio viscStiffnessRatio (M > 0), on the lab clock viscTimeScale (lab seconds per DEM second).
template <class Base>
struct LabViscous {
    static constexpr int HB = Base::H;
    static constexpr int H = Base::H + 2;
    static constexpr bool kNeedsMass = Base::kNeedsMass, kNeedsRadius = Base::kNeedsRadius;

    static void validate(const ContactParameters& p, const std::string& who) {
        Base::validate(p, who);
        detail::requireNonNegative(p.viscTime, "contact viscous time (viscTime)", who);
        detail::requirePositive(p.viscStiffnessRatio, "viscous branch stiffness ratio (viscStiffnessRatio)", who);
        detail::requireNonNegative(p.viscTimeScale, "viscous branch's lab time scale (viscTimeScale)", who);
    }
    static double stiffness(const ContactParameters& p, double rEff) {
        return Base::stiffness(p, rEff) * (p.viscTime > 0 ? 1 + p.viscStiffnessRatio : 1.0);
    }
    static double damping(const ContactParameters& p) { return Base::damping(p); }

    /// New branch force after a step of lab duration dtau (> 0) over which the overlap changes by
    /// dDelta at a constant rate: the exact solution of dg/dtau = k_m dDelta/dtau - g/tau_m.
    static double branchForce(double g, double km, double taum, double dDelta, double dtau) {
        const double x = dtau / taum;
        const double gain = x > 1e-12 ? -std::expm1(-x) / x : 1 - 0.5 * x;  // (1 - e^-x)/x
        return g * std::exp(-x) + km * dDelta * gain;
    }

    static void apply(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        Base::apply(p, s, h, o);
        if (!(p.viscTime > 0)) return;
        double* v = h + HB;
        const double km = p.viscStiffnessRatio * Base::stiffness(p, s.rEff);
        const double dtau = s.dt * p.viscTimeScale;
        if (dtau > 0) {
            const double dDelta = s.overlapRate * s.dt;
            const double g = v[0];
            const double gNew = branchForce(g, km, p.viscTime / p.viscStiffnessRatio, dDelta, dtau);
            // work done on the branch minus the change of the energy its spring stores
            v[1] += 0.5 * (g + gNew) * dDelta - (gNew * gNew - g * g) / (2 * km);
            v[0] = gNew;
        }
        o.fn += v[0];
        o.fnFriction = std::max(0.0, o.fnFriction + v[0]);
        o.energy += v[0] * v[0] / (2 * km);
    }
};

} // namespace pdpm
