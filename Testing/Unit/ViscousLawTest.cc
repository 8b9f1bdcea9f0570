// Contact viscosity on the lab clock (Contacts/ViscousLaws.h) as a pure function of one contact:
//  - a ramp of the overlap at a constant lab rate builds the Maxwell force g(t) = eta r (1 - e^(-t/tau_m))
//    (eta = k tau_v, tau_m = tau_v / M), exactly for any step size; it tends to the dashpot's eta r;
//  - at a stop the force decays as e^(-t/tau_m); while no lab time passes it neither grows nor decays;
//  - viscTime = 0 is the base law bit for bit; stiffness() is (1 + M) k when the branch is on;
//  - energy: work put in = base law's stored energy + branch's stored energy + branch dissipation;
//  - the Maxwell branch keeps an explicit integration stable where the dashpot of the same viscosity
//    does not (two masses on a contact, lab clock 1000 lab s per DEM s);
//  - parameters are validated; the law's history round-trips (continuing from a copy is bitwise equal).
// Expected values are computed here from the equations, not from kernel helpers.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "Contacts/ContactLaw.h"
#include "Core/Error.h"
#include "SingleContact.h"

using namespace pdpm;

namespace {

ContactParameters linearViscous(double tauV, double M, double scale) {
    ContactParameters p = test::linearRelaxParams(0, 1, scale);  // relaxation off: the base is the linear spring
    p.viscTime = tauV;
    p.viscStiffnessRatio = M;
    p.viscTimeScale = scale;
    return p;
}

// History of linear-relax-viscous: the normal part first, Relaxing<NormalLinear>'s four doubles, then
// the branch force g and its dissipation W_visc; the tangential spring after them.
constexpr std::size_t kG = 4, kW = 5;

/// A SingleContact owning its law, made by name (the owner is a base, so it is built first).
struct LawOwner {
    std::unique_ptr<ContactLaw> owned;
};
struct Contact : LawOwner, test::SingleContact {
    Contact(const std::string& name, const ContactParameters& pp) : LawOwner{makeContactLaw(name)}, test::SingleContact(*owned, pp) {}
};

} // namespace

TEST(ContactViscosity, RegisteredByName) {
    for (const char* n : {"linear-relax-viscous", "luding-relax-viscous"}) EXPECT_EQ(makeContactLaw(n)->name(), n);
    EXPECT_EQ(makeContactLaw("linear-relax-viscous")->historySize(), makeContactLaw("linear-relax")->historySize() + 2);
    EXPECT_EQ(makeContactLaw("luding-relax-viscous")->historySize(), makeContactLaw("luding-relax")->historySize() + 2);
}

TEST(ContactViscosity, ValidateRefusesBadParameters) {
    const auto law = makeContactLaw("linear-relax-viscous");
    EXPECT_NO_THROW(law->validate(linearViscous(2, 4, 1e3), "pair"));
    EXPECT_NO_THROW(law->validate(linearViscous(0, 4, 1e3), "pair"));
    EXPECT_THROW(law->validate(linearViscous(-1, 4, 1e3), "pair"), InputError);
    EXPECT_THROW(law->validate(linearViscous(2, 0, 1e3), "pair"), InputError);
    EXPECT_THROW(law->validate(linearViscous(2, -1, 1e3), "pair"), InputError);
    ContactParameters bad = linearViscous(2, 4, 1e3);
    bad.viscTimeScale = -1;
    EXPECT_THROW(law->validate(bad, "pair"), InputError);
}

TEST(ContactViscosity, StiffnessIncludesTheBranch) {
    const auto law = makeContactLaw("linear-relax-viscous");
    EXPECT_DOUBLE_EQ(law->stiffness(linearViscous(2, 4, 1), 1e-3), 5e4);
    EXPECT_DOUBLE_EQ(law->stiffness(linearViscous(0, 4, 1), 1e-3), 1e4);
}

TEST(ContactViscosity, OffIsTheBaseLawBitForBit) {
    Contact a("linear-relax-viscous", linearViscous(0, 4, 1e3));
    Contact b("linear-relax", linearViscous(0, 4, 1e3));
    for (int k = 1; k <= 200; ++k) {
        const double d = 1e-5 * std::sin(0.05 * k) + 2e-5, r = 1e-5 * 0.05 * std::cos(0.05 * k) / 1e-6;
        const ContactOutput oa = a.step(d, 1e-6, r), ob = b.step(d, 1e-6, r);
        ASSERT_EQ(oa.fn, ob.fn);
        ASSERT_EQ(oa.fnFriction, ob.fnFriction);
        ASSERT_EQ(oa.energy, ob.energy);
    }
}

// A ramp at the constant lab rate r: the branch force is eta r (1 - e^(-t/tau_m)) at every step,
// whatever the step's lab duration (the update is exact for a constant rate), and the total force is
// k delta + that.
TEST(ContactViscosity, RampBuildsTheDashpotForceWithTheBranchLag) {
    const double tauV = 2, M = 4, k = 1e4, scale = 1e3;  // lab s, -, N/m, lab s per DEM s
    const double eta = k * tauV, tauM = tauV / M;
    const double rLab = 1e-7;  // overlap rate, m per lab second
    for (double dt : {1e-6, 1e-5, 1e-3}) {  // lab step 1e-3 .. 1 s against tau_m = 0.5 s
        Contact c("linear-relax-viscous", linearViscous(tauV, M, scale));
        const double rDem = rLab * scale;
        double worst = 0;
        const int n = int(std::lround(5.0 / (dt * scale)));  // 5 lab seconds = 10 tau_m
        for (int i = 1; i <= n; ++i) {
            const double t = i * dt * scale;
            const double delta = 1e-6 + rLab * t;
            const double f = c.step(delta, dt, rDem).fn;
            const double expected = k * delta + eta * rLab * -std::expm1(-t / tauM);
            worst = std::max(worst, std::abs(f - expected) / (eta * rLab));
        }
        EXPECT_LT(worst, 1e-9) << "dt " << dt;
        EXPECT_NEAR(c.h[kG], eta * rLab, 1e-4 * eta * rLab);  // after 10 tau_m
    }
}

// After a ramp, a held overlap: the branch force decays as e^(-t/tau_m); with no lab time (scale 0)
// it is frozen.
TEST(ContactViscosity, StopDecaysWithTheBranchTimeAndFreezesWithoutLabTime) {
    const double tauV = 2, M = 4, k = 1e4, scale = 1e3, dt = 1e-5, rLab = 1e-7;
    Contact c("linear-relax-viscous", linearViscous(tauV, M, scale));
    double delta = 1e-6;
    for (int i = 1; i <= 500; ++i) delta = 1e-6 + rLab * i * dt * scale, c.step(delta, dt, rLab * scale);
    const double g0 = c.h[kG];
    ASSERT_GT(g0, 0);
    c.p.viscTimeScale = 0;
    for (int i = 0; i < 100; ++i) EXPECT_EQ(c.step(delta, dt, 0).fn, k * delta + g0);
    c.p.viscTimeScale = scale;
    double worst = 0;
    for (int i = 1; i <= 200; ++i) {
        const double f = c.step(delta, dt, 0).fn;
        const double expected = k * delta + g0 * std::exp(-i * dt * scale * M / tauV);
        worst = std::max(worst, std::abs(f - expected) / g0);
    }
    EXPECT_LT(worst, 1e-12);
}

// Energy: the work put in along an overlap path (trapezoid in the step's constant rate, which is
// what the exact update assumes) equals the base spring's energy + the branch spring's energy + the
// branch's dissipation.
TEST(ContactViscosity, EnergyBookkeeping) {
    const double tauV = 1, M = 4, k = 1e4, scale = 1e3, dt = 1e-5;
    Contact c("linear-relax-viscous", linearViscous(tauV, M, scale));
    double delta = 0, work = 0, gPrev = 0;
    ContactOutput o;
    for (int i = 1; i <= 3000; ++i) {
        const double rate = 2e-7 * std::sin(0.004 * i) * scale;  // loads and partly unloads
        const double dDelta = rate * dt;
        delta += dDelta;
        o = c.step(1e-6 + delta, dt, rate);
        const double g = c.h[kG];
        work += (k * (1e-6 + delta - 0.5 * dDelta)) * dDelta + 0.5 * (gPrev + g) * dDelta;
        gPrev = g;
    }
    const double W = c.h[kW];
    const double stored = o.energy;  // base spring + branch spring
    EXPECT_GT(W, 0);
    EXPECT_NEAR(work + 0.5 * k * 1e-6 * 1e-6, stored + W, 1e-9 * stored);
}

// Two masses m on one contact under an explicit (velocity-Verlet-like) integration at dt = t_c / 25
// of the base spring: the branch (M = 4) keeps the motion bounded; a dashpot of the same viscosity,
// gamma = k tau_v / scale, is far beyond 2 m*/dt and diverges.
TEST(ContactViscosity, MaxwellBranchStaysStableWhereTheDashpotDiverges) {
    const double m = 1e-3, k = 1e4, tauV = 20, scale = 1e3;
    const double mEff = 0.5 * m;
    const double tc = std::numbers::pi * std::sqrt(mEff / k);
    auto run = [&](bool maxwell) {
        ContactParameters p = linearViscous(maxwell ? tauV : 0, 4, scale);
        if (!maxwell) p.gamma = k * tauV / scale;  // the lab-time dashpot in DEM units
        Contact c("linear-relax-viscous", p);
        const double dt = std::numbers::pi * std::sqrt(mEff / c.law.stiffness(p, 1e-3)) / 25;  // from the law's stiffness
        double x = 1e-6, v = -1e-4;  // overlap and its rate
        double peak = 0;
        for (int i = 0; i < 20000; ++i) {
            ContactState s = test::headOnState(x, dt, v);
            s.mEff = mEff;
            ContactOutput o;
            c.law.evaluate(c.p, s, c.h.data(), o);
            v += -o.fn / mEff * dt;  // the overlap's acceleration: the force pushes the masses apart
            x += v * dt;
            if (!std::isfinite(x)) return 1e300;
            peak = std::max(peak, std::abs(x));
        }
        return peak;
    };
    EXPECT_LT(run(true), 1e-5);
    EXPECT_GT(k * tauV / scale * (tc / 25) / (2 * mEff), 1);  // the dashpot is beyond its limit
    EXPECT_GT(run(false), 1e-3);
}

TEST(ContactViscosity, HistoryRoundTrip) {
    Contact a("luding-relax-viscous", linearViscous(2, 4, 1e3));
    a.p.k = 24067;
    a.p.k1 = a.p.k / 5;
    a.p.kc = 0.5 * a.p.k;
    a.p.phiF = 0.05;
    a.p.relaxC = 0.08;
    a.p.relaxT0 = 0.3;
    for (int i = 1; i <= 300; ++i) a.step(1e-6 * (1 + std::sin(0.02 * i)), 1e-5, 1e-6 * 0.02 * std::cos(0.02 * i) / 1e-5);
    Contact b("luding-relax-viscous", a.p);
    b.h = a.h;
    for (int i = 301; i <= 600; ++i) {
        const double d = 1e-6 * (1 + std::sin(0.02 * i)), r = 1e-6 * 0.02 * std::cos(0.02 * i) / 1e-5;
        ASSERT_EQ(a.step(d, 1e-5, r).fn, b.step(d, 1e-5, r).fn);
    }
}
