#include "Contacts/ContactParameters.h"

#include <cmath>
#include <numbers>

#include <istream>
#include <ostream>

#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

double effectiveYoungModulus(double e1, double nu1, double e2, double nu2) {
    return 1.0 / ((1 - nu1 * nu1) / e1 + (1 - nu2 * nu2) / e2);
}
double effectiveShearModulus(double e1, double nu1, double e2, double nu2) {
    return 1.0 / (2 * (2 - nu1) * (1 + nu1) / e1 + 2 * (2 - nu2) * (1 + nu2) / e2);
}

namespace {
/// The fields in file order; `version` is the restart format (the viscous fields since version 5).
template <class P, class F>
void forEachField(P& p, F&& f, int version = 5) {
    f(p.k); f(p.gamma); f(p.k1); f(p.kc); f(p.phiF); f(p.youngEff); f(p.shearEff); f(p.restitution);
    f(p.kt); f(p.gammaT); f(p.muS); f(p.muD); f(p.kr); f(p.gammaR); f(p.muR); f(p.ko); f(p.gammaO); f(p.muO);
    f(p.relaxC); f(p.relaxT0); f(p.relaxTimeScale); f(p.relaxMemory);
    if (version >= 5) { f(p.viscTime); f(p.viscStiffnessRatio); f(p.viscTimeScale); }
}
} // namespace

void writeContactParameters(std::ostream& os, const ContactParameters& p) {
    os << (p.defined ? 1 : 0);
    forEachField(p, [&](double v) { os << ' ' << fmt(v); });
}

ContactParameters readContactParameters(std::istream& is, int restartVersion) {
    ContactParameters p;
    int d = 0;
    is >> d;
    p.defined = d != 0;
    bool nan = false;
    forEachField(p, [&](double& v) {
        v = readDouble(is);
        nan = nan || std::isnan(v);
    }, restartVersion);
    if (!is || nan) inputError("restart: malformed contact parameters");
    return p;
}

double reducedMass(double mi, double mj) {
    if (mj <= 0) return mi;
    if (mi <= 0) return mj;
    return mi * mj / (mi + mj);
}

double collisionTime(double k, double gamma, double m) {
    const double w2 = k / m - (gamma / (2 * m)) * (gamma / (2 * m));
    if (!(w2 > 0)) inputError("contact is over-damped (gamma^2 >= 4 k m): no collision time");
    return std::numbers::pi / std::sqrt(w2);
}

double restitutionCoefficient(double k, double gamma, double m) {
    return std::exp(-gamma * collisionTime(k, gamma, m) / (2 * m));
}

StiffnessDamping stiffnessAndDamping(double tc, double e, double m) {
    if (!(tc > 0)) inputError("collision time must be > 0");
    if (!(e > 0 && e <= 1)) inputError("restitution coefficient must be in (0, 1]");
    const double lne = std::log(e);
    const double gamma = -2 * m * lne / tc;
    const double k = m * (std::numbers::pi * std::numbers::pi + lne * lne) / (tc * tc);
    return {k, gamma};
}

} // namespace pdpm
