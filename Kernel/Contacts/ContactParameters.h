// Parameters of the interaction between two species (or a species and a wall).
// One flat struct holds the parameters of every law part; a law reads only the parts it is made of
// and validates only those (ContactLaw::validate). Documentation/contact-laws.md lists them.
#pragma once
#include <iosfwd>
#include <string>

namespace pdpm {

struct ContactParameters {
    bool defined = false;  ///< set by SpeciesTable when the user gave this pair explicitly

    // ---- normal: linear visco-elastic (Eq. 2.1) and Luding's hysteretic model (Eq. 5.5-5.7)
    double k = 0;       ///< linear stiffness k (N/m); for Luding: the maximal unloading stiffness k2-hat
    double gamma = 0;   ///< normal dashpot gamma (kg/s)
    double k1 = 0;      ///< Luding: plastic loading stiffness k1 <= k (N/m)
    double kc = 0;      ///< Luding: adhesive stiffness k_c (N/m)
    double phiF = 0;    ///< Luding: dimensionless plasticity depth phi_f in [0,1]

    // ---- normal: Hertz with Tsuji-type damping (from a restitution coefficient)
    double youngEff = 0;     ///< effective Young's modulus E* (Pa)
    double shearEff = 0;     ///< effective shear modulus G* (Pa), Mindlin tangential stiffness
    double restitution = 1;  ///< e in (0,1] for the Hertz family

    // ---- tangential: linear spring-dashpot with Coulomb limit (or Mindlin for Hertz)
    double kt = 0;       ///< tangential stiffness (N/m)
    double gammaT = 0;   ///< tangential dashpot (kg/s)
    double muS = 0;      ///< static friction coefficient
    double muD = 0;      ///< dynamic (sliding) friction coefficient, <= muS

    // ---- rolling resistance (spring, dashpot, Coulomb-type limit)
    double kr = 0, gammaR = 0, muR = 0;
    // ---- torsion resistance
    double ko = 0, gammaO = 0, muO = 0;

    // ---- time-dependent relaxation (issue: OedometerRelaxation); C = 0 switches it off
    double relaxC = 0;
    double relaxT0 = 1;
    /// Lab seconds per DEM second: the relaxation clock advances by dt * relaxTimeScale (see
    /// Contacts/RelaxationLaws.h). Only the slow relaxation physics reads it.
    double relaxTimeScale = 1;
    /// Memory of the relaxation clock across load increases (>= 0). 0: the clock restarts at every
    /// load increase; m > 0: it is shortened by the factor (f_ref/f_new)^(1/m) instead, so a contact
    /// reloaded by a small fraction keeps most of its age (Contacts/RelaxationLaws.h).
    double relaxMemory = 0;

    // ---- contact viscosity on the lab clock (Contacts/ViscousLaws.h); viscTime = 0 switches it off
    double viscTime = 0;            ///< viscous time tau_v of the Maxwell branch (lab seconds), eta = k tau_v
    double viscStiffnessRatio = 4;  ///< M = k_m / k of the branch's spring (> 0); its lag is tau_v / M
    /// Lab seconds per DEM second of the viscous branch's clock (like relaxTimeScale, but a driver may
    /// stop the relaxation clocks in ramps while lab time, and so the lab rate, still runs there).
    double viscTimeScale = 1;
};

/// All numeric fields in a fixed order (restart files); `defined` first.
void writeContactParameters(std::ostream& os, const ContactParameters& p);
/// Reads what writeContactParameters wrote; `restartVersion` 4 files lack the viscous fields (defaults).
ContactParameters readContactParameters(std::istream& is, int restartVersion);

/// Effective modulus of two Hertzian materials: 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2.
double effectiveYoungModulus(double e1, double nu1, double e2, double nu2);
/// Effective shear modulus (Mindlin): 1/G* = 2(2-nu1)(1+nu1)/E1 + 2(2-nu2)(1+nu2)/E2.
double effectiveShearModulus(double e1, double nu1, double e2, double nu2);

// ---- conversions for the linear visco-elastic law (thesis Sec. 2.2.2) -------------------------
// t_c = pi / sqrt(k/m - (gamma/2m)^2),  e = exp(-gamma t_c / (2 m)),  m = reduced mass.

/// Collision time of the linear law for reduced mass m; InputError if over-damped.
double collisionTime(double k, double gamma, double reducedMass);
/// Restitution coefficient of the linear law for reduced mass m.
double restitutionCoefficient(double k, double gamma, double reducedMass);
struct StiffnessDamping { double k, gamma; };
/// Inverse: stiffness and dashpot that give collision time tc and restitution e for reduced mass m.
StiffnessDamping stiffnessAndDamping(double tc, double e, double reducedMass);
/// Reduced mass m_i m_j / (m_i + m_j); a wall (mass 0 meaning infinite) gives m_i.
double reducedMass(double mi, double mj);

} // namespace pdpm
