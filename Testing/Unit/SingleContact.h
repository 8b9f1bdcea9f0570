// One contact of a law driven along a prescribed overlap path, for the unit tests of contact laws
// as pure functions (RelaxationTest, ViscousLawTest): head-on along z, reduced mass and radius 1e-3.
#pragma once
#include <vector>

#include "Contacts/ContactLaw.h"

namespace pdpm::test {

/// p with the relaxing law's contact C and t0, its clock running `scale` lab seconds per simulated second.
inline ContactParameters withRelaxation(ContactParameters p, double C, double t0, double scale) {
    p.relaxC = C;
    p.relaxT0 = t0;
    p.relaxTimeScale = scale;
    return p;
}

/// Linear contact parameters (k = 1e4, no dashpot, no tangential spring, mu 0.5) of the relaxing law.
inline ContactParameters linearRelaxParams(double C, double t0, double scale) {
    ContactParameters p;
    p.k = 1e4;
    p.gamma = 0;
    p.kt = 0;
    p.muS = p.muD = 0.5;
    return withRelaxation(p, C, t0, scale);
}

inline ContactState headOnState(double overlap, double dt, double rate = 0) {
    ContactState s;
    s.n = {0, 0, 1};
    s.overlap = overlap;
    s.overlapRate = rate;
    s.mEff = 1e-3;
    s.rEff = 1e-3;
    s.dt = dt;
    return s;
}

/// A law's parameters and one contact's history; step() evaluates the law at the next overlap.
struct SingleContact {
    const ContactLaw& law;
    ContactParameters p;
    std::vector<double> h;
    SingleContact(const ContactLaw& l, const ContactParameters& pp) : law(l), p(pp), h(static_cast<std::size_t>(l.historySize()), 0.0) {}
    ContactOutput step(double overlap, double dt, double rate = 0) {
        ContactOutput o;
        law.evaluate(p, headOnState(overlap, dt, rate), h.data(), o);
        return o;
    }
};

} // namespace pdpm::test
