// Material presets of the OedometerRelaxation driver: cocoa meso-particles with the chapter 5
// parameters (thesis Table 5.3) and a non-cohesive frictional material; and the driver's flags that
// change a preset's contacts (OedometerKnobs: plasticity, adhesion, Hertz, stiffness scale, viscosity)
// with the contact law they need.
#pragma once
#include <cmath>
#include <numbers>
#include <string>

#include "Contacts/ContactParameters.h"
#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

/// Material parameters of one preset (chapter 5, Table 5.3, for "cocoa").
struct OedometerMaterial {
    std::string name;
    double density = 1427, dMean = 2.5e-3, sizeRatio = 3;
    ContactParameters pp, pw;  ///< particle-particle and particle-wall
};

inline OedometerMaterial oedometerMaterial(const std::string& name, double muWall) {
    OedometerMaterial m;
    m.name = name;
    ContactParameters c;
    c.k = 24067;  // Table 5.3: maximal elastic stiffness k (kg/s^2)
    c.gamma = 0.0827;
    c.kt = 0.286 * c.k;
    c.gammaT = 0.286 * c.gamma;
    c.kr = 0.286 * c.k;
    c.gammaR = 0.286 * c.gamma;
    c.muS = c.muD = 0.5;
    if (name == "cocoa") {
        c.k1 = c.k / 5;  // k/k1 = 5 (see data/thesis table_5_2_5_3 note)
        c.kc = 0.873 * c.k;
        c.phiF = 0.05;
        c.muR = 0.5;
    } else if (name == "frictional") {  // non-cohesive, elastic: Luding with k1 = k, kc = 0
        c.k1 = c.k;
        c.kc = 0;
        c.phiF = 0;
        c.muR = 0.1;
    } else {
        inputError("--material: unknown material '" + name + "' (cocoa, frictional)");
    }
    m.pp = c;
    m.pw = c;
    m.pw.muS = m.pw.muD = muWall;
    m.pw.muR = 0;
    m.pw.kc = 0;  // walls are not sticky
    return m;
}

/// Multiplies the normal stiffnesses of c (k, k1, kc) by `scale` and the normal dashpot by
/// sqrt(scale): the same restitution and stiffness ratios; the tangential, rolling and torsion parts
/// are left as they are.
inline void scaleNormalStiffness(ContactParameters& c, double scale) {
    for (double* k : {&c.k, &c.k1, &c.kc}) *k *= scale;
    c.gamma *= std::sqrt(scale);
}

/// The OedometerRelaxation flags that change a material preset's contacts (the driver registers them,
/// Documentation/driver-oedometer-relaxation.md has their meaning).
struct OedometerKnobs {
    std::string material;
    double muWall = 0, fillMuWall = -1, kOverK1 = 0, kcOverK = -1, wallKcOverK = 0, hertzModulus = 0, normalScale = 1,
           viscTime = 0, viscRatio = 4, dMean = 0;
    std::string contactLaw;        ///< --contact_law
    bool contactLawGiven = false;  ///< whether --contact_law was on the command line

    /// --contact_law, or with --hertz_modulus the same law parts around a Hertzian normal force, or
    /// with --contact_viscous_time luding-relax with the viscous branch.
    std::string lawName() const {
        if (hertzModulus > 0) return "hertz-rolling-relax";
        return viscTime > 0 && contactLaw == "luding-relax" ? "luding-relax-viscous" : contactLaw;
    }
    /// The bed is poured with the material's own contacts whatever the knobs that compare contact
    /// laws on it (--hertz_modulus, --normal_stiffness_scale, --contact_viscous_time), so that a run
    /// with one of them and its twin without compress the same bed: the law is luding-relax for a
    /// Hertzian or viscous run (luding-relax-viscous with the branch off gives the same forces, but
    /// compiled apart it may differ in the last bit, FMA contraction, and the chaotic pour amplified
    /// that into another bed: 193 against 196 particles at seed 1313, until 2026-12-07), and the
    /// material is pourMaterial(). Hertzian and stiffness-scaled runs poured their own beds until
    /// 2026-12-07 (session 42).
    std::string pourLawName() const {
        if (hertzModulus > 0) return "luding-relax";
        return lawName() == "luding-relax-viscous" ? "luding-relax" : lawName();
    }
    /// The material the bed is poured with: apply() without the Hertz modulus and the stiffness scale.
    OedometerMaterial pourMaterial() const {
        OedometerKnobs plain = *this;
        plain.hertzModulus = 0;
        plain.normalScale = 1;
        return plain.apply();
    }
    /// --hertz_modulus and --contact_viscous_time need their law in use (not another one given by
    /// --contact_law or a restart file).
    void checkLaw(const std::string& law) const {
        if (hertzModulus > 0 && law != "hertz-rolling-relax")
            inputError("--hertz_modulus: the contact law in use is '" + law +
                       "' (from --contact_law or the restart file); Hertz contacts need hertz-rolling-relax");
        if (viscTime > 0 && (law.size() < 8 || law.compare(law.size() - 8, 8, "-viscous") != 0))
            inputError("--contact_viscous_time: the contact law in use is '" + law +
                       "' (from --contact_law, --hertz_modulus or the restart file); the viscosity needs a '-viscous' law (luding-relax-viscous)");
    }
    /// The preset with the knobs applied; InputError where they contradict each other or the material.
    OedometerMaterial apply() const {
        OedometerMaterial m = oedometerMaterial(material, muWall);
        for (ContactParameters* c : {&m.pp, &m.pw}) scaleNormalStiffness(*c, normalScale);
        if (kOverK1 > 0) {
            if (kOverK1 < 1) inputError("--k_over_k1: expected 0 (the material's value) or at least 1 (k1 <= k), got " + fmt(kOverK1));
            m.pp.k1 = m.pw.k1 = m.pp.k / kOverK1;
        }
        if (kcOverK >= 0) m.pp.kc = kcOverK * m.pp.k;
        else if (kcOverK != -1) inputError("--kc_over_k: expected -1 (the material's value) or a value >= 0, got " + fmt(kcOverK));
        m.pw.kc = wallKcOverK * m.pw.k;  // particle-wall adhesion only when asked for
        if (fillMuWall < 0 && fillMuWall != -1)
            inputError("--fill_wall_friction: expected -1 (the same as --wall_friction) or a value >= 0, got " + fmt(fillMuWall));
        if (hertzModulus > 0) {
            // Hertzian normal force: elastic and non-adhesive, so the material (or the plasticity and
            // adhesion knobs) must be; the dashpot becomes the restitution of the linear law for two
            // mean particles
            if (contactLawGiven && contactLaw != "hertz-rolling-relax")
                inputError("--hertz_modulus: it sets the contact law hertz-rolling-relax; leave out --contact_law " + contactLaw);
            if (normalScale != 1)
                inputError("--normal_stiffness_scale: it scales the linear normal force, which --hertz_modulus replaces (set E* instead)");
            if (m.pp.k1 != m.pp.k || m.pp.kc != 0 || m.pw.kc != 0)
                inputError("--hertz_modulus: Hertz contacts are elastic and non-adhesive, the " + material +
                           " material is not: give --k_over_k1 1 --kc_over_k 0 (and --wall_kc_over_k 0) with it");
            const double mass = m.density * std::numbers::pi * dMean * dMean * dMean / 6;
            const double e = restitutionCoefficient(m.pp.k, m.pp.gamma, 0.5 * mass);
            for (ContactParameters* c : {&m.pp, &m.pw}) {
                c->youngEff = hertzModulus;
                c->restitution = e;
            }
        }
        m.dMean = dMean;
        return m;
    }
};

} // namespace pdpm
