// Material presets of the OedometerRelaxation driver: cocoa meso-particles with the chapter 5
// parameters (thesis Table 5.3) and a non-cohesive frictional material.
#pragma once
#include <cmath>
#include <string>

#include "Contacts/ContactParameters.h"
#include "Core/Error.h"

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

} // namespace pdpm
